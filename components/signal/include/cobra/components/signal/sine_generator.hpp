#pragma once
/// @file
/// SineGenerator: a Calculation component producing y(t) = offset + amplitude·sin(2π·frequency·t + phase).

#include "cobra/core/component.hpp"

namespace cobra::components {

/// Writes one sample of the sine on `out` per update; t is the time since start on the
/// component's clock (simulated time on the lockstep clock), so the signal is deterministic.
class SineGenerator : public core::Component {
 public:
  explicit SineGenerator(std::string name);

 protected:
  bool startHook() override;
  void updateHook() override;

 private:
  core::OutputPort<double> out_{"out", "the sine sample", "1"};
  core::Property<double> amplitude_{"amplitude", 1.0, "1", "peak value of the sine"};
  core::Property<double> frequency_{"frequency", 1.0, "Hz", "frequency of the sine"};
  core::Property<double> phase_{"phase", 0.0, "rad", "phase at t = 0"};
  core::Property<double> offset_{"offset", 0.0, "1", "value added to the sine"};
  std::chrono::nanoseconds start_{0};
};

}  // namespace cobra::components
