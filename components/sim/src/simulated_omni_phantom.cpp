#include "cobra/components/sim/simulated_omni_phantom.hpp"

#include <stdexcept>

#include "cobra/core/activity.hpp"
#include "cobra/kinematics/kinematics_solver.hpp"

namespace cobra::components {
namespace {
constexpr double kWristTimeConstant = 0.05;  // s: the hand turning the stylus toward its target orientation
}  // namespace

SimulatedOmniPhantom::SimulatedOmniPhantom(std::string name)
    : Component(std::move(name), core::Role::Bridge,
                "Simulated Phantom Omni (thesis §4.5.9 interface) held by a scripted surgeon's hand") {
  addProperty(origin_pose_offset_);
  addProperty(initial_position_);
  addProperty(hand_motion_);
  addPort(des_wrench_);
  addPort(hand_target_);
  addPort(hand_buttons_);
  addPort(meas_cart_pose_);
  addPort(meas_twist_);
  addPort(status_buttons_);
  addPort(dissipated_power_);
}

bool SimulatedOmniPhantom::configureHook() {
  if (!kinematics::validFrame(origin_pose_offset_()))
    return refuse("property origin_pose_offset must be a finite frame with an orthonormal rotation");
  try {
    device_.emplace(sim::HapticMasterModel{}, initial_position_());
  } catch (const std::invalid_argument& e) {
    return refuse(std::string("property initial_position: ") + e.what());
  }
  device_->setHandTarget(initial_position_());
  stylus_.reset(KDL::Frame::Identity());
  target_rotation_ = KDL::Rotation::Identity();
  hand_target_seen_ = false;
  buttons_ = 0;
  return true;
}

bool SimulatedOmniPhantom::startHook() {
  last_update_ns_ = -1;
  return true;
}

void SimulatedOmniPhantom::cleanupHook() { device_.reset(); }

void SimulatedOmniPhantom::updateHook() {
  const std::int64_t now_ns = now().count();
  const double dt = last_update_ns_ < 0 ? std::chrono::duration<double>(activity().period()).count()
                                        : static_cast<double>(now_ns - last_update_ns_) * 1e-9;
  last_update_ns_ = now_ns;
  const KDL::Frame& offset = origin_pose_offset_();
  KDL::Frame target;
  if (hand_target_.read(target) == core::FlowStatus::NewData) {
    hand_target_seen_ = true;
    device_->setHandTarget(offset.Inverse(target.p));
    target_rotation_ = offset.M.Inverse() * target.M;
  } else if (!hand_target_seen_) {
    const KDL::Frame& motion = hand_motion_();
    device_->setHandTarget(initial_position_() + motion.p);
    target_rotation_ = motion.M;
  }
  KDL::Wrench wrench;
  if (des_wrench_.read(wrench) != core::FlowStatus::NoData) device_->setCommandedForce(offset.M.Inverse(wrench.force));
  (void)hand_buttons_.read(buttons_);
  device_->step(dt);
  const KDL::Rotation before = stylus_.pose().M;
  stylus_.step(KDL::Frame(target_rotation_), dt, kWristTimeConstant);
  meas_cart_pose_.write(KDL::Frame(offset.M * stylus_.pose().M, offset * device_->measured()));
  meas_twist_.write(
      KDL::Twist(offset.M * device_->velocity(), offset.M * angularVelocity(before, stylus_.pose().M, dt)));
  status_buttons_.write(buttons_);
  dissipated_power_.write(device_->dissipatedPower());
}

}  // namespace cobra::components
