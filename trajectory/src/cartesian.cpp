#include "cobra/trajectory/cartesian.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include "checks.hpp"
#include "so3.hpp"

namespace cobra::trajectory {

namespace {

constexpr const char* kWho = "CartesianTrajectory: ";
constexpr std::size_t kAxesPerArm = 4;  // x, y, z, cumulative angle s

void requireFiniteFrame(const KDL::Frame& f, std::size_t k, std::size_t arm) {
  for (int i = 0; i < 3; ++i)
    if (!std::isfinite(f.p(i)))
      detail::fail(kWho, "waypoint ", k, " arm ", arm, " has a position that is not finite, expected metres");
  double error = 0.0;  // max |R^T R - I|
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      double dot = 0.0;
      for (int m = 0; m < 3; ++m) dot += f.M(m, i) * f.M(m, j);
      error = std::max(error, std::abs(dot - (i == j ? 1.0 : 0.0)));
    }
  if (!(error < 1e-6) || f.M(0, 0) * (f.M(1, 1) * f.M(2, 2) - f.M(1, 2) * f.M(2, 1)) -
                                 f.M(0, 1) * (f.M(1, 0) * f.M(2, 2) - f.M(1, 2) * f.M(2, 0)) +
                                 f.M(0, 2) * (f.M(1, 0) * f.M(2, 1) - f.M(1, 1) * f.M(2, 0)) <
                             0.0)
    detail::fail(kWho, "waypoint ", k, " arm ", arm, " has a rotation that is not a proper orthonormal matrix (|R^T R - I| = ",
                 error, "), expected a rotation; build it with KDL::Rotation::RPY, Rot or Quaternion");
}

void requireLimits(const CartesianLimits& limits, int blend_order) {
  detail::requirePositive(limits.max_linear_velocity, "m/s", kWho, "max_linear_velocity");
  detail::requirePositive(limits.max_angular_velocity, "rad/s", kWho, "max_angular_velocity");
  detail::requirePositive(limits.linear_acceleration_time, "s", kWho, "linear_acceleration_time");
  detail::requirePositive(limits.angular_acceleration_time, "s", kWho, "angular_acceleration_time");
  if (blend_order < MultiPointLinearTrajBlends::kMinBlendOrder || blend_order > MultiPointLinearTrajBlends::kMaxBlendOrder)
    detail::fail(kWho, "blend order ", blend_order, " is out of range, expected ", MultiPointLinearTrajBlends::kMinBlendOrder,
                 " to ", MultiPointLinearTrajBlends::kMaxBlendOrder);
}

}  // namespace

MultiAxisPath CartesianTrajectory::geodesics(const std::vector<std::vector<KDL::Frame>>& waypoints,
                                             std::vector<Arm>& arms) {
  const std::size_t arm_count = waypoints.front().size();
  arms.assign(arm_count, Arm{});
  std::vector<std::vector<double>> coordinates(waypoints.size(), std::vector<double>(kAxesPerArm * arm_count));
  for (std::size_t a = 0; a < arm_count; ++a) {
    double s = 0.0;
    for (std::size_t k = 0; k < waypoints.size(); ++k) {
      const KDL::Frame& f = waypoints[k][a];
      for (std::size_t c = 0; c < 3; ++c) coordinates[k][kAxesPerArm * a + c] = f.p(static_cast<int>(c));
      coordinates[k][kAxesPerArm * a + 3] = s;
      if (k + 1 == waypoints.size()) break;
      KDL::Vector axis;
      const double angle = (f.M.Inverse() * waypoints[k + 1][a].M).GetRotAngle(axis);
      arms[a].push_back(Geodesic{f.M, axis, f.M * axis, s, angle, 0.0});
      s += angle;
    }
  }
  return MultiAxisPath(std::move(coordinates));
}

CartesianTrajectory::CartesianTrajectory(const std::vector<KDL::Frame>& waypoints, const CartesianLimits& limits,
                                         int blend_order)
    : CartesianTrajectory(
          [&] {
            std::vector<std::vector<KDL::Frame>> arms;
            arms.reserve(waypoints.size());
            for (const KDL::Frame& f : waypoints) arms.push_back({f});
            return arms;
          }(),
          limits, blend_order) {}

MultiAxisTrajectory CartesianTrajectory::synchronisedAxes(const std::vector<std::vector<KDL::Frame>>& waypoints,
                                                          const CartesianLimits& limits, int blend_order,
                                                          std::vector<Arm>& arms) {
  if (waypoints.size() < 2) detail::fail(kWho, "the path has ", waypoints.size(), " waypoint(s), expected at least 2");
  const std::size_t arm_count = waypoints.front().size();
  if (arm_count == 0) detail::fail(kWho, "waypoint 0 has no arms, expected at least 1");
  for (std::size_t k = 0; k < waypoints.size(); ++k) {
    if (waypoints[k].size() != arm_count)
      detail::fail(kWho, "waypoint ", k, " has ", waypoints[k].size(), " arms, expected ", arm_count, " (as waypoint 0)");
    for (std::size_t a = 0; a < arm_count; ++a) requireFiniteFrame(waypoints[k][a], k, a);
  }
  requireLimits(limits, blend_order);
  AxisLimits axis_limits;
  for (std::size_t a = 0; a < arm_count; ++a) {
    axis_limits.max_velocity.insert(axis_limits.max_velocity.end(),
                                    {limits.max_linear_velocity, limits.max_linear_velocity, limits.max_linear_velocity,
                                     limits.max_angular_velocity});
    axis_limits.acceleration_time.insert(axis_limits.acceleration_time.end(),
                                         {limits.linear_acceleration_time, limits.linear_acceleration_time,
                                          limits.linear_acceleration_time, limits.angular_acceleration_time});
  }
  return MultiAxisTrajectory(geodesics(waypoints, arms), axis_limits, blend_order);
}

CartesianTrajectory::CartesianTrajectory(const std::vector<std::vector<KDL::Frame>>& waypoints,
                                         const CartesianLimits& limits, int blend_order)
    : axes_(synchronisedAxes(waypoints, limits, blend_order, arms_)),
      angular_acceleration_time_(limits.angular_acceleration_time),
      unit_blend_(blend_order, Conditions(State{0.0, 0.0}, State{limits.angular_acceleration_time / 2.0, 1.0}),
                  limits.angular_acceleration_time) {
  // The linear-part angular speed of each segment, as MultiPointLinearTrajBlends computes it for s.
  const auto times = axes_.waypointTimes();
  const std::size_t segment_count = times.size() - 1;
  for (Arm& arm : arms_) {
    for (std::size_t k = 0; k < segment_count; ++k) {
      const double line_time = times[k + 1] - times[k] -
                               MultiPointLinearTrajBlends::lineShortening(k, segment_count, angular_acceleration_time_);
      arm[k].angular_speed = arm[k].angle / line_time;
    }
  }
}

KDL::Rotation CartesianTrajectory::orientation(const Arm& arm, double t, const State& s, KDL::Vector& angular_velocity,
                                               KDL::Vector& angular_acceleration) const noexcept {
  const auto times = axes_.waypointTimes();
  const double clamped = std::clamp(t >= 0.0 ? t : 0.0, 0.0, duration());
  // Segment k holds `clamped`; inner waypoints are times[1 .. n-1].
  const std::size_t k = static_cast<std::size_t>(std::upper_bound(times.begin() + 1, times.end() - 1, clamped) -
                                                 (times.begin() + 1));
  const double half = angular_acceleration_time_ / 2.0;
  std::size_t window = 0;  // the inner waypoint whose blend holds `clamped`, 0 for none
  if (k >= 1 && clamped - times[k] < half) window = k;
  else if (k + 2 < times.size() && times[k + 1] - clamped < half) window = k + 1;

  if (window == 0) {
    const Geodesic& segment = arm[k];
    angular_velocity = segment.world_axis * s.velocity;
    angular_acceleration = segment.world_axis * s.acceleration;
    return segment.start * KDL::Rotation::Rot2(segment.axis, s.position - segment.start_angle);
  }
  const Geodesic& in = arm[window - 1];
  const Geodesic& out = arm[window];
  const KDL::Vector w_in = in.world_axis * in.angular_speed;
  const KDL::Vector w_change = out.world_axis * out.angular_speed - w_in;
  const State beta = unit_blend_.at(clamped - times[window] + half);
  const KDL::Vector r = w_in * (clamped - times[window]) + w_change * beta.position;
  const KDL::Vector r_dot = w_in + w_change * beta.velocity;
  const KDL::Vector r_ddot = w_change * beta.acceleration;
  return detail::exponentialMotion(r, r_dot, r_ddot, angular_velocity, angular_acceleration) * out.start;
}

void CartesianTrajectory::evaluate(double t, std::size_t arm, KDL::Frame& pose, KDL::Twist& twist,
                                   KDL::Twist& acceleration) const noexcept {
  const std::size_t first = kAxesPerArm * arm;
  State axis;
  for (int c = 0; c < 3; ++c) {
    axes_.axis(first + static_cast<std::size_t>(c)).evaluate(t, axis);
    pose.p(c) = axis.position;
    twist.vel(c) = axis.velocity;
    acceleration.vel(c) = axis.acceleration;
  }
  axes_.axis(first + 3).evaluate(t, axis);
  pose.M = orientation(arms_[arm], t, axis, twist.rot, acceleration.rot);
}

void CartesianTrajectory::evaluate(double t, std::size_t arm, KDL::Frame& pose, KDL::Twist& twist) const noexcept {
  KDL::Twist acceleration;
  evaluate(t, arm, pose, twist, acceleration);
}

void CartesianTrajectory::evaluate(double t, std::span<KDL::Frame> poses, std::span<KDL::Twist> twists) const noexcept {
  const std::size_t n = std::min({poses.size(), twists.size(), arms_.size()});
  for (std::size_t a = 0; a < n; ++a) evaluate(t, a, poses[a], twists[a]);
}

}  // namespace cobra::trajectory
