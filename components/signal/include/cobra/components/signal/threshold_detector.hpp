#pragma once
/// @file
/// ThresholdDetector: a Decision component: reads pure data, writes logic data (events).

#include "cobra/core/component.hpp"

namespace cobra::components {

/// Emits `e_above_threshold` when the signal on `in` rises above `threshold` and
/// `e_below_threshold` when it falls back below `threshold − hysteresis`, on its `events` port.
class ThresholdDetector : public core::Component {
 public:
  explicit ThresholdDetector(std::string name);

 protected:
  bool startHook() override;
  void updateHook() override;

 private:
  core::InputPort<double> in_{"in", "the monitored signal", "1"};
  core::Property<double> threshold_{"threshold", 1.0, "1", "level whose upward crossing raises e_above_threshold"};
  core::Property<double> hysteresis_{"hysteresis", 0.0, "1", "how far below the threshold the signal must fall to re-arm"};
  bool above_ = false;
};

}  // namespace cobra::components
