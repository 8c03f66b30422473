#pragma once
/// @file
/// The interface every kinematics solver implements, so that a component can switch between the
/// KDL (iterative) and the closed-form solver of a robot by a property (thesis §6.2.4).

#include <span>
#include <string_view>

#include <kdl/frames.hpp>
#include <kdl/jntarray.hpp>

#include "cobra/kinematics/types.hpp"

namespace cobra::kinematics {

/// Forward and inverse position kinematics of one robot. A solver owns an immutable model and a
/// workspace preallocated at construction; `forward` and `inverse` are noexcept, return a status
/// and (for the closed-form solvers) allocate nothing. Not thread-safe: one solver per thread.
/// Poses are of the tool frame in the robot's base frame, in m and rad.
class KinematicsSolver {
 public:
  virtual ~KinematicsSolver() = default;

  /// Name of the robot model, as used in error messages ("UR5", "Puma 260", ...).
  virtual std::string_view name() const noexcept = 0;
  virtual unsigned jointCount() const noexcept = 0;
  /// Joint limits (rad / m), one per joint.
  virtual const JointLimits& limits() const noexcept = 0;

  /// Pose of the tool for joint values `q` (size jointCount()). `pose` is untouched unless Ok;
  /// BadInput when the size is wrong or a value is not finite.
  virtual IkStatus forward(const KDL::JntArray& q, KDL::Frame& pose) noexcept = 0;

  /// Joint values that put the tool at `target`, within the limits, nearest to `seed` (analytic
  /// solvers) or found starting from `seed` (iterative solvers). `q_out` (size jointCount()) is
  /// untouched unless the status is Ok.
  virtual IkStatus inverse(const KDL::Frame& target, const KDL::JntArray& seed, KDL::JntArray& q_out) noexcept = 0;

  /// The branch configuration `q` (jointCount() values, rad / m) lies on (see IkBranch; each solver
  /// documents its choices). Default: a solver that does not tell branches apart (IkBranch{}:
  /// compatible with every branch). An empty IkBranch for a wrong-size `q`. No allocation.
  virtual IkBranch branch(std::span<const double> q) const noexcept;

  /// As `inverse`, among the solutions on a branch compatible with `branch` only (for a solver
  /// with branches: the solution nearest to `seed` on that branch); Discontinuous when solutions
  /// exist within the limits but none on that branch. Default: `inverse` (no branches).
  virtual IkStatus inverseOnBranch(const KDL::Frame& target, const KDL::JntArray& seed, IkBranch branch,
                                   KDL::JntArray& q_out) noexcept;

 protected:
  KinematicsSolver() = default;
  KinematicsSolver(const KinematicsSolver&) = default;
  KinematicsSolver& operator=(const KinematicsSolver&) = default;
};

/// A solver with a closed-form inverse: every solution at once, and `inverse` = the one nearest
/// to the seed within the limits (see `selectNearest`).
class AnalyticSolver : public KinematicsSolver {
 public:
  /// Every solution for `target`, each joint wrapped into (-π, π] (rad) before the limits are
  /// considered: `solutions` ignores the joint limits, `inverse` applies them. `seed` only fixes
  /// the joint left free at a singular configuration (e.g. the wrist when two axes align), so
  /// that the answer is continuous along a path through the singularity. Unreachable (and an
  /// empty set) when no solution exists. No allocation.
  virtual IkStatus allInverse(const KDL::Frame& target, const KDL::JntArray& seed,
                              IkSolutionSet& solutions) noexcept = 0;

  /// allInverse, then selectNearest. No allocation.
  IkStatus inverse(const KDL::Frame& target, const KDL::JntArray& seed, KDL::JntArray& q_out) noexcept override;
  /// allInverse, then selectNearest among the solutions on `branch` (allInverse labels each
  /// solution with its branch). No allocation.
  IkStatus inverseOnBranch(const KDL::Frame& target, const KDL::JntArray& seed, IkBranch branch,
                           KDL::JntArray& q_out) noexcept override;

 protected:
  AnalyticSolver() = default;

 private:
  IkSolutionSet scratch_;
};

/// Which implementation of a robot's kinematics a component runs (thesis §6.2.4: the KDL and the
/// closed-form Kinematics Solver components are interchangeable).
enum class SolverKind {
  ClosedForm,             ///< the robot's analytic solver
  KdlNewtonRaphson,       ///< SerialChainSolver, KDL's ChainIkSolverPos_NR_JL, same DH chain
  KdlLevenbergMarquardt,  ///< SerialChainSolver, KDL's ChainIkSolverPos_LMA, same DH chain
};

/// "closed_form", "kdl_nr" or "kdl_lma" (property values).
/// @throws std::invalid_argument listing the accepted names for anything else.
SolverKind parseSolverKind(std::string_view text);

/// True when every value of `q` is finite and there are `joints` of them.
bool validJointArray(const KDL::JntArray& q, unsigned joints) noexcept;
/// True when the frame's translation and rotation are finite and the rotation is orthonormal
/// within 1e-6 (KDL does not check what it is given).
bool validFrame(const KDL::Frame& frame) noexcept;

}  // namespace cobra::kinematics
