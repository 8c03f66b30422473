#include "cobra/trajectory/multi_point.hpp"

#include <cmath>
#include <utility>

#include "checks.hpp"

namespace cobra::trajectory {

namespace {

/// Checks what every multi-point trajectory needs (>= 2 finite waypoints, one finite duration > 0
/// per segment) and returns the waypoint times t_0 = 0 .. t_N. `who` prefixes the messages.
std::vector<double> checkedWaypointTimes(const char* who, std::span<const double> waypoints,
                                         std::span<const double> segment_durations) {
  if (waypoints.size() < 2) detail::fail(who, "the path has ", waypoints.size(), " waypoint(s), expected at least 2");
  const std::size_t n = waypoints.size() - 1;
  if (segment_durations.size() != n)
    detail::fail(who, waypoints.size(), " waypoints need ", n, " segment durations, got ", segment_durations.size());
  for (std::size_t k = 0; k <= n; ++k) detail::requireFinite(waypoints[k], who, "waypoint ", k);
  std::vector<double> times(n + 1, 0.0);
  for (std::size_t k = 0; k < n; ++k) {
    detail::requirePositive(segment_durations[k], "s", who, "duration of segment ", k);
    times[k + 1] = times[k] + segment_durations[k];
  }
  return times;
}

}  // namespace

MultiPointTrajectory::MultiPointTrajectory(std::vector<Segment> segments, std::vector<double> waypoint_times)
    : Trajectory(std::move(segments)), waypoint_times_(std::move(waypoint_times)) {}

struct MultiPointLinearTrajBlends::Build {
  std::vector<Segment> segments;
  std::vector<double> waypoint_times;
  std::vector<double> velocities;
  double acceleration_time;
  int blend_order;
};

double MultiPointLinearTrajBlends::minimumSegmentDuration(std::size_t index, std::size_t segment_count,
                                                          double acceleration_time) noexcept {
  const double half = acceleration_time / 2.0;
  return (index == 0 ? acceleration_time : half) + (index + 1 == segment_count ? acceleration_time : half);
}

double MultiPointLinearTrajBlends::lineShortening(std::size_t index, std::size_t segment_count,
                                                  double acceleration_time) noexcept {
  const double half = acceleration_time / 2.0;
  return (index == 0 ? half : 0.0) + (index + 1 == segment_count ? half : 0.0);
}

MultiPointLinearTrajBlends::Build MultiPointLinearTrajBlends::build(std::span<const double> waypoints,
                                                                    std::span<const double> segment_durations,
                                                                    double acceleration_time, int blend_order) {
  constexpr const char* kWho = "MultiPointLinearTrajBlends: ";
  std::vector<double> times = checkedWaypointTimes(kWho, waypoints, segment_durations);
  const std::size_t n = waypoints.size() - 1;  // segments
  if (blend_order < kMinBlendOrder || blend_order > kMaxBlendOrder)
    detail::fail(kWho, "blend order ", blend_order, " is out of range, expected ", kMinBlendOrder, " to ",
                 kMaxBlendOrder);
  detail::requirePositive(acceleration_time, "s", kWho, "acceleration time");
  for (std::size_t k = 0; k < n; ++k) {
    const double needed = minimumSegmentDuration(k, n, acceleration_time);
    // A relative tolerance so that durations computed as exactly this minimum are accepted.
    if (segment_durations[k] < needed * (1.0 - 1e-12))
      detail::fail(kWho, "segment ", k, " lasts ", segment_durations[k], " s but its blends take ", needed,
                   " s (acceleration time ", acceleration_time, " s); lengthen the segment to at least ", needed,
                   " s or shorten the acceleration time");
  }

  Build b{{}, std::move(times), std::vector<double>(n, 0.0), acceleration_time, blend_order};
  // Line k: q(t) = anchor_k + v_k (t - t_k). An inner line passes through (t_k, q_k); the first is
  // shifted back by v_0 T_a / 2 so that the initial blend from rest ends on it (eq. 3.10).
  std::vector<double> anchors(n);
  for (std::size_t k = 0; k < n; ++k) {
    const double effective = segment_durations[k] - lineShortening(k, n, acceleration_time);
    b.velocities[k] = (waypoints[k + 1] - waypoints[k]) / effective;
    anchors[k] = waypoints[k] - (k == 0 ? b.velocities[k] * acceleration_time / 2.0 : 0.0);
  }
  const auto line = [&](std::size_t k, double t) { return anchors[k] + b.velocities[k] * (t - b.waypoint_times[k]); };

  // Blend k spans [start, start + T_a]: from rest at q_0 for k = 0, centred on t_k inside, to rest at
  // q_N for k = N. Between blends k and k + 1 lies line k, unless the segment is at its minimum.
  b.segments.reserve(2 * n + 1);
  const double half = acceleration_time / 2.0;
  for (std::size_t k = 0; k <= n; ++k) {
    const double t = b.waypoint_times[k];
    const double start = k == 0 ? 0.0 : (k == n ? t - acceleration_time : t - half);
    const double end = start + acceleration_time;
    const State from = k == 0 ? State{waypoints[0]} : State{line(k - 1, start), b.velocities[k - 1]};
    const State to = k == n ? State{waypoints[n]} : State{line(k, end), b.velocities[k]};
    b.segments.push_back(Segment{start, Polynomial(blend_order, Conditions(from, to), acceleration_time)});
    if (k == n) break;
    const double line_end = k + 1 == n ? b.waypoint_times[n] - acceleration_time : b.waypoint_times[k + 1] - half;
    const double line_duration = line_end - end;
    if (line_duration > 1e-12 * b.waypoint_times[n])
      b.segments.push_back(
          Segment{end, Polynomial(1, Conditions(line(k, end), line(k, line_end)), line_duration)});
  }
  return b;
}

MultiPointLinearTrajBlends::MultiPointLinearTrajBlends(std::span<const double> waypoints,
                                                       std::span<const double> segment_durations,
                                                       double acceleration_time, int blend_order)
    : MultiPointLinearTrajBlends(build(waypoints, segment_durations, acceleration_time, blend_order)) {}

MultiPointLinearTrajBlends::MultiPointLinearTrajBlends(Build&& b)
    : MultiPointTrajectory(std::move(b.segments), std::move(b.waypoint_times)),
      acceleration_time_(b.acceleration_time),
      blend_order_(b.blend_order),
      segment_velocities_(std::move(b.velocities)) {}

struct MultiPointInterpolation::Build {
  std::vector<Segment> segments;
  std::vector<double> waypoint_times;
  std::vector<double> velocities;
  int order;
};

MultiPointInterpolation::Build MultiPointInterpolation::build(std::span<const double> waypoints,
                                                              std::span<const double> segment_durations, int order) {
  constexpr const char* kWho = "MultiPointInterpolation: ";
  std::vector<double> times = checkedWaypointTimes(kWho, waypoints, segment_durations);
  if (order != 3 && order != 5 && order != 7)
    detail::fail(kWho, "order ", order,
                 " is not supported, expected 3, 5 or 7 (odd orders meet the same conditions at both ends of a segment)");
  const std::size_t n = waypoints.size() - 1;
  const auto slope = [&](std::size_t k) { return (waypoints[k] - waypoints[k - 1]) / segment_durations[k - 1]; };
  std::vector<double> velocities(n + 1, 0.0), accelerations(n + 1, 0.0);
  for (std::size_t k = 1; k < n; ++k) {
    const double in = slope(k), out = slope(k + 1);
    if ((in > 0.0 && out > 0.0) || (in < 0.0 && out < 0.0)) velocities[k] = (in + out) / 2.0;
  }
  if (order >= 5)
    for (std::size_t k = 1; k < n; ++k)
      accelerations[k] = (velocities[k + 1] - velocities[k - 1]) / (segment_durations[k - 1] + segment_durations[k]);
  Build b{{}, std::move(times), std::move(velocities), order};
  b.segments.reserve(n);
  for (std::size_t k = 0; k < n; ++k) {
    const Conditions c(State{waypoints[k], b.velocities[k], accelerations[k]},
                       State{waypoints[k + 1], b.velocities[k + 1], accelerations[k + 1]});
    b.segments.push_back(Segment{b.waypoint_times[k], Polynomial(order, c, segment_durations[k])});
  }
  return b;
}

MultiPointInterpolation::MultiPointInterpolation(std::span<const double> waypoints,
                                                 std::span<const double> segment_durations, int order)
    : MultiPointInterpolation(build(waypoints, segment_durations, order)) {}

MultiPointInterpolation::MultiPointInterpolation(Build&& b)
    : MultiPointTrajectory(std::move(b.segments), std::move(b.waypoint_times)),
      order_(b.order),
      velocities_(std::move(b.velocities)) {}

}  // namespace cobra::trajectory
