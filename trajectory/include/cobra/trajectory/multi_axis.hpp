#pragma once
/// @file
/// Multi-axis trajectories of the thesis' TGL (§3.2.3): `MultiAxisConditions`, `MultiAxisPath` and
/// `MultiAxisTrajectory`, which synchronises all axes at every waypoint by giving each segment the
/// duration its slowest axis needs and scaling the other axes' velocities down to it. Each axis is
/// unit-agnostic (m, rad, ...); its limits are in that unit per s.

#include <cstddef>
#include <span>
#include <utility>
#include <vector>

#include "cobra/trajectory/conditions.hpp"
#include "cobra/trajectory/multi_point.hpp"
#include "cobra/trajectory/trajectory.hpp"

namespace cobra::trajectory {

/// Boundary conditions for several axes at once, one `Conditions` per axis (thesis: "similar to the
/// Conditions class, it allows to specify constraints for multiple axes").
class MultiAxisConditions {
 public:
  MultiAxisConditions() = default;
  explicit MultiAxisConditions(std::vector<Conditions> axes) : axes_(std::move(axes)) {}
  /// Rest to rest from `initial` to `final` positions; throws std::invalid_argument when their sizes
  /// differ or a value is not finite.
  MultiAxisConditions(std::span<const double> initial, std::span<const double> final);

  std::size_t axisCount() const noexcept { return axes_.size(); }
  const Conditions& axis(std::size_t i) const { return axes_.at(i); }
  std::span<const Conditions> axes() const noexcept { return axes_; }

 private:
  std::vector<Conditions> axes_;
};

/// A multi-point path for several axes: waypoint k holds one position per axis. Plain data, as the
/// motion planner writes it on its `plannedPath` port (thesis §4.5.1-4.5.2); it is not checked
/// here but by MultiAxisTrajectory, which names the offending waypoint.
class MultiAxisPath {
 public:
  MultiAxisPath() = default;
  explicit MultiAxisPath(std::vector<std::vector<double>> waypoints) : waypoints_(std::move(waypoints)) {}

  void addWaypoint(std::vector<double> positions) { waypoints_.push_back(std::move(positions)); }
  std::size_t size() const noexcept { return waypoints_.size(); }
  bool empty() const noexcept { return waypoints_.empty(); }
  /// Axes of the first waypoint (0 for an empty path).
  std::size_t axisCount() const noexcept { return waypoints_.empty() ? 0 : waypoints_.front().size(); }
  const std::vector<double>& waypoint(std::size_t k) const { return waypoints_.at(k); }
  /// Waypoint k, writable: lets a writer refill a path of fixed shape without allocating.
  std::vector<double>& waypoint(std::size_t k) { return waypoints_.at(k); }
  const std::vector<std::vector<double>>& waypoints() const noexcept { return waypoints_; }

  friend bool operator==(const MultiAxisPath&, const MultiAxisPath&) = default;

 private:
  std::vector<std::vector<double>> waypoints_;
};

/// Per-axis limits of a synchronised path. Sizes must equal the path's axis count.
struct AxisLimits {
  /// Maximum velocity of each axis (axis unit / s, > 0): no axis ever exceeds it.
  std::vector<double> max_velocity;
  /// Acceleration time T_a of each axis (s, > 0): the duration of each of its blends.
  std::vector<double> acceleration_time;
};

/// Trajectories for several axes sharing one time line. Model/Data split: immutable after
/// construction; `evaluate` writes one `State` per axis into caller-owned storage, never allocates
/// or throws, and costs O(axes * log segments). Outside [0, duration()] every axis clamps as
/// Trajectory does (held at its start or end position, at rest).
class MultiAxisTrajectory {
 public:
  /// The synchronised path (thesis §3.2.3): each axis is a MultiPointLinearTrajBlends of
  /// `blend_order` through its coordinates of `path`, and every axis shares the waypoint times. The
  /// duration of segment k is the largest over the axes of what that axis needs to move there at its
  /// max velocity, |dq| / v_max + MultiPointLinearTrajBlends::lineShortening, and at least
  /// MultiPointLinearTrajBlends::minimumSegmentDuration for its acceleration time, so the slowest
  /// axis sets the pace and the others are scaled down to it. A segment where nothing moves lasts
  /// that minimum. Throws std::invalid_argument (fewer than 2 waypoints, a waypoint whose axis count
  /// differs from waypoint 0's, limits of the wrong size, a non-finite value, a limit <= 0, a blend
  /// order outside 2..5) with a message naming the element.
  MultiAxisTrajectory(const MultiAxisPath& path, const AxisLimits& limits, int blend_order = 5);

  /// One PolynomialTrajectory of `order` 1..7 per axis over the same `duration` s.
  MultiAxisTrajectory(int order, const MultiAxisConditions& conditions, double duration = 1.0);

  /// The synchronised stop (thesis §4.5.2, askStopMove): every axis from its `current` state to rest
  /// in exactly `stop_time` s (see Polynomial::stop).
  static MultiAxisTrajectory stop(std::span<const State> current, double stop_time);

  std::size_t axisCount() const noexcept { return axes_.size(); }
  double duration() const noexcept { return duration_; }
  /// The shared waypoint times t_k (s): every axis starts at t_0 = 0 and ends at t_N = duration()
  /// exactly; at an inner t_k each axis is at the centre of its blend, where its incoming and outgoing
  /// lines meet at its waypoint. {0, duration()} for a polynomial or a stop.
  std::span<const double> waypointTimes() const noexcept { return waypoint_times_; }
  const Trajectory& axis(std::size_t i) const { return axes_.at(i); }

  /// The state of every axis at `t` s. Contract: `out.size() == axisCount()`; a shorter span gets
  /// its first out.size() axes, a longer one keeps its extra entries untouched. Real-time safe.
  void evaluate(double t, std::span<State> out) const noexcept;

 private:
  MultiAxisTrajectory() = default;
  static void checkPath(const MultiAxisPath& path, const AxisLimits& limits);
  static std::vector<double> synchronisedDurations(const MultiAxisPath& path, const AxisLimits& limits);

  std::vector<Trajectory> axes_;
  std::vector<double> waypoint_times_;
  double duration_ = 0.0;
};

}  // namespace cobra::trajectory
