#include "cobra/sim/cia402_drive.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace cobra::sim {
namespace {

void requireRange(const char* parameter, double value, double minimum, bool inclusive, const char* unit) {
  if (!std::isfinite(value) || value < minimum || (!inclusive && value == minimum)) {
    throw std::invalid_argument(std::string("CiA 402 drive: ") + parameter + " = " + std::to_string(value) +
                                ", expected " + (inclusive ? ">= " : "> ") + std::to_string(minimum) + " " + unit);
  }
}

/// Moves `value` towards `target` by at most `step`.
double approach(double value, double target, double step) noexcept {
  return value + std::clamp(target - value, -step, step);
}

}  // namespace

const char* toString(Cia402State state) noexcept {
  switch (state) {
    case Cia402State::NotReadyToSwitchOn: return "not_ready_to_switch_on";
    case Cia402State::SwitchOnDisabled: return "switch_on_disabled";
    case Cia402State::ReadyToSwitchOn: return "ready_to_switch_on";
    case Cia402State::SwitchedOn: return "switched_on";
    case Cia402State::OperationEnabled: return "operation_enabled";
    case Cia402State::QuickStopActive: return "quick_stop_active";
    case Cia402State::FaultReactionActive: return "fault_reaction_active";
    case Cia402State::Fault: return "fault";
  }
  return "unknown";
}

void validate(const Cia402DriveModel& m) {
  requireRange("inertia", m.inertia, 0.0, false, "kg*m^2");
  requireRange("viscous_friction", m.viscous_friction, 0.0, true, "N*m*s/rad");
  requireRange("torque_constant", m.torque_constant, 0.0, false, "N*m/A");
  requireRange("continuous_current", m.continuous_current, 0.0, false, "A");
  requireRange("peak_current", m.peak_current, m.continuous_current, true, "A (continuous_current)");
  requireRange("over_current_time", m.over_current_time, 0.0, false, "s");
  requireRange("velocity_bandwidth", m.velocity_bandwidth, 0.0, false, "rad/s");
  requireRange("position_gain", m.position_gain, 0.0, false, "1/s");
  requireRange("following_error_window", m.following_error_window, 0.0, false, "rad");
  requireRange("following_error_timeout", m.following_error_timeout, 0.0, true, "s");
  requireRange("position_window", m.position_window, 0.0, false, "rad");
  requireRange("velocity_window", m.velocity_window, 0.0, false, "rad/s");
  requireRange("profile_velocity", m.profile_velocity, 0.0, false, "rad/s");
  requireRange("profile_acceleration", m.profile_acceleration, 0.0, false, "rad/s^2");
  requireRange("torque_slope", m.torque_slope, 0.0, false, "N*m/s");
  requireRange("quick_stop_deceleration", m.quick_stop_deceleration, 0.0, false, "rad/s^2");
  requireRange("internal_period", m.internal_period, 0.0, false, "s");
  if (m.quick_stop_option != 2 && m.quick_stop_option != 6) {
    throw std::invalid_argument("CiA 402 drive: quick_stop_option = " + std::to_string(m.quick_stop_option) +
                                ", expected 2 (stop, then switch on disabled) or 6 (stop, stay in quick stop active)");
  }
}

Cia402Drive::Cia402Drive(const Cia402DriveModel& model, double initial_position)
    : model_(model), position_(initial_position), setpoint_position_(initial_position), pp_target_(initial_position) {
  validate(model_);
  if (!std::isfinite(initial_position)) throw std::invalid_argument("CiA 402 drive: initial_position is not finite (rad)");
  updateStatusword();
}

void Cia402Drive::enterFault(std::uint16_t code) noexcept {
  error_code_ = code;
  state_ = Cia402State::FaultReactionActive;
}

// Device control commands of the CiA 402 state machine (transition numbers of the standard).
void Cia402Drive::evaluateControlword() noexcept {
  const std::uint16_t cw = controlword_;
  const bool fault_reset_edge = (cw & controlword::kFaultReset) && !(previous_controlword_ & controlword::kFaultReset);
  previous_controlword_ = cw;
  const bool disable_voltage = (cw & 0x82) == 0x00;
  const bool quick_stop = (cw & 0x86) == 0x02;
  const bool shutdown = (cw & 0x87) == 0x06;
  const bool switch_on = (cw & 0x87) == 0x07;             // bit 3 free: 3 (and 3+4 over two cycles)
  const bool enable_operation = (cw & 0x8F) == 0x0F;
  const bool disable_operation = (cw & 0x8F) == 0x07;
  const auto enable = [&] {
    velocity_integral_ = 0.0;
    setpoint_position_ = pp_target_ = position_;
    setpoint_velocity_ = velocity_;
    setpoint_torque_ = 0.0;
    state_ = Cia402State::OperationEnabled;
  };
  switch (state_) {
    case Cia402State::NotReadyToSwitchOn: state_ = Cia402State::SwitchOnDisabled; break;  // 1
    case Cia402State::SwitchOnDisabled:
      if (shutdown) state_ = Cia402State::ReadyToSwitchOn;  // 2
      break;
    case Cia402State::ReadyToSwitchOn:
      if (disable_voltage || quick_stop) state_ = Cia402State::SwitchOnDisabled;  // 7
      else if (switch_on) state_ = Cia402State::SwitchedOn;                       // 3
      break;
    case Cia402State::SwitchedOn:
      if (disable_voltage || quick_stop) state_ = Cia402State::SwitchOnDisabled;  // 10
      else if (shutdown) state_ = Cia402State::ReadyToSwitchOn;                   // 6
      else if (enable_operation) enable();                                        // 4
      break;
    case Cia402State::OperationEnabled:
      if (disable_voltage) state_ = Cia402State::SwitchOnDisabled;                // 9
      else if (quick_stop) {                                                      // 11
        quick_stop_velocity_ = velocity_;
        state_ = Cia402State::QuickStopActive;
      }
      else if (shutdown) state_ = Cia402State::ReadyToSwitchOn;                   // 8
      else if (disable_operation) state_ = Cia402State::SwitchedOn;               // 5
      break;
    case Cia402State::QuickStopActive:
      if (disable_voltage) state_ = Cia402State::SwitchOnDisabled;  // 12
      else if (model_.quick_stop_option == 2 && std::abs(velocity_) < model_.velocity_window) {
        state_ = Cia402State::SwitchOnDisabled;  // 12, automatic: option 2 disables once stopped
      } else if (enable_operation && model_.quick_stop_option == 6 && std::abs(velocity_) < model_.velocity_window) {
        enable();  // 16
      }
      break;
    case Cia402State::FaultReactionActive: state_ = Cia402State::Fault; break;  // 14: reaction = torque off
    case Cia402State::Fault:
      if (fault_reset_edge) {  // 15
        error_code_ = error_code::kNone;
        following_error_ = false;
        following_error_time_ = over_current_time_ = 0.0;
        state_ = Cia402State::SwitchOnDisabled;
      }
      break;
  }
}

double Cia402Drive::demandedTorque(double h) noexcept {
  const double kv = model_.inertia * model_.velocity_bandwidth;  // N·m·s/rad: crossover at the bandwidth
  const double ki = kv * model_.velocity_bandwidth / 4.0;        // N·m/rad: PI zero a quarter below
  double velocity_demand = 0.0;
  double feed_forward = 0.0;
  switch (mode_) {
    case Cia402Mode::CyclicSynchronousTorque: return target_torque_;
    case Cia402Mode::ProfileTorque:
      setpoint_torque_ = approach(setpoint_torque_, target_torque_, model_.torque_slope * h);
      return setpoint_torque_;
    case Cia402Mode::CyclicSynchronousVelocity: velocity_demand = target_velocity_; break;
    case Cia402Mode::ProfileVelocity:
      setpoint_velocity_ = approach(setpoint_velocity_, target_velocity_, model_.profile_acceleration * h);
      velocity_demand = setpoint_velocity_;
      break;
    case Cia402Mode::CyclicSynchronousPosition:
      setpoint_position_ = target_position_;
      velocity_demand = model_.position_gain * (setpoint_position_ - position_);
      break;
    case Cia402Mode::ProfilePosition: {
      // Trapezoidal profile: brake in time (v² = 2·a·distance), never faster than profile_velocity.
      const double remaining = pp_target_ - setpoint_position_;
      const double cruise = std::min(model_.profile_velocity, std::sqrt(2.0 * model_.profile_acceleration * std::abs(remaining)));
      setpoint_velocity_ = approach(setpoint_velocity_, std::copysign(cruise, remaining), model_.profile_acceleration * h);
      setpoint_position_ += setpoint_velocity_ * h;
      if (std::abs(pp_target_ - setpoint_position_) < 1e-9 || (remaining > 0) != (pp_target_ - setpoint_position_ > 0)) {
        setpoint_position_ = pp_target_;
        setpoint_velocity_ = 0.0;
      }
      feed_forward = setpoint_velocity_;
      velocity_demand = feed_forward + model_.position_gain * (setpoint_position_ - position_);
      break;
    }
  }
  if (state_ == Cia402State::QuickStopActive) {
    quick_stop_velocity_ = approach(quick_stop_velocity_, 0.0, model_.quick_stop_deceleration * h);
    velocity_demand = quick_stop_velocity_;
  }
  const double error = velocity_demand - velocity_;
  const double integral = velocity_integral_ + ki * error * h;
  const double torque = kv * error + integral;
  // Conditional integration (anti-windup): the integrator only moves while the current is not limited.
  if (std::abs(torque) <= model_.peak_current * model_.torque_constant) velocity_integral_ = integral;
  return torque;
}

double Cia402Drive::controlTorque(double h, double position, double velocity) noexcept {
  position_ = position;
  velocity_ = velocity;
  double torque = powered() && h > 0.0 ? demandedTorque(h) : 0.0;
  double current = torque / model_.torque_constant;
  if (std::abs(current) > model_.peak_current) {
    current = std::copysign(model_.peak_current, current);
    torque = current * model_.torque_constant;
    internal_limit_ = true;
  }
  current_ = current;
  torque_ = torque;
  return torque;
}

void Cia402Drive::runLoops(double dt) noexcept {
  const int substeps = std::max(1, static_cast<int>(std::ceil(dt / model_.internal_period - 1e-9)));
  const double h = dt / substeps;
  for (int i = 0; i < substeps; ++i) {
    const double torque = controlTorque(h, position_, velocity_);
    // Semi-implicit Euler of J·dω/dt = τ - b·ω - τ_load: stable for the stiff viscous term.
    velocity_ = (velocity_ + h * (torque - load_torque_) / model_.inertia) / (1.0 + h * model_.viscous_friction / model_.inertia);
    position_ += velocity_ * h;
  }
}

void Cia402Drive::superviseFaults(double dt) noexcept {
  if (!powered()) return;
  over_current_time_ = internal_limit_ ? over_current_time_ + dt : 0.0;
  const bool position_mode = mode_ == Cia402Mode::CyclicSynchronousPosition || mode_ == Cia402Mode::ProfilePosition;
  following_error_ = position_mode && std::abs(setpoint_position_ - position_) > model_.following_error_window;
  following_error_time_ = following_error_ ? following_error_time_ + dt : 0.0;
  if (over_current_time_ >= model_.over_current_time) enterFault(error_code::kOverCurrent);
  else if (following_error_ && following_error_time_ > model_.following_error_timeout) enterFault(error_code::kFollowingError);
}

void Cia402Drive::updateStatusword() noexcept {
  using namespace statusword;
  std::uint16_t word = 0;
  switch (state_) {  // the bit patterns of the standard's statusword table (bits 0-3, 5, 6)
    case Cia402State::NotReadyToSwitchOn: word = 0x0000; break;
    case Cia402State::SwitchOnDisabled: word = kSwitchOnDisabled; break;
    case Cia402State::ReadyToSwitchOn: word = kQuickStop | kReadyToSwitchOn; break;
    case Cia402State::SwitchedOn: word = kQuickStop | kSwitchedOn | kReadyToSwitchOn; break;
    case Cia402State::OperationEnabled: word = kQuickStop | kOperationEnabled | kSwitchedOn | kReadyToSwitchOn; break;
    case Cia402State::QuickStopActive: word = kOperationEnabled | kSwitchedOn | kReadyToSwitchOn; break;
    case Cia402State::FaultReactionActive: word = kFault | kOperationEnabled | kSwitchedOn | kReadyToSwitchOn; break;
    case Cia402State::Fault: word = kFault; break;
  }
  if (state_ != Cia402State::NotReadyToSwitchOn) word |= kVoltageEnabled | kRemote;  // DC bus present, bus control
  if (internal_limit_) word |= kInternalLimit;
  if (following_error_) word |= kFollowingError;
  if (state_ == Cia402State::OperationEnabled) {
    bool reached = false;
    switch (mode_) {
      case Cia402Mode::ProfilePosition:
      case Cia402Mode::CyclicSynchronousPosition:
        reached = std::abs((mode_ == Cia402Mode::ProfilePosition ? pp_target_ : target_position_) - position_) <=
                  model_.position_window;
        break;
      case Cia402Mode::ProfileVelocity:
      case Cia402Mode::CyclicSynchronousVelocity: reached = std::abs(target_velocity_ - velocity_) <= model_.velocity_window; break;
      case Cia402Mode::ProfileTorque:
      case Cia402Mode::CyclicSynchronousTorque: reached = std::abs(target_torque_ - torque_) <= 1e-6 + 1e-3 * std::abs(target_torque_); break;
    }
    if (reached) word |= kTargetReached;
    if (mode_ == Cia402Mode::ProfilePosition && set_point_acknowledge_) word |= kSetPointAcknowledge;
  }
  statusword_ = word;
}

void Cia402Drive::beginCycle() noexcept {
  if (injected_fault_ != error_code::kNone && state_ != Cia402State::Fault && state_ != Cia402State::FaultReactionActive) {
    enterFault(injected_fault_);
    injected_fault_ = error_code::kNone;
  } else {
    evaluateControlword();
  }
  if (mode_ != requested_mode_) {
    mode_ = requested_mode_;
    setpoint_position_ = pp_target_ = position_;
    setpoint_velocity_ = velocity_;
    setpoint_torque_ = torque_;
  }
  // Profile position: a new set-point is taken on the rising edge of bit 4 and acknowledged
  // (statusword bit 12) while bit 4 stays high.
  const bool new_set_point = controlword_ & controlword::kNewSetPoint;
  if (mode_ == Cia402Mode::ProfilePosition && state_ == Cia402State::OperationEnabled && new_set_point &&
      !set_point_acknowledge_) {
    pp_target_ = target_position_;
  }
  set_point_acknowledge_ = new_set_point && mode_ == Cia402Mode::ProfilePosition;
  internal_limit_ = false;
}

std::uint16_t Cia402Drive::endCycle(double dt, double position, double velocity) noexcept {
  position_ = position;
  velocity_ = velocity;
  if (std::isfinite(dt) && dt > 0.0) superviseFaults(dt);
  updateStatusword();
  return statusword_;
}

std::uint16_t Cia402Drive::step(double dt) noexcept {
  if (!std::isfinite(dt) || dt <= 0.0) return statusword_;
  beginCycle();
  runLoops(dt);
  return endCycle(dt, position_, velocity_);
}

}  // namespace cobra::sim
