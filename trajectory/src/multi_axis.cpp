#include "cobra/trajectory/multi_axis.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include "checks.hpp"

namespace cobra::trajectory {

namespace {

constexpr const char* kWho = "MultiAxisTrajectory: ";

void requireAxisCount(std::size_t got, std::size_t axes, const char* what) {
  if (got != axes) detail::fail(kWho, what, " has ", got, " values, expected ", axes, " (one per axis of the path)");
}

}  // namespace

MultiAxisConditions::MultiAxisConditions(std::span<const double> initial, std::span<const double> final) {
  if (initial.size() != final.size())
    detail::fail("MultiAxisConditions: ", initial.size(), " initial positions but ", final.size(),
                 " final ones, expected one of each per axis");
  axes_.reserve(initial.size());
  for (std::size_t i = 0; i < initial.size(); ++i) axes_.emplace_back(initial[i], final[i]);
}

void MultiAxisTrajectory::checkPath(const MultiAxisPath& path, const AxisLimits& limits) {
  if (path.size() < 2) detail::fail(kWho, "the path has ", path.size(), " waypoint(s), expected at least 2");
  const std::size_t axes = path.axisCount();
  if (axes == 0) detail::fail(kWho, "waypoint 0 has no axes, expected at least 1");
  for (std::size_t k = 1; k < path.size(); ++k)
    if (path.waypoint(k).size() != axes)
      detail::fail(kWho, "waypoint ", k, " has ", path.waypoint(k).size(), " axes, expected ", axes, " (as waypoint 0)");
  requireAxisCount(limits.max_velocity.size(), axes, "max_velocity");
  requireAxisCount(limits.acceleration_time.size(), axes, "acceleration_time");
  for (std::size_t i = 0; i < axes; ++i) {
    detail::requirePositive(limits.max_velocity[i], "(axis unit)/s", kWho, "max_velocity of axis ", i);
    detail::requirePositive(limits.acceleration_time[i], "s", kWho, "acceleration_time of axis ", i);
  }
  for (std::size_t k = 0; k < path.size(); ++k)
    for (std::size_t i = 0; i < axes; ++i)
      detail::requireFinite(path.waypoint(k)[i], kWho, "waypoint ", k, " axis ", i);
}

std::vector<double> MultiAxisTrajectory::synchronisedDurations(const MultiAxisPath& path, const AxisLimits& limits) {
  // The slowest axis of each segment sets its duration (thesis §3.2.3).
  const std::size_t segments = path.size() - 1;
  std::vector<double> durations(segments, 0.0);
  for (std::size_t k = 0; k < segments; ++k) {
    for (std::size_t i = 0; i < path.axisCount(); ++i) {
      const double ta = limits.acceleration_time[i];
      const double distance = std::abs(path.waypoint(k + 1)[i] - path.waypoint(k)[i]);
      const double at_max_velocity =
          distance / limits.max_velocity[i] + MultiPointLinearTrajBlends::lineShortening(k, segments, ta);
      durations[k] = std::max(
          {durations[k], at_max_velocity, MultiPointLinearTrajBlends::minimumSegmentDuration(k, segments, ta)});
    }
  }
  return durations;
}

MultiAxisTrajectory::MultiAxisTrajectory(const MultiAxisPath& path, const AxisLimits& limits, int blend_order) {
  checkPath(path, limits);
  const std::vector<double> durations = synchronisedDurations(path, limits);
  axes_.reserve(path.axisCount());
  std::vector<double> coordinates(path.size());
  for (std::size_t i = 0; i < path.axisCount(); ++i) {
    for (std::size_t k = 0; k < path.size(); ++k) coordinates[k] = path.waypoint(k)[i];
    MultiPointLinearTrajBlends axis(coordinates, durations, limits.acceleration_time[i], blend_order);
    if (waypoint_times_.empty()) waypoint_times_.assign(axis.waypointTimes().begin(), axis.waypointTimes().end());
    axes_.push_back(std::move(axis));
  }
  duration_ = waypoint_times_.back();
}

MultiAxisTrajectory::MultiAxisTrajectory(int order, const MultiAxisConditions& conditions, double duration) {
  if (conditions.axisCount() == 0) detail::fail(kWho, "the conditions have no axes, expected at least 1");
  axes_.reserve(conditions.axisCount());
  for (const Conditions& c : conditions.axes()) axes_.push_back(PolynomialTrajectory(order, c, duration));
  waypoint_times_ = {0.0, duration};
  duration_ = duration;
}

MultiAxisTrajectory MultiAxisTrajectory::stop(std::span<const State> current, double stop_time) {
  if (current.empty()) detail::fail(kWho, "stop from a state with no axes, expected at least 1");
  MultiAxisTrajectory result;
  result.axes_.reserve(current.size());
  for (const State& s : current) result.axes_.push_back(stopTrajectory(s, stop_time));
  result.waypoint_times_ = {0.0, stop_time};
  result.duration_ = stop_time;
  return result;
}

void MultiAxisTrajectory::evaluate(double t, std::span<State> out) const noexcept {
  const std::size_t n = std::min(out.size(), axes_.size());
  for (std::size_t i = 0; i < n; ++i) axes_[i].evaluate(t, out[i]);
}

}  // namespace cobra::trajectory
