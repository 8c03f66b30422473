#pragma once
/// @file
/// Inverse kinematics for the control path: a Cartesian command becomes joints only when the
/// robot can get there continuously from where it is.
///
/// The rule (every place in cobra that turns a Cartesian command into joints applies it):
///  1. Branch: the solution is the one nearest to the current joints among the solutions on the
///     current configuration's IK branch (KinematicsSolver::branch: UR5/Puma shoulder, elbow and
///     wrist; I-SUR pitch representation). A target that only another branch reaches is refused:
///     changing branch means passing through a singular configuration, where a Cartesian servo
///     swings the arm. On a singular boundary (within kBranchMargin) either side is allowed.
///  2. Speed: the solution must be reachable from the current joints within one period dt at
///     the joints' velocity limits: |q_i - current_i| <= max_velocity_i · dt for every joint i.
///     A Cartesian command that needs more (e.g. a pose across the I-SUR's wrist singularity, where
///     yaw and roll turn by π for a small tilt of the needle) is refused.
/// A refused command returns IkStatus::Discontinuous and leaves the output untouched: the caller
/// holds its last valid command (and tells its supervisor, e.g. the event `e_ik_discontinuity`).
/// The solver's own failures (Unreachable, JointLimits, ...) pass through unchanged.
///
/// "Current joints" is the joint command the robot is following (the servo's set point), or the
/// measured joints when no command stream is running: the caller decides and documents it.

#include <cstddef>
#include <string_view>
#include <vector>

#include <kdl/frames.hpp>
#include <kdl/jntarray.hpp>

#include "cobra/kinematics/kinematics_solver.hpp"

namespace cobra::kinematics {

/// Why the last `ContinuousIk::solve` returned Discontinuous.
struct ContinuityRefusal {
  bool branch_change = false;  ///< only another branch reaches the target
  int joint = -1;              ///< 0-based joint whose step is too large (-1: branch change)
  double step = 0.0;           ///< |q_joint - current_joint|, rad / m
  double allowed = 0.0;        ///< max_velocity_joint · dt, rad / m
};

/// Real-time continuity filter around a KinematicsSolver (Model/Data style: the limits are fixed
/// at construction, the workspace preallocated). Holds a reference: the solver must outlive it.
/// `solve` is noexcept and allocates nothing (when the solver's `inverseOnBranch` does not: the
/// closed-form solvers and the I-SUR's do not). Not thread-safe: one per thread, like the solver.
class ContinuousIk {
 public:
  /// @param max_velocity per joint, rad/s (revolute) or m/s (prismatic), finite and > 0
  /// @param period the default dt of `solve`, s, finite and > 0
  /// @throws std::invalid_argument naming the solver, the joint (1-based) and what was expected,
  /// e.g. "UR5: max_velocity of joint 3 is 0 rad/s: give a finite value > 0".
  ContinuousIk(KinematicsSolver& solver, std::vector<double> max_velocity, double period);

  /// The rule above with dt = period(). `current` and `q_out` have jointCount() values (rad / m);
  /// BadInput when a size is wrong or a value not finite. `q_out` is untouched unless Ok.
  IkStatus solve(const KDL::Frame& target, const KDL::JntArray& current, KDL::JntArray& q_out) noexcept;
  /// The rule above with this dt (s); BadInput when dt is not finite and > 0.
  IkStatus solve(const KDL::Frame& target, const KDL::JntArray& current, double dt, KDL::JntArray& q_out) noexcept;

  /// Why the last solve returned Discontinuous (unchanged by other outcomes).
  const ContinuityRefusal& lastRefusal() const noexcept { return refusal_; }
  KinematicsSolver& solver() const noexcept { return solver_; }
  const std::vector<double>& maxVelocity() const noexcept { return max_velocity_; }
  double period() const noexcept { return period_; }

 private:
  KinematicsSolver& solver_;
  std::vector<double> max_velocity_;
  double period_;
  KDL::JntArray candidate_;  // preallocated: solve allocates nothing
  ContinuityRefusal refusal_;
};

/// Rule 2 of the file comment on a candidate solution: Ok when |candidate_i - current_i| <=
/// max_velocity_i · dt on every joint (rad / m; dt in s); otherwise Discontinuous, with `refusal`
/// naming the joint that exceeds its step by the largest factor. The sizes must agree (the callers
/// check them). No allocation.
IkStatus checkJointSteps(const KDL::JntArray& candidate, const KDL::JntArray& current,
                         const std::vector<double>& max_velocity, double dt, ContinuityRefusal& refusal) noexcept;

/// Checks `max_velocity` (one finite value > 0 per joint of `limits`, rad/s or m/s) for `robot`.
/// @throws std::invalid_argument as ContinuousIk's constructor.
void validateMaxVelocity(std::string_view robot, const JointLimits& limits, const std::vector<double>& max_velocity);

}  // namespace cobra::kinematics
