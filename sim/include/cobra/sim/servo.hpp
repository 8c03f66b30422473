#pragma once
/// @file
/// Position-controlled robot joints: each joint follows its command with a first-order lag,
/// within position and velocity limits, and is read back through a quantising encoder. A helper
/// drives such a robot in Cartesian space through a kinematics::KinematicsSolver, refusing the
/// commands it could only follow by swinging (kinematics::ContinuousIk).

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <kdl/frames.hpp>
#include <kdl/jntarray.hpp>

#include "cobra/kinematics/continuity.hpp"
#include "cobra/kinematics/kinematics_solver.hpp"

namespace cobra::sim {

/// Immutable description of a position-controlled robot of n <= 64 joints. Joint units: rad for
/// revolute, m for prismatic joints (as in kinematics::JointLimits).
struct ServoRobotModel {
  std::string name = "robot";           ///< used in error messages
  kinematics::JointLimits limits;       ///< position limits per joint (rad / m), lower <= upper
  std::vector<double> time_constant;    ///< first-order lag per joint (s), > 0
  std::vector<double> max_velocity;     ///< |velocity| limit per joint (rad/s, m/s), > 0
  std::vector<double> encoder_counts;   ///< counts per revolution (revolute) / per metre (prismatic), >= 0 (0 = exact)
};

/// A model with the same lag, velocity limit and encoder on every joint of `limits`.
ServoRobotModel uniformServoModel(std::string name, const kinematics::JointLimits& limits, double time_constant,
                                  double max_velocity, double encoder_counts);

/// @throws std::invalid_argument naming the robot, the parameter, the joint (1-based) and the range.
void validate(const ServoRobotModel& model);

/// What happened in one step; bit i = joint i.
struct ServoStatus {
  std::uint64_t position_limited = 0;  ///< the command was outside the limits and was clamped
  std::uint64_t velocity_limited = 0;  ///< the lag asked for more than max_velocity; clamped
  bool ok() const noexcept { return position_limited == 0 && velocity_limited == 0; }
};

/// The state of a servo robot. The response to a held command c from q0 is exact:
/// q(t) = c + (q0 - c)·exp(-t/τ), unless the velocity limit clamps it. `command` and `step` are
/// noexcept and allocate nothing.
class ServoRobot {
 public:
  /// Starts at rest at `initial` (clamped into the limits), commanded to stay there.
  /// @throws std::invalid_argument when the model is invalid or `initial` has the wrong size.
  ServoRobot(ServoRobotModel model, std::span<const double> initial);

  unsigned jointCount() const noexcept { return q_.rows(); }
  /// Sets the joint command (rad / m); values outside the limits are clamped and flagged in the
  /// next status. False (command unchanged) when the size is wrong or a value is not finite.
  bool command(std::span<const double> q_command) noexcept;
  bool command(const KDL::JntArray& q_command) noexcept;
  /// Advances by `dt` (s); a non-positive or non-finite dt changes nothing.
  ServoStatus step(double dt) noexcept;

  const KDL::JntArray& position() const noexcept { return q_; }       ///< true joint position (rad / m)
  const KDL::JntArray& velocity() const noexcept { return qd_; }      ///< joint velocity (rad/s, m/s)
  const KDL::JntArray& measured() const noexcept { return q_meas_; }  ///< encoder reading (rad / m)
  const KDL::JntArray& commanded() const noexcept { return q_cmd_; }  ///< clamped command (rad / m)
  const ServoRobotModel& model() const noexcept { return model_; }

 private:
  ServoRobotModel model_;
  std::vector<double> resolution_;  // encoder step per joint (rad / m), 0 = exact
  std::vector<double> decay_;       // exp(-decay_dt_ / time_constant) per joint
  double decay_dt_ = -1.0;          // s: the dt decay_ holds (a control loop's dt is constant)
  KDL::JntArray q_, qd_, q_meas_, q_cmd_;
  std::uint64_t pending_position_limited_ = 0;
};

/// Result of a Cartesian command.
struct CartesianCommandStatus {
  /// Ok, or why the last valid command is held: the solver's failure (e.g. Unreachable), or
  /// Discontinuous when the solution is not reachable continuously (see CartesianServo).
  kinematics::IkStatus ik = kinematics::IkStatus::Ok;
  bool holding = false;  ///< true when the command was refused and the last valid one is kept
};

/// Drives a ServoRobot in Cartesian space. Each `command` solves the IK with the continuity rule
/// of kinematics::ContinuousIk from the robot's current joint command (its set point: the last
/// valid Cartesian or joint command): the solution must lie on the IK branch of that command and
/// differ from it by at most max_velocity · dt on every joint (the robot model's own velocity
/// limits, rad/s or m/s; dt the period over which the command is to be reached, s). A command
/// that fails either way, or that the IK cannot solve, is refused: the robot keeps its command
/// (nothing swings) and the status says why. Poses are of the solver's tool frame in its base
/// frame (m, rad). Holds references: both objects must outlive it. `command` and `pose` are
/// noexcept and allocate nothing (with the closed-form solvers).
class CartesianServo {
 public:
  /// @param period dt of `command(target)`, s, > 0 (the caller's control period)
  /// @throws std::invalid_argument when the solver and the robot differ in joint count, or the
  /// period is not > 0.
  CartesianServo(kinematics::KinematicsSolver& solver, ServoRobot& robot, double period = 1e-3);

  /// Commands `target` to be reached within `dt` (s).
  CartesianCommandStatus command(const KDL::Frame& target, double dt) noexcept;
  /// Commands `target` to be reached within period() s.
  CartesianCommandStatus command(const KDL::Frame& target) noexcept { return command(target, continuity_.period()); }
  /// Forward kinematics of the robot's true position; false when the solver fails.
  bool pose(KDL::Frame& out) noexcept;
  /// Why the last Discontinuous command was refused (joint, step, allowed step, branch change).
  const kinematics::ContinuityRefusal& lastRefusal() const noexcept { return continuity_.lastRefusal(); }

 private:
  kinematics::KinematicsSolver& solver_;
  ServoRobot& robot_;
  kinematics::ContinuousIk continuity_;
  KDL::JntArray solution_;
};

}  // namespace cobra::sim
