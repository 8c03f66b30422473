#pragma once
/// @file
/// Multi-point one-axis trajectories of the thesis' TGL (§3.2.3): `MultiPointTrajectory`, the base
/// of trajectories through a whole path; `MultiPointLinearTrajBlends`, linear segments joined by
/// polynomial blends of order 2 to 5 (eq. 3.7-3.13; Biagiotti & Melchiorri, the thesis' [28]); and
/// `MultiPointInterpolation`, one polynomial per segment passing through every waypoint.

#include <span>
#include <vector>

#include "cobra/trajectory/trajectory.hpp"

namespace cobra::trajectory {

/// A trajectory through waypoints q_0..q_N reached at the waypoint times t_0 = 0 < t_1 < ... < t_N;
/// the velocities at the intermediate waypoints are not given but derived by the subclass.
class MultiPointTrajectory : public Trajectory {
 public:
  /// Number of waypoints N + 1 (>= 2).
  std::size_t waypointCount() const noexcept { return waypoint_times_.size(); }
  /// t_k in s, from 0 to duration().
  std::span<const double> waypointTimes() const noexcept { return waypoint_times_; }

 protected:
  MultiPointTrajectory(std::vector<Segment> segments, std::vector<double> waypoint_times);

 private:
  std::vector<double> waypoint_times_;
};

/// Linear segments joined by polynomial blends lasting the acceleration time T_a (thesis eq. 3.13
/// for one segment, generalised to N segments and blend orders 2..5):
///  - segment k runs from waypoint k to k + 1 in `segment_durations[k]` s; its linear part is the line
///    through (t_k, q_k) and (t_k+1, q_k+1) for an inner segment; the first (last) segment's line is
///    shifted so that the trajectory starts (ends) exactly at q_0 (q_N) at rest after (before) a blend
///    of T_a: v_0 = (q_1 - q_0) / (T_0 - T_a / 2), v_N-1 = (q_N - q_N-1) / (T_N-1 - T_a / 2), and
///    with one segment v = (q_1 - q_0) / (T - T_a) as in eq. 3.10;
///  - an inner waypoint's blend is centred on t_k, so q_k itself is passed near, not through (the
///    thesis' Fig. 3.5); only q_0 and q_N are met exactly;
///  - each blend is the Polynomial of `blend_order` from the incoming line's state to the outgoing
///    one's, with zero acceleration and jerk at both ends. Guaranteed continuity: position and
///    velocity for orders 2 and 3 (the blends of both are the parabola of eq. 3.7-3.8), position,
///    velocity and acceleration for orders 4 and 5 (both give the quartic whose velocity is a cubic
///    smoothstep). The velocity in a blend stays between its two line velocities.
/// Positions are in the axis' unit, durations in s. Throws std::invalid_argument when there are
/// fewer than 2 waypoints, the durations do not match the segments, a value is not finite, a
/// duration or T_a is not > 0, the order is outside 2..5, or two blends would overlap (an inner
/// segment shorter than T_a, a first or last one shorter than 1.5 T_a, a single one shorter than
/// 2 T_a).
class MultiPointLinearTrajBlends : public MultiPointTrajectory {
 public:
  static constexpr int kMinBlendOrder = 2;
  static constexpr int kMaxBlendOrder = 5;

  MultiPointLinearTrajBlends(std::span<const double> waypoints, std::span<const double> segment_durations,
                             double acceleration_time, int blend_order = 5);

  /// T_a in s.
  double accelerationTime() const noexcept { return acceleration_time_; }
  int blendOrder() const noexcept { return blend_order_; }
  /// The velocities of the linear parts, one per segment (axis unit / s).
  std::span<const double> segmentVelocities() const noexcept { return segment_velocities_; }

  /// The shortest duration segment `index` of `segment_count` can have without overlapping blends.
  static double minimumSegmentDuration(std::size_t index, std::size_t segment_count, double acceleration_time) noexcept;
  /// The segment's line covers q_k+1 - q_k in its duration minus this (s): T_a / 2 for a first or a
  /// last segment, T_a for a single one, 0 for an inner one; so v_k = (q_k+1 - q_k) / (T_k - this).
  static double lineShortening(std::size_t index, std::size_t segment_count, double acceleration_time) noexcept;

 private:
  struct Build;  // what the constructor computes before the base classes can be initialised
  static Build build(std::span<const double> waypoints, std::span<const double> segment_durations,
                     double acceleration_time, int blend_order);
  explicit MultiPointLinearTrajBlends(Build&& build);

  double acceleration_time_;
  int blend_order_;
  std::vector<double> segment_velocities_;
};

/// One polynomial of odd `order` 3, 5 or 7 per segment, passing exactly through every waypoint q_k
/// at t_k. The velocities at the inner waypoints are chosen by the heuristic of Biagiotti &
/// Melchiorri (§4.4): with d_k = (q_k - q_k-1) / T_k-1, v_k = (d_k + d_k+1) / 2 when both slopes
/// have the same sign, else 0 (the path turns back there, or stops); orders 5
/// and 7 also set the accelerations, a_k = (v_k+1 - v_k-1) / (T_k-1 + T_k); jerks are zero. The ends
/// are at rest. Continuity: velocity for order 3, acceleration for 5, jerk for 7. Positions in the
/// axis' unit, durations in s. Throws std::invalid_argument as MultiPointLinearTrajBlends does, and
/// for an order other than 3, 5 or 7.
class MultiPointInterpolation : public MultiPointTrajectory {
 public:
  MultiPointInterpolation(std::span<const double> waypoints, std::span<const double> segment_durations,
                          int order = 5);

  int order() const noexcept { return order_; }
  /// The velocity chosen at each waypoint (axis unit / s), zero at both ends.
  std::span<const double> waypointVelocities() const noexcept { return velocities_; }

 private:
  struct Build;  // what the constructor computes before the base classes can be initialised
  static Build build(std::span<const double> waypoints, std::span<const double> segment_durations, int order);
  explicit MultiPointInterpolation(Build&& build);

  int order_;
  std::vector<double> velocities_;
};

}  // namespace cobra::trajectory
