#include "cobra/sim/servo.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <utility>

namespace cobra::sim {
namespace {

void checkPerJoint(const ServoRobotModel& m, const std::vector<double>& values, const char* parameter,
                   const char* unit, bool zero_allowed) {
  if (values.size() != m.limits.size()) {
    throw std::invalid_argument("servo robot '" + m.name + "': " + parameter + " has " +
                                std::to_string(values.size()) + " values, expected one per joint (" +
                                std::to_string(m.limits.size()) + ")");
  }
  for (std::size_t i = 0; i < values.size(); ++i) {
    const double v = values[i];
    if (!std::isfinite(v) || v < 0.0 || (!zero_allowed && v == 0.0)) {
      throw std::invalid_argument("servo robot '" + m.name + "': " + parameter + " of joint " + std::to_string(i + 1) +
                                  " = " + std::to_string(v) + ", expected a finite value " +
                                  (zero_allowed ? ">= 0 " : "> 0 ") + unit);
    }
  }
}

}  // namespace

ServoRobotModel uniformServoModel(std::string name, const kinematics::JointLimits& limits, double time_constant,
                                  double max_velocity, double encoder_counts) {
  ServoRobotModel m;
  m.name = std::move(name);
  m.limits = limits;
  m.time_constant.assign(limits.size(), time_constant);
  m.max_velocity.assign(limits.size(), max_velocity);
  m.encoder_counts.assign(limits.size(), encoder_counts);
  return m;
}

void validate(const ServoRobotModel& m) {
  const std::size_t n = m.limits.size();
  if (n == 0 || n > 64) {
    throw std::invalid_argument("servo robot '" + m.name + "': " + std::to_string(n) +
                                " joints, expected 1 to 64");
  }
  if (m.limits.upper.size() != n || m.limits.types.size() != n) {
    throw std::invalid_argument("servo robot '" + m.name + "': limits.lower, limits.upper and limits.types "
                                "must have one entry per joint");
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (!std::isfinite(m.limits.lower[i]) || !std::isfinite(m.limits.upper[i]) ||
        m.limits.lower[i] > m.limits.upper[i]) {
      throw std::invalid_argument("servo robot '" + m.name + "': limits of joint " + std::to_string(i + 1) + " [" +
                                  std::to_string(m.limits.lower[i]) + ", " + std::to_string(m.limits.upper[i]) +
                                  "], expected finite values with lower <= upper (rad or m)");
    }
  }
  checkPerJoint(m, m.time_constant, "time_constant", "s", false);
  checkPerJoint(m, m.max_velocity, "max_velocity", "rad/s or m/s", false);
  checkPerJoint(m, m.encoder_counts, "encoder_counts", "counts per revolution or per metre", true);
}

ServoRobot::ServoRobot(ServoRobotModel model, std::span<const double> initial) : model_(std::move(model)) {
  validate(model_);
  const std::size_t n = model_.limits.size();
  if (initial.size() != n) {
    throw std::invalid_argument("servo robot '" + model_.name + "': initial position has " +
                                std::to_string(initial.size()) + " values, expected " + std::to_string(n));
  }
  resolution_.resize(n);
  decay_.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double counts = model_.encoder_counts[i];
    const double span = model_.limits.types[i] == kinematics::JointType::Revolute ? 2.0 * std::numbers::pi : 1.0;
    resolution_[i] = counts > 0.0 ? span / counts : 0.0;
  }
  q_.resize(static_cast<unsigned>(n));
  qd_.resize(static_cast<unsigned>(n));
  q_meas_.resize(static_cast<unsigned>(n));
  q_cmd_.resize(static_cast<unsigned>(n));
  for (unsigned i = 0; i < q_.rows(); ++i) {
    q_(i) = std::clamp(initial[i], model_.limits.lower[i], model_.limits.upper[i]);
    qd_(i) = 0.0;
    q_cmd_(i) = q_(i);
    q_meas_(i) = resolution_[i] > 0.0 ? resolution_[i] * std::rint(q_(i) / resolution_[i]) : q_(i);
  }
}

bool ServoRobot::command(std::span<const double> q_command) noexcept {
  const std::size_t n = resolution_.size();
  if (q_command.size() != n) return false;
  for (double v : q_command) {
    if (!std::isfinite(v)) return false;
  }
  for (std::size_t i = 0; i < n; ++i) {
    const double clamped = std::clamp(q_command[i], model_.limits.lower[i], model_.limits.upper[i]);
    if (clamped != q_command[i]) pending_position_limited_ |= (std::uint64_t{1} << i);
    q_cmd_.data[static_cast<Eigen::Index>(i)] = clamped;
  }
  return true;
}

bool ServoRobot::command(const KDL::JntArray& q_command) noexcept {
  return command(std::span<const double>(q_command.data.data(), q_command.rows()));
}

ServoStatus ServoRobot::step(double dt) noexcept {
  ServoStatus status;
  status.position_limited = std::exchange(pending_position_limited_, 0);
  if (!std::isfinite(dt) || dt <= 0.0) return status;
  const std::size_t n = decay_.size();
  if (dt != decay_dt_) {
    for (std::size_t i = 0; i < n; ++i) decay_[i] = std::exp(-dt / model_.time_constant[i]);
    decay_dt_ = dt;
  }
  // Raw element access: KDL::JntArray's operator() is an out-of-line call per element.
  double* q = q_.data.data();
  double* qd = qd_.data.data();
  double* q_meas = q_meas_.data.data();
  const double* q_cmd = q_cmd_.data.data();
  for (std::size_t i = 0; i < n; ++i) {
    const double target = q_cmd[i] + (q[i] - q_cmd[i]) * decay_[i];
    const double max_step = model_.max_velocity[i] * dt;
    double delta = target - q[i];
    if (std::abs(delta) > max_step) {
      delta = std::copysign(max_step, delta);
      status.velocity_limited |= (std::uint64_t{1} << i);
    }
    q[i] = std::clamp(q[i] + delta, model_.limits.lower[i], model_.limits.upper[i]);
    qd[i] = delta / dt;
    // The encoder's nearest count (rint: ties to even, inlined by the compiler; round is a libm call).
    q_meas[i] = resolution_[i] > 0.0 ? resolution_[i] * std::rint(q[i] / resolution_[i]) : q[i];
  }
  return status;
}

namespace {

kinematics::KinematicsSolver& sameJointCount(kinematics::KinematicsSolver& solver, const ServoRobot& robot) {
  if (solver.jointCount() != robot.jointCount()) {
    throw std::invalid_argument("CartesianServo: solver '" + std::string(solver.name()) + "' has " +
                                std::to_string(solver.jointCount()) + " joints but robot '" + robot.model().name +
                                "' has " + std::to_string(robot.jointCount()));
  }
  return solver;
}

}  // namespace

CartesianServo::CartesianServo(kinematics::KinematicsSolver& solver, ServoRobot& robot, double period)
    : solver_(sameJointCount(solver, robot)),
      robot_(robot),
      continuity_(solver, robot.model().max_velocity, period),
      solution_(robot.jointCount()) {}

CartesianCommandStatus CartesianServo::command(const KDL::Frame& target, double dt) noexcept {
  CartesianCommandStatus status;
  status.ik = continuity_.solve(target, robot_.commanded(), dt, solution_);
  if (status.ik != kinematics::IkStatus::Ok || !robot_.command(solution_)) {
    if (status.ik == kinematics::IkStatus::Ok) status.ik = kinematics::IkStatus::BadInput;
    status.holding = true;
  }
  return status;
}

bool CartesianServo::pose(KDL::Frame& out) noexcept {
  return solver_.forward(robot_.position(), out) == kinematics::IkStatus::Ok;
}

}  // namespace cobra::sim
