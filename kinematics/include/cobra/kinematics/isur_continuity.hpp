#pragma once
/// @file
/// The continuity rule of continuity.hpp (kinematics::ContinuousIk) for the two-armed I-SUR
/// (thesis §5.4.1): both tool commands become joints only when the robot can get there
/// continuously from where it is.

#include <vector>

#include <kdl/frames.hpp>
#include <kdl/jntarray.hpp>

#include "cobra/kinematics/continuity.hpp"
#include "cobra/kinematics/isur.hpp"

namespace cobra::kinematics {

/// ContinuousIk's rule on each sub-structure of the split IK: the macro + Endo Stitch arm on the
/// branch (wrist representation) of the current joints, then the 6-DOF arm, from the platform
/// pose that gives, on its current shoulder / elbow / wrist branch (IsurSuturingSolver::
/// inverseOnBranch); then every one of the 14 joints within max_velocity · dt of the current
/// joints. A refused command returns Discontinuous (lastRefusal() says why: a branch change, or
/// the joint, 0-based in the solver's order, whose step is too large) and leaves the output
/// untouched; the solver's own failures (Unreachable, JointLimits, ...) pass through.
/// Holds a reference: the solver must outlive it. `solve` is noexcept and allocates nothing.
/// Not thread-safe: one per thread, like the solver.
class ContinuousIsurSuturingIk {
 public:
  /// @param max_velocity 14 values, rad/s (m/s for the sliders q1..q3), finite and > 0
  /// @param period the default dt of `solve`, s, finite and > 0
  /// @throws std::invalid_argument as ContinuousIk ("I-SUR suturing: max_velocity of joint 9 is 0
  /// rad/s: give a finite value > 0").
  ContinuousIsurSuturingIk(IsurSuturingSolver& solver, std::vector<double> max_velocity, double period);

  /// The rule with dt = period(). `current` and `q_out` have 14 values (m / rad); BadInput when a
  /// size is wrong or a value not finite. `q_out` is untouched unless Ok.
  IkStatus solve(const KDL::Frame& stitch_target, const KDL::Frame& gripper_target, const KDL::JntArray& current,
                 KDL::JntArray& q_out) noexcept;
  /// The rule with this dt (s); BadInput when dt is not finite and > 0.
  IkStatus solve(const KDL::Frame& stitch_target, const KDL::Frame& gripper_target, const KDL::JntArray& current,
                 double dt, KDL::JntArray& q_out) noexcept;

  /// Why the last solve returned Discontinuous (unchanged by other outcomes).
  const ContinuityRefusal& lastRefusal() const noexcept { return refusal_; }
  IsurSuturingSolver& solver() const noexcept { return solver_; }
  const std::vector<double>& maxVelocity() const noexcept { return max_velocity_; }
  double period() const noexcept { return period_; }

 private:
  IsurSuturingSolver& solver_;
  std::vector<double> max_velocity_;
  double period_;
  KDL::JntArray candidate_;  // preallocated: solve allocates nothing
  ContinuityRefusal refusal_;
};

}  // namespace cobra::kinematics
