#include "cobra/components/drivers/leap_motion_driver.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include "cobra/core/activity.hpp"

namespace cobra::components {

LeapMotionDriver::LeapMotionDriver(std::string name)
    : Component(std::move(name), core::Role::Bridge,
                "Leap Motion hand tracker (thesis §5.4.4): right and left hand poses in the interaction box") {
  for (core::PropertyBase* p :
       std::initializer_list<core::PropertyBase*>{&box_, &offset_, &scale_, &sim_noise_, &sim_seed_})
    addProperty(*p);
  for (core::PortBase* p : std::initializer_list<core::PortBase*>{&sim_right_, &sim_left_, &meas_right_, &meas_left_})
    addPort(*p);
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
  sim::HandTrackerModel model;
  model.position_noise = sim_noise_();
  try {
    tracker_.emplace(model, static_cast<std::uint64_t>(sim_seed_()));
  } catch (const std::invalid_argument& e) {
    return refuse(e.what());
  }
  right_ = Hand{};
  left_ = Hand{};
  return true;
}

KDL::Frame LeapMotionDriver::map(const KDL::Frame& measured) const noexcept {
  KDL::Vector p;
  for (int i = 0; i < 3; ++i) p(i) = std::clamp(measured.p(i), box_min_(i), box_max_(i));
  return offset_() * KDL::Frame(measured.M, p * scale_());
}

void LeapMotionDriver::publish(const sim::TrackedHand& tracked, Hand& hand, core::OutputPort<KDL::Frame>& port,
                               const char* lost, const char* found) noexcept {
  if (tracked.valid) {
    port.write(map(tracked.pose));
    if (!hand.seen) emitEvent(found);
  } else if (hand.seen) {
    emitEvent(lost);
  }
  hand.seen = tracked.valid;
}

void LeapMotionDriver::updateHook() {
  if (sim_right_.read(right_.truth) != core::FlowStatus::NoData) right_.present = true;
  if (sim_left_.read(left_.truth) != core::FlowStatus::NoData) left_.present = true;
  const double dt = std::chrono::duration<double>(activity().period()).count();
  if (!tracker_->step(dt, right_.present, right_.truth, left_.present, left_.truth)) return;
  publish(tracker_->frame().right, right_, meas_right_, "e_right_hand_lost", "e_right_hand_found");
  publish(tracker_->frame().left, left_, meas_left_, "e_left_hand_lost", "e_left_hand_found");
}

}  // namespace cobra::components
