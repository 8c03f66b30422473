#pragma once
/// @file
/// What the state validator needs from a robot's kinematics (thesis Algorithms 4.2 and 5.1): given
/// the pose(s) of its tool(s), say whether they are reachable and, if so, where every link is.
/// The kinematics library implements it for the I-SUR robot and the UR5; tests use stand-ins.

#include <cstddef>
#include <span>

#include <kdl/frames.hpp>

namespace cobra::planning {

/// Outcome of a robot's inverse kinematics for one state.
enum class Reachability { Reachable, Unreachable };

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
};

}  // namespace cobra::planning
