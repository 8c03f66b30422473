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
       std::initializer_list<core::PropertyBase*>{&box_, &offset_, &scale_, &device_name_, &twist_filter_time_})
    addProperty(*p);
  addPort(meas_right_);
  addPort(meas_left_);
  addPort(twist_right_);
  addPort(twist_left_);
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
  if (!std::isfinite(twist_filter_time_()) || twist_filter_time_() < 0.0)
    return refuse("property twist_filter_time = " + std::to_string(twist_filter_time_()) + " s; expected >= 0");
  box_min_ = KDL::Vector(b[0], b[1], b[2]);
  box_max_ = KDL::Vector(b[3], b[4], b[5]);
  try {
    device_ = core::BackendRegistry<fieldbus::HandTrackerDevice>::open(device_name_());
  } catch (const std::exception& e) {
    return refuse("property device = '" + device_name_() + "': " + e.what());
  }
  right_ = left_ = HandState{};
  return true;
}

KDL::Frame LeapMotionDriver::map(const KDL::Frame& measured) const noexcept {
  KDL::Vector p;
  for (int i = 0; i < 3; ++i) p(i) = std::clamp(measured.p(i), box_min_(i), box_max_(i));
  return offset_() * KDL::Frame(measured.M, p * scale_());
}

void LeapMotionDriver::publish(const fieldbus::TrackedHand& tracked, HandState& hand,
                               core::OutputPort<KDL::Frame>& pose_port, core::OutputPort<KDL::Twist>& twist_port,
                               const char* lost, const char* found) noexcept {
  if (tracked.valid) {
    const KDL::Frame pose = map(tracked.pose);
    const std::chrono::nanoseconds at = now();
    const double dt = std::chrono::duration<double>(at - hand.at).count();  // s
    if (hand.seen && dt > 0.0) {
      // The finite difference in the published frame (KDL::diff: the rotation vector of the turn
      // in base axes), then the first-order filter stepped by the time between the two frames.
      const KDL::Twist raw = KDL::diff(hand.pose, pose, dt);
      const double gain = dt / (twist_filter_time_() + dt);
      hand.twist = hand.twist + (raw - hand.twist) * gain;
    } else {
      hand.twist = KDL::Twist::Zero();  // found again, or the first frame: no previous pose
    }
    hand.pose = pose;
    hand.at = at;
    pose_port.write(pose);
    twist_port.write(hand.twist);
    if (!hand.seen) emitEvent(found);
  } else if (hand.seen) {
    hand.twist = KDL::Twist::Zero();  // the last pose stays on its port: it does not move
    twist_port.write(hand.twist);
    emitEvent(lost);
  }
  hand.seen = tracked.valid;
}

void LeapMotionDriver::cleanupHook() { device_.reset(); }

void LeapMotionDriver::updateHook() {
  if (!device_->takeFrame(frame_)) return;
  publish(frame_.right, right_, meas_right_, twist_right_, "e_right_hand_lost", "e_right_hand_found");
  publish(frame_.left, left_, meas_left_, twist_left_, "e_left_hand_lost", "e_left_hand_found");
}

}  // namespace cobra::components
