#pragma once
// ForceSampleHold: holds the latest example.ForceSample it receives and passes it on; what a
// process at the other end of a DDS connection records.

#include "cobra/core/component.hpp"
#include "force_sample.hpp"

namespace example {

/// A Calculation component: at every update, a new sample on `sample_in` becomes the held one and
/// is written to `sample_out` (nothing is written while nothing arrives). `sample` is the held
/// sample at start (a property of the package's type: `Hold.sample = {force = 1, filtered = 2,
/// count = 3}` in a deployment file); `received` counts the samples received since start.
class ForceSampleHold : public cobra::core::Component {
 public:
  explicit ForceSampleHold(std::string name);

 protected:
  bool startHook() override;
  void updateHook() override;

 private:
  cobra::core::InputPort<ForceSample> sample_in_{"sample_in", "samples to hold", ""};
  cobra::core::OutputPort<ForceSample> sample_out_{"sample_out", "each sample received, as held", ""};
  cobra::core::Property<ForceSample> sample_{"sample", ForceSample{}, "", "the held sample at start"};
  cobra::core::Property<int> received_{"received", 0, "", "samples received since start (read-only)"};
  ForceSample held_;
};

}  // namespace example
