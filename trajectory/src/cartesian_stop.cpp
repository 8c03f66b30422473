#include "cobra/trajectory/cartesian_stop.hpp"

#include <algorithm>

#include "checks.hpp"
#include "so3.hpp"

namespace cobra::trajectory {

namespace {

constexpr const char* kWho = "CartesianStop: ";

std::array<Polynomial, 6> stopAxes(const KDL::Frame& pose, const KDL::Twist& twist, const KDL::Twist& acceleration,
                                   double stop_time) {
  detail::requirePositive(stop_time, "s", kWho, "stop time");
  for (int i = 0; i < 3; ++i) {
    detail::requireFinite(pose.p(i), kWho, "position component ", i);
    detail::requireFinite(twist.vel(i), kWho, "linear velocity component ", i);
    detail::requireFinite(twist.rot(i), kWho, "angular velocity component ", i);
    detail::requireFinite(acceleration.vel(i), kWho, "linear acceleration component ", i);
    detail::requireFinite(acceleration.rot(i), kWho, "angular acceleration component ", i);
  }
  const auto axis = [&](double position, double velocity, double acc) {
    return Polynomial::stop(State{position, velocity, acc}, stop_time);
  };
  return {axis(pose.p.x(), twist.vel.x(), acceleration.vel.x()), axis(pose.p.y(), twist.vel.y(), acceleration.vel.y()),
          axis(pose.p.z(), twist.vel.z(), acceleration.vel.z()), axis(0.0, twist.rot.x(), acceleration.rot.x()),
          axis(0.0, twist.rot.y(), acceleration.rot.y()), axis(0.0, twist.rot.z(), acceleration.rot.z())};
}

}  // namespace

CartesianStop::CartesianStop(const KDL::Frame& pose, const KDL::Twist& twist, const KDL::Twist& acceleration,
                             double stop_time)
    : start_orientation_(pose.M), axes_(stopAxes(pose, twist, acceleration, stop_time)) {}

void CartesianStop::evaluate(double t, KDL::Frame& pose, KDL::Twist& twist, KDL::Twist& acceleration) const noexcept {
  const bool inside = t >= 0.0 && t <= duration();
  const double clamped = inside ? t : (t > 0.0 ? duration() : 0.0);  // NaN holds the start
  std::array<State, 6> s;
  for (std::size_t i = 0; i < 6; ++i) axes_[i].evaluate(clamped, s[i]);
  pose.p = KDL::Vector(s[0].position, s[1].position, s[2].position);
  twist.vel = KDL::Vector(s[0].velocity, s[1].velocity, s[2].velocity);
  acceleration.vel = KDL::Vector(s[0].acceleration, s[1].acceleration, s[2].acceleration);
  pose.M = detail::exponentialMotion(KDL::Vector(s[3].position, s[4].position, s[5].position),
                                     KDL::Vector(s[3].velocity, s[4].velocity, s[5].velocity),
                                     KDL::Vector(s[3].acceleration, s[4].acceleration, s[5].acceleration), twist.rot,
                                     acceleration.rot) *
           start_orientation_;
  if (!inside) {
    twist = KDL::Twist::Zero();
    acceleration = KDL::Twist::Zero();
  }
}

void CartesianStop::evaluate(double t, KDL::Frame& pose, KDL::Twist& twist) const noexcept {
  KDL::Twist acceleration;
  evaluate(t, pose, twist, acceleration);
}

}  // namespace cobra::trajectory
