#pragma once
/// @file
/// Constant: a Calculation component that writes the value of a property at every update, e.g. a
/// set-point whose value a configuration chooses.

#include "cobra/core/component.hpp"

namespace cobra::components {

/// Writes `value` on `out` at every update (give it a periodic activity).
class Constant : public core::Component {
 public:
  explicit Constant(std::string name);

 protected:
  void updateHook() override;

 private:
  core::OutputPort<double> out_{"out", "the value, at every update", "1"};
  core::Property<double> value_{"value", 0.0, "1", "the value written (unit: that of what it feeds)"};
};

}  // namespace cobra::components
