#pragma once
/// @file
/// Gain: a Calculation component, y = k·u, updated whenever a sample arrives.

#include "cobra/core/component.hpp"

namespace cobra::components {

/// Scales every sample read on `in` (an event port) by the property `k` and writes it on `out`.
class Gain : public core::Component {
 public:
  explicit Gain(std::string name);

 protected:
  void updateHook() override;

 private:
  core::InputPort<double> in_{"in", "signal u", "1"};
  core::OutputPort<double> out_{"out", "signal y = k·u", "1"};
  core::Property<double> k_{"k", 1.0, "1", "gain factor"};
};

}  // namespace cobra::components
