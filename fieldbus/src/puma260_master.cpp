#include "cobra/fieldbus/puma260_master.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>

#include "cobra/text/number.hpp"

namespace cobra::fieldbus {
namespace {

using text::number;

void requirePositive(const char* parameter, double value, const char* unit) {
  if (!std::isfinite(value) || value <= 0.0) {
    throw std::invalid_argument(std::string("Puma 260 master: ") + parameter + " = " + number(value) + " " + unit +
                                ", expected > 0");
  }
}

void requireWithinLimits(const char* parameter, const JointVector& q, const Puma260MasterConfig& c) {
  for (std::size_t i = 0; i < 6; ++i) {
    if (!std::isfinite(q[i]) || q[i] < c.lower[i] || q[i] > c.upper[i]) {
      throw std::invalid_argument(std::string("Puma 260 master: ") + parameter + "[" + std::to_string(i) +
                                  "] = " + number(q[i]) + " rad is outside the joint limits [" + number(c.lower[i]) +
                                  ", " + number(c.upper[i]) + "] rad");
    }
  }
}

/// Minimum-jerk blend 10τ³ − 15τ⁴ + 6τ⁵ (zero velocity and acceleration at both ends); its peak
/// slope is 1.875.
double minimumJerk(double tau) noexcept {
  tau = std::clamp(tau, 0.0, 1.0);
  return tau * tau * tau * (10.0 + tau * (-15.0 + 6.0 * tau));
}
constexpr double kMinimumJerkPeakSlope = 1.875;

bool faulted(cia402::DeviceState s) noexcept {
  return s == cia402::DeviceState::Fault || s == cia402::DeviceState::FaultReactionActive;
}

}  // namespace

const char* toString(MasterState state) noexcept {
  switch (state) {
    case MasterState::NotInitialized:
      return "NotInitialized";
    case MasterState::Initialized:
      return "Initialized";
    case MasterState::MovingToNest:
      return "MovingToNest";
    case MasterState::NestPosition:
      return "NestPosition";
    case MasterState::MovingToReady:
      return "MovingToReady";
    case MasterState::ReadyPosition:
      return "ReadyPosition";
    case MasterState::Operative:
      return "Operative";
    case MasterState::Fault:
      return "Fault";
  }
  return "Unknown";
}

bool parseControlMode(const char* text, ControlMode& out) noexcept {
  if (std::strcmp(text, "position") == 0)
    out = ControlMode::Position;
  else if (std::strcmp(text, "velocity") == 0)
    out = ControlMode::Velocity;
  else if (std::strcmp(text, "torque") == 0)
    out = ControlMode::Torque;
  else
    return false;
  return true;
}

void validate(const Puma260MasterConfig& c) {
  for (std::size_t i = 0; i < 6; ++i) {
    if (!std::isfinite(c.lower[i]) || !std::isfinite(c.upper[i]) || c.lower[i] >= c.upper[i]) {
      throw std::invalid_argument("Puma 260 master: joint " + std::to_string(i) + " limits [" + number(c.lower[i]) +
                                  ", " + number(c.upper[i]) + "] rad: expected finite lower < upper");
    }
  }
  requireWithinLimits("nest", c.nest, c);
  requireWithinLimits("ready", c.ready, c);
  requirePositive("move_speed", c.move_speed, "rad/s");
  requirePositive("position_tolerance", c.position_tolerance, "rad");
  requirePositive("max_velocity", c.max_velocity, "rad/s");
  requirePositive("max_torque", c.max_torque, "N*m");
}

Puma260Master::Puma260Master(const Puma260MasterConfig& config, Cia402Bus& bus) : config_(config), bus_(bus) {
  validate(config_);
  if (bus_.slaveCount() != 6) {
    throw std::invalid_argument("Puma 260 master: the bus has " + std::to_string(bus_.slaveCount()) +
                                " slaves; the Puma 260 needs 6 (one drive per joint)");
  }
  setGoal(cia402::Goal::Enabled);
}

void Puma260Master::setGoal(cia402::Goal goal) noexcept {
  for (auto& s : sequencers_) s.setGoal(goal);
}

bool Puma260Master::allAtGoal() const noexcept {
  return std::all_of(sequencers_.begin(), sequencers_.end(), [](const auto& s) { return s.atGoal(); });
}

bool Puma260Master::request(Request r) noexcept {
  switch (r) {
    case Request::Ready:
      if (state_ != MasterState::Initialized && state_ != MasterState::NestPosition &&
          state_ != MasterState::ReadyPosition && state_ != MasterState::Operative)
        return false;
      startMove(config_.ready, MasterState::MovingToReady);
      return true;
    case Request::Nest:
      if (state_ != MasterState::ReadyPosition) return false;
      startMove(config_.nest, MasterState::MovingToNest);
      return true;
    case Request::Operative:
      if (state_ != MasterState::ReadyPosition) return false;
      state_ = MasterState::Operative;
      operative_pending_ = true;
      return true;
    case Request::FaultReset:
      if (state_ != MasterState::Fault) return false;
      for (auto& s : sequencers_) s.requestFaultReset();
      recovering_ = true;
      return true;
  }
  return false;
}

void Puma260Master::startMove(const JointVector& goal, MasterState moving) noexcept {
  move_start_ = position_;
  move_goal_ = goal;
  double distance = 0.0;
  for (std::size_t i = 0; i < 6; ++i) distance = std::max(distance, std::abs(goal[i] - position_[i]));
  move_duration_ = kMinimumJerkPeakSlope * distance / config_.move_speed;
  move_time_ = 0.0;
  state_ = moving;
}

void Puma260Master::fillTargets(const JointCommands& cmd, std::uint32_t& events) noexcept {
  bool clamped = false;
  const bool operative = state_ == MasterState::Operative;
  for (std::size_t i = 0; i < 6; ++i) {
    Cia402Outputs& o = outputs_[i];
    o.mode = cia402::Mode::CyclicPosition;
    o.target_velocity = 0.0;
    o.target_torque = 0.0;
    if (operative) {
      // Until the first command of the selected mode arrives, the joints hold their position.
      switch (config_.control_mode) {
        case ControlMode::Position:
          if (cmd.position_valid) {
            const double q = std::clamp(cmd.position[i], config_.lower[i], config_.upper[i]);
            clamped = clamped || q != cmd.position[i];
            hold_[i] = q;
          }
          break;
        case ControlMode::Velocity:
          if (cmd.velocity_valid) {
            double v = std::clamp(cmd.velocity[i], -config_.max_velocity, config_.max_velocity);
            if ((position_[i] >= config_.upper[i] && v > 0) || (position_[i] <= config_.lower[i] && v < 0)) v = 0.0;
            clamped = clamped || v != cmd.velocity[i];
            o.mode = cia402::Mode::CyclicVelocity;
            o.target_velocity = v;
          }
          break;
        case ControlMode::Torque:
          if (cmd.torque_valid) {
            const double t = std::clamp(cmd.torque[i], -config_.max_torque, config_.max_torque);
            clamped = clamped || t != cmd.torque[i];
            o.mode = cia402::Mode::CyclicTorque;
            o.target_torque = t;
          }
          break;
      }
      if (o.mode != cia402::Mode::CyclicPosition) hold_[i] = position_[i];
    }
    o.target_position = hold_[i];
  }
  if (clamped && !clamped_) events |= master_event::kCommandClamped;
  clamped_ = clamped;
}

std::uint32_t Puma260Master::step(double dt, const JointCommands& commands) noexcept {
  std::uint32_t events = 0;
  for (std::size_t i = 0; i < 6; ++i) outputs_[i].controlword = sequencers_[i].next(inputs_[i].statusword);
  fillTargets(commands, events);
  const BusStatus status = bus_.exchange(outputs_, inputs_);
  if (status != BusStatus::Ok) {
    // A wrong working counter is its own event (with the counters kept for the log) every time it
    // happens; either failure puts the master in Fault once: the drives quick-stop.
    if (status == BusStatus::WorkingCounterMismatch) {
      working_counter_fault_ = bus_.workingCounter();
      events |= master_event::kWorkingCounterMismatch;
    }
    if (state_ != MasterState::Fault) {
      state_ = MasterState::Fault;
      fault_slave_ = -1;
      fault_code_ = 0;
      recovering_ = false;
      setGoal(cia402::Goal::QuickStop);
      hold_ = position_;
      if (status != BusStatus::WorkingCounterMismatch) events |= master_event::kBusError | master_event::kDriveFault;
    }
    return events;
  }
  std::array<cia402::DeviceState, 6> states{};
  for (std::size_t i = 0; i < 6; ++i) {
    position_[i] = inputs_[i].position;
    velocity_[i] = inputs_[i].velocity;
    torque_[i] = inputs_[i].torque;
    states[i] = cia402::decodeStatusword(inputs_[i].statusword);
  }
  if (state_ != MasterState::Fault) {
    for (std::size_t i = 0; i < 6; ++i) {
      if (!faulted(states[i])) continue;
      state_ = MasterState::Fault;
      fault_slave_ = static_cast<int>(i);
      fault_code_ = inputs_[i].error_code;
      recovering_ = false;
      setGoal(cia402::Goal::QuickStop);  // stop commanding: the healthy drives ramp down and switch off
      hold_ = position_;
      return events | master_event::kDriveFault;
    }
  }
  const auto all = [&](cia402::DeviceState s) {
    return std::all_of(states.begin(), states.end(), [s](cia402::DeviceState x) { return x == s; });
  };
  switch (state_) {
    case MasterState::NotInitialized:
      if (all(cia402::DeviceState::OperationEnabled)) {
        state_ = MasterState::Initialized;
        events |= master_event::kInitialized;
      } else {
        hold_ = position_;  // enable on the spot: no jump when the power stage comes on
      }
      break;
    case MasterState::MovingToNest:
    case MasterState::MovingToReady: {
      move_time_ += dt;
      const double s = move_duration_ > 0.0 ? minimumJerk(move_time_ / move_duration_) : 1.0;
      bool arrived = move_time_ >= move_duration_;
      for (std::size_t i = 0; i < 6; ++i) {
        hold_[i] = move_start_[i] + (move_goal_[i] - move_start_[i]) * s;
        arrived = arrived && std::abs(position_[i] - move_goal_[i]) <= config_.position_tolerance;
      }
      if (arrived) {
        const bool nest = state_ == MasterState::MovingToNest;
        state_ = nest ? MasterState::NestPosition : MasterState::ReadyPosition;
        events |= nest ? master_event::kNestReached : master_event::kReadyReached;
      }
      break;
    }
    case MasterState::Operative:
      if (operative_pending_) {
        operative_pending_ = false;
        events |= master_event::kOperative;
      }
      break;
    case MasterState::Fault:
      hold_ = position_;
      if (recovering_ && std::none_of(states.begin(), states.end(), faulted)) {
        recovering_ = false;
        fault_slave_ = -1;
        fault_code_ = 0;
        setGoal(cia402::Goal::Enabled);
        state_ = MasterState::NotInitialized;  // re-enables every drive, then Initialized
        events |= master_event::kFaultReset;
      }
      break;
    case MasterState::Initialized:
    case MasterState::NestPosition:
    case MasterState::ReadyPosition:
      break;
  }
  return events;
}

}  // namespace cobra::fieldbus
