#pragma once
// ForceLowPass: a first-order low-pass filter of a measured force, the kind of component a
// force-controlled task puts between its sensor driver and its admittance controller.

#include <chrono>

#include "cobra/core/component.hpp"
#include "force_sample.hpp"

namespace example {

/// A Calculation component: at every update, `force_out` moves towards the latest `force_in`
/// as a first-order system of cut-off frequency `cutoff_frequency` would, exactly for an input
/// held between updates: y += (1 - exp(-2π·fc·dt))·(u - y), dt being the time since the last
/// update on the component's clock. Starts from `initial_force`. `sample_out` gives each update
/// as the package's own type, example.ForceSample (force read, force written, update count).
class ForceLowPass : public cobra::core::Component {
 public:
  explicit ForceLowPass(std::string name);

 protected:
  bool configureHook() override;
  bool startHook() override;
  void updateHook() override;

 private:
  cobra::core::InputPort<double> force_in_{"force_in", "measured force", "N"};
  cobra::core::OutputPort<double> force_out_{"force_out", "filtered force", "N"};
  cobra::core::OutputPort<ForceSample> sample_out_{"sample_out", "each update: force read, force written, count", ""};
  cobra::core::Property<double> cutoff_frequency_{"cutoff_frequency", 5.0, "Hz", "cut-off frequency fc (> 0)"};
  cobra::core::Property<double> initial_force_{"initial_force", 0.0, "N", "filter output at start"};
  double input_ = 0.0;    // N, the latest force read
  double filtered_ = 0.0; // N
  int count_ = 0;         // updates since start
  std::chrono::nanoseconds last_update_{0};
};

}  // namespace example
