#include "cobra/components/drivers/leap_motion_driver.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "cobra/core/activity.hpp"
#include "cobra/core/backend_registry.hpp"

namespace cobra::components {

LeapMotionDriver::LeapMotionDriver(std::string name)
    : Component(std::move(name), core::Role::Bridge,
                "Leap Motion hand tracker (thesis §5.4.4): right and left hand poses in the interaction box") {
  for (core::PropertyBase* p :
       std::initializer_list<core::PropertyBase*>{&box_, &offset_, &scale_, &device_name_})
    addProperty(*p);
  addPort(meas_right_);
  addPort(meas_left_);
}

bool LeapMotionDriver::configureHook() {
  if (activity().period().count() <= 0) return refuse("needs a periodic activity: each update polls the tracker");
  const std::vector<double>& b = box_();
  if (b.size() != 6)
    return refuse("property interaction_box has " + std::to_string(b.size()) +
                  " numbers; give 6: x_min, y_min, z_min, x_max, y_max, z_max in m");
  static const char* const kAxis[3] = {"x", "y", "z"};
  for (std::size_t i = 0; i < 3; ++i) {
    if (!std::isfinite(b[i]) || !std::isfinite(b[i + 3]) || b[i] >= b[i + 3])
      return refuse("property interaction_box: " + std::string(kAxis[i]) + "_min = " + std::to_string(b[i]) +
                    " m must be below " + kAxis[i] + "_max = " + std::to_string(b[i + 3]) + " m");
  }
  if (!std::isfinite(scale_()) || scale_() <= 0.0)
    return refuse("property workspace_scale = " + std::to_string(scale_()) + "; expected > 0");
  box_min_ = KDL::Vector(b[0], b[1], b[2]);
  box_max_ = KDL::Vector(b[3], b[4], b[5]);
  try {
    device_ = core::BackendRegistry<fieldbus::HandTrackerDevice>::open(device_name_());
  } catch (const std::exception& e) {
    return refuse("property device = '" + device_name_() + "': " + e.what());
  }
  right_seen_ = left_seen_ = false;
  return true;
}

KDL::Frame LeapMotionDriver::map(const KDL::Frame& measured) const noexcept {
  KDL::Vector p;
  for (int i = 0; i < 3; ++i) p(i) = std::clamp(measured.p(i), box_min_(i), box_max_(i));
  return offset_() * KDL::Frame(measured.M, p * scale_());
}

void LeapMotionDriver::publish(const fieldbus::TrackedHand& tracked, bool& seen, core::OutputPort<KDL::Frame>& port,
                               const char* lost, const char* found) noexcept {
  if (tracked.valid) {
    port.write(map(tracked.pose));
    if (!seen) emitEvent(found);
  } else if (seen) {
    emitEvent(lost);
  }
  seen = tracked.valid;
}

void LeapMotionDriver::cleanupHook() { device_.reset(); }

void LeapMotionDriver::updateHook() {
  if (!device_->takeFrame(frame_)) return;
  publish(frame_.right, right_seen_, meas_right_, "e_right_hand_lost", "e_right_hand_found");
  publish(frame_.left, left_seen_, meas_left_, "e_left_hand_lost", "e_left_hand_found");
}

}  // namespace cobra::components
