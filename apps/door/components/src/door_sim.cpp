#include "cobra/components/door/door_sim.hpp"

#include <algorithm>
#include <cmath>

namespace cobra::components {

DoorSim::DoorSim(std::string name)
    : Component(std::move(name), core::Role::Bridge, "Simulated arm, handle and door of the door example") {
  for (core::PortBase* port : std::initializer_list<core::PortBase*>{&arm_target_, &grip_command_, &handle_torque_,
                                                                     &pull_force_, &arm_position_, &gripped_,
                                                                     &handle_angle_, &door_angle_,
                                                                     &applied_arm_target_, &applied_grip_,
                                                                     &applied_torque_, &applied_force_})
    addPort(*port);
  addProperty(handle_position_.range(0.0, 10.0));
  addProperty(arm_time_constant_.range(1e-3, 10.0));
  addProperty(grip_tolerance_.range(1e-4, 1.0));
  addProperty(handle_stiffness_.range(0.0, 1e3));
  addProperty(handle_damping_.range(1e-3, 1e3));
  addProperty(latch_angle_.range(0.0, 3.0));
  addProperty(door_inertia_.range(1e-3, 1e3));
  addProperty(door_damping_.range(0.0, 1e3));
  addProperty(lever_arm_.range(1e-2, 10.0));
  addProperty(door_max_angle_.range(0.0, 3.2));
  addProperty(command_timeout_.range(1e-3, 10.0));
}

bool DoorSim::startHook() {
  last_step_ = now();
  arm_ = handle_ = door_ = door_rate_ = 0.0;
  arm_target_value_ = grip_value_ = torque_value_ = force_value_ = 0.0;
  gripped_state_ = false;
  arm_refused_ = grip_refused_ = torque_refused_ = force_refused_ = false;
  return true;
}

bool DoorSim::takeFinite(core::InputPort<double>& port, double& value, bool& refused) noexcept {
  double sample = 0.0;
  // Only a new sample counts: an old one is the value taken, or the non-finite one refused.
  if (port.read(sample) != core::FlowStatus::NewData) return false;
  if (std::isfinite(sample)) {
    value = sample;
    refused = false;
    return true;
  }
  if (!refused) emitEvent("e_command_not_finite");  // once per episode
  refused = true;
  return false;
}

double DoorSim::freshCommand(core::InputPort<double>& port, double& value, std::chrono::nanoseconds& stamp,
                             bool& refused) {
  if (takeFinite(port, value, refused)) stamp = now();
  const bool stale = std::chrono::duration<double>(now() - stamp).count() > command_timeout_();
  return stale ? 0.0 : value;
}

void DoorSim::updateHook() {
  const double dt = std::chrono::duration<double>(now() - last_step_).count();
  last_step_ = now();
  (void)takeFinite(arm_target_, arm_target_value_, arm_refused_);  // a position target holds until changed
  const double grip = freshCommand(grip_command_, grip_value_, grip_stamp_, grip_refused_);
  const double torque = freshCommand(handle_torque_, torque_value_, torque_stamp_, torque_refused_);
  const double force = freshCommand(pull_force_, force_value_, force_stamp_, force_refused_);
  applied_arm_target_.write(arm_target_value_);
  applied_grip_.write(grip);
  applied_torque_.write(torque);
  applied_force_.write(force);

  // Exact discretisation of the arm's first-order lag; once grasped the arm moves with the handle.
  if (!gripped_state_) arm_ += (arm_target_value_ - arm_) * (1.0 - std::exp(-dt / arm_time_constant_()));
  if (grip > 0.5 && std::abs(arm_ - handle_position_()) < grip_tolerance_()) gripped_state_ = true;
  if (grip <= 0.5) gripped_state_ = false;

  // Handle: overdamped spring, driven only when grasped (semi-implicit: stable for any dt).
  const double drive = gripped_state_ ? torque : 0.0;
  handle_ = (handle_ + dt * drive / handle_damping_()) / (1.0 + dt * handle_stiffness_() / handle_damping_());
  handle_ = std::clamp(handle_, 0.0, 1.5);

  // Door: latched while closed and the handle is below the latch angle.
  const bool latched = door_ < 1e-6 && handle_ < latch_angle_();
  if (latched) {
    door_rate_ = 0.0;
  } else {
    const double moment = gripped_state_ ? force * lever_arm_() : 0.0;
    door_rate_ = (door_rate_ + dt * moment / door_inertia_()) / (1.0 + dt * door_damping_() / door_inertia_());
    door_ += dt * door_rate_;
    if (door_ <= 0.0 || door_ >= door_max_angle_()) door_rate_ = 0.0;
    door_ = std::clamp(door_, 0.0, door_max_angle_());
  }
  arm_position_.write(arm_);
  gripped_.write(gripped_state_ ? 1.0 : 0.0);
  handle_angle_.write(handle_);
  door_angle_.write(door_);
}

}  // namespace cobra::components
