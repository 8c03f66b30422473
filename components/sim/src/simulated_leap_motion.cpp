#include "cobra/components/sim/simulated_leap_motion.hpp"

#include "cobra/core/activity.hpp"

namespace cobra::components {
namespace {
constexpr double kHandTimeConstant = 0.1;  // s: a scripted hand moving to its new pose
}  // namespace

SimulatedLeapMotion::SimulatedLeapMotion(std::string name)
    : Component(std::move(name), core::Role::Bridge,
                "simulated Leap Motion hand tracker (thesis §5.3.3), for LeapMotionDriver device = sim:<name>") {
  addProperty(noise_);
  addProperty(seed_);
  addProperty(scripted_);
  addProperty(right_pose_);
  addProperty(left_pose_);
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
  started_ = false;
  return true;
}

void SimulatedLeapMotion::cleanupHook() { device_.close(); }

void SimulatedLeapMotion::follow(core::InputPort<KDL::Frame>& port, const KDL::Frame& scripted, bool start, double dt,
                                 Hand& hand) noexcept {
  if (port.read(hand.truth) != core::FlowStatus::NoData) {
    hand.present = hand.from_port = true;
    return;
  }
  if (hand.from_port || !scripted_()) return;
  if (start || !hand.present) hand.scripted.reset(scripted);  // the hand appears where the script puts it
  hand.scripted.step(scripted, dt, kHandTimeConstant);
  hand.truth = hand.scripted.pose();
  hand.present = true;
}

void SimulatedLeapMotion::updateHook() {
  const double dt = interval_.next(*this);
  follow(right_, right_pose_(), !started_, dt, right_hand_);
  follow(left_, left_pose_(), !started_, dt, left_hand_);
  started_ = true;
  device_.get()->step(dt, right_hand_.present, right_hand_.truth, left_hand_.present, left_hand_.truth);
}

}  // namespace cobra::components
