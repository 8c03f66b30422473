#include "cobra/components/sim/simulated_leap_motion.hpp"

#include "cobra/core/activity.hpp"

namespace cobra::components {

SimulatedLeapMotion::SimulatedLeapMotion(std::string name)
    : Component(std::move(name), core::Role::Bridge,
                "simulated Leap Motion hand tracker (thesis §5.3.3), for LeapMotionDriver device = sim:<name>") {
  addProperty(noise_);
  addProperty(seed_);
  addPort(right_);
  addPort(left_);
}

bool SimulatedLeapMotion::configureHook() {
  if (activity().period().count() <= 0) return refuse("needs a periodic activity: each update advances the tracker");
  sim::HandTrackerModel model;
  model.position_noise = noise_();
  try {
    device_.open(*this, "simulated Leap Motion of component '" + name() + "'", model,
                 static_cast<std::uint64_t>(seed_()));
  } catch (const std::exception& e) {
    return refuse(e.what());
  }
  right_hand_ = Hand{};
  left_hand_ = Hand{};
  return true;
}

bool SimulatedLeapMotion::startHook() {
  interval_.reset();
  return true;
}

void SimulatedLeapMotion::cleanupHook() { device_.close(); }

void SimulatedLeapMotion::updateHook() {
  const double dt = interval_.next(*this);
  if (right_.read(right_hand_.truth) != core::FlowStatus::NoData) right_hand_.present = true;
  if (left_.read(left_hand_.truth) != core::FlowStatus::NoData) left_hand_.present = true;
  device_.get()->step(dt, right_hand_.present, right_hand_.truth, left_hand_.present, left_hand_.truth);
}

}  // namespace cobra::components
