#include "cobra/components/signal/threshold_detector.hpp"

namespace cobra::components {

ThresholdDetector::ThresholdDetector(std::string name)
    : Component(std::move(name), core::Role::Decision, "Raises events when a signal crosses a threshold") {
  addEventPort(in_);
  addProperty(threshold_);
  addProperty(hysteresis_.range(0.0, 1e12));
}

bool ThresholdDetector::startHook() {
  above_ = false;
  return true;
}

void ThresholdDetector::updateHook() {
  double value = 0.0;
  while (in_.read(value) == core::FlowStatus::NewData) {
    if (!above_ && value > threshold_()) {
      above_ = true;
      emitEvent("e_above_threshold");
    } else if (above_ && value < threshold_() - hysteresis_()) {
      above_ = false;
      emitEvent("e_below_threshold");
    }
  }
}

}  // namespace cobra::components
