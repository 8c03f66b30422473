#pragma once
/// @file
/// What the state validator needs from a robot's kinematics (thesis Algorithms 4.2 and 5.1): given
/// the pose(s) of its tool(s), say whether they are reachable and, if so, where every link is.
/// The kinematics library implements it for the I-SUR robot and the UR5; tests use stand-ins.

#include <cstddef>
#include <span>
#include <vector>

#include <kdl/frames.hpp>

namespace cobra::planning {

/// Outcome of a robot's inverse kinematics for one state.
enum class Reachability {
  Reachable,
  Unreachable,  ///< no inverse kinematics solution within the joint limits
  OtherBranch,  ///< inverseNear(): solutions exist, but only on another IK branch than the seed's
};

/// Inverse then forward kinematics of one robot, as one call.
///
/// A robot serves one tool (the I-SUR with its needle, the UR5 with its probe: Algorithm 4.2) or
/// both tools of q ∈ SE(3)×SE(3) with a single solver (the two-armed I-SUR: Algorithm 5.1).
/// Not thread-safe by contract: a solver may warm-start from its previous solution.
class RobotModel {
 public:
  virtual ~RobotModel() = default;

  /// How many tool poses solve() takes (1 or 2).
  virtual std::size_t toolCount() const = 0;
  /// How many link frames solve() writes.
  virtual std::size_t linkCount() const = 0;

  /// @param tools_in_base  toolCount() tool poses, each in the robot's base frame [m, rad].
  /// @param links_in_base  linkCount() frames to fill with each link's pose in the base frame when
  ///                       the tools are reachable; unspecified otherwise.
  /// Must not throw; should not allocate: it runs for every sampled state and edge step of the
  /// planner (thousands per second).
  virtual Reachability solve(std::span<const KDL::Frame> tools_in_base, std::span<KDL::Frame> links_in_base) = 0;

  /// Forgets the warm-start state (the previous solution) of a solver that has one, so that the
  /// next solve() answers as after construction: the planner calls it before each query and before
  /// verifying a path, which makes a query's result independent of the queries before it.
  virtual void resetWarmStart() {}

  // ---- Joint space (what the motion planner searches; jointCount() == 0: the model offers none
  // and the planner searches SE(3)×SE(3) through solve() instead). Units: m (prismatic), rad.

  /// Number of joints (0: no joint-space support).
  virtual std::size_t jointCount() const { return 0; }
  /// Position limits and velocity limits [m/s, rad/s] of every joint (jointCount() each).
  virtual void jointLimits(std::span<double> lower, std::span<double> upper, std::span<double> max_velocity) const {
    (void)lower, (void)upper, (void)max_velocity;
  }
  /// Forward kinematics: every link frame for joints `q` (base frame); the tool frames are
  /// links_in_base[toolLink(t)]. False when q has no forward kinematics (outside the limits, a
  /// delta that cannot close). Must not throw or allocate.
  virtual bool linkFramesAt(std::span<const double> q, std::span<KDL::Frame> links_in_base) {
    (void)q, (void)links_in_base;
    return false;
  }
  /// Index in the link frames of tool `tool` (< toolCount()).
  virtual std::size_t toolLink(std::size_t tool) const { return tool; }
  /// The continuity-keeping inverse kinematics: the solution for `tools_in_base` on the IK branch of
  /// `seed` nearest to it (the rule the control path's IK follows: warm-started, branch kept).
  /// OtherBranch when only another branch reaches the tools. Must not throw or allocate.
  virtual Reachability inverseNear(std::span<const KDL::Frame> tools_in_base, std::span<const double> seed,
                                   std::span<double> q) {
    (void)tools_in_base, (void)seed, (void)q;
    return Reachability::Unreachable;
  }

  /// The goal IK of a query from joints `start`: by default inverseNear(); a redundant robot may
  /// prefer a solution its control path's IK reaches without leaving the start's redundancy rule.
  virtual Reachability inverseGoal(std::span<const KDL::Frame> tools_in_base, std::span<const double> start,
                                   std::span<double> q) {
    return inverseNear(tools_in_base, start, q);
  }
  /// A second goal the control path's IK reaches from `start`, for a planner to take when
  /// inverseGoal's cannot be taken (its state not valid, or the straight motion that follows the
  /// goal cannot be made from it): Reachable with its joints in `q`, or Unreachable when the model
  /// has none (the default). Must not throw or allocate.
  virtual Reachability inverseGoalAlternative(std::span<const KDL::Frame> tools_in_base, std::span<const double> start,
                                              std::span<double> q) {
    (void)tools_in_base, (void)start, (void)q;
    return Reachability::Unreachable;
  }
  /// Where the straight joint-space segment a → b crosses a singular set of the robot's Cartesian
  /// control (the I-SUR: the needle vertical, its wrist's gimbal lock, where a Cartesian path that
  /// misses the singular pose by any distance turns the yaw half a turn): two configurations
  /// `before` and `after` on either side of the crossing whose Cartesian path passes exactly
  /// through the singular pose. False when the segment does not cross one. No allocation.
  virtual bool singularCrossing(std::span<const double> a, std::span<const double> b, std::span<double> before,
                                std::span<double> after) const {
    (void)a, (void)b, (void)before, (void)after;
    return false;
  }
  /// Whether joints `q` may be a state of a path from joints `start` to joints `goal` (both on one
  /// IK branch: the goal IK keeps the start's): on that branch of the control path's IK, which never
  /// changes branch, and far enough from the singular sets that bound it that a Cartesian path
  /// through `q` needs no joint speed beyond the limits (each model documents its margins; closer
  /// than the start or the goal themselves is allowed up to half their distance). The planner's
  /// search keeps every state on it. Default: no branches (true). No allocation.
  virtual bool keepsBranch(std::span<const double> q, std::span<const double> start,
                           std::span<const double> goal) const {
    (void)q, (void)start, (void)goal;
    return true;
  }
  /// The configured warm-start seed (jointCount() values): the joints a start given as tool poses
  /// is solved from.
  virtual void seedJoints(std::span<double> q) const { (void)q; }

  /// Planning coordinates: what the planner varies. By default the joints themselves; a redundant
  /// robot whose IK resolves its redundancy by a fixed rule around the start (the I-SUR's yaw and
  /// pitch shares) gives fewer coordinates, so that every planned configuration is the one its
  /// control path's IK reaches from the start.
  virtual std::size_t coordinateCount() const { return jointCount(); }
  /// Scale of each coordinate: its velocity limit [m/s, rad/s] (the planner measures distances in
  /// s at full speed, so that metres of a slider and radians of a wrist compare).
  virtual void coordinateScales(std::span<double> scale) const {
    std::vector<double> lower(jointCount()), upper(jointCount());
    jointLimits(lower, upper, scale);
  }
  /// Bounds of the coordinates for a query from joints `start` to joints `goal`.
  virtual void coordinateBounds(std::span<const double> start, std::span<const double> goal, std::span<double> lower,
                                std::span<double> upper) const {
    std::vector<double> velocity(jointCount());
    jointLimits(lower, upper, velocity);
    (void)start, (void)goal;
  }
  /// Joints of coordinates `c` for a query starting at `start` (no allocation).
  virtual void jointsOf(std::span<const double> c, std::span<const double> start, std::span<double> q) const {
    (void)start;
    for (std::size_t i = 0; i < q.size(); ++i) q[i] = c[i];
  }
  /// Coordinates of joints `q` (no allocation).
  virtual void coordinatesOf(std::span<const double> q, std::span<double> c) const {
    for (std::size_t i = 0; i < c.size(); ++i) c[i] = q[i];
  }
};

}  // namespace cobra::planning
