#pragma once
/// @file
/// The Cartesian stop motion of the thesis' trajectory generator (§4.5.2, askStopMove): one arm
/// from its current pose, twist and acceleration to rest in exactly the stop time, with position
/// and orientation continuous up to acceleration where the stop begins.

#include <array>

#include <kdl/frames.hpp>

#include "cobra/trajectory/polynomial.hpp"

namespace cobra::trajectory {

/// Each of x, y, z (m) follows Polynomial::stop from its velocity and acceleration. Orientation is
/// R(t) = Exp(r(t)) R_0 with r (rad) a rotation vector in the base frame whose three components
/// follow Polynomial::stop from r = 0, rdot = omega_0, rddot = alpha_0: at r = 0 the angular
/// velocity and acceleration are exactly rdot and rddot, so the stop starts with the given twist and
/// acceleration and ends with both zero. This is on SO(3), not per matrix element, and it stays a
/// rotation. A fixed-size value: building and evaluating it never allocate, so a generator can
/// build it in its real-time update from the set-point it is sending. Outside [0, duration()] it
/// holds the start or rest pose at zero twist and acceleration.
class CartesianStop {
 public:
  /// `twist` and `acceleration` in the base frame: `.vel` linear (m/s, m/s^2) of the origin, `.rot`
  /// angular (rad/s, rad/s^2); `stop_time` in s. Throws std::invalid_argument for a stop time that
  /// is not finite and > 0 or a non-finite input (check the stop time at configuration).
  CartesianStop(const KDL::Frame& pose, const KDL::Twist& twist, const KDL::Twist& acceleration, double stop_time);

  /// Stop time in s.
  double duration() const noexcept { return axes_[0].duration(); }

  /// Pose and twist at `t` s from the start of the stop. Real-time safe.
  void evaluate(double t, KDL::Frame& pose, KDL::Twist& twist) const noexcept;
  /// With the acceleration too (same conventions as the twist). Real-time safe.
  void evaluate(double t, KDL::Frame& pose, KDL::Twist& twist, KDL::Twist& acceleration) const noexcept;

 private:
  KDL::Rotation start_orientation_;
  std::array<Polynomial, 6> axes_;  // x, y, z, r_x, r_y, r_z
};

}  // namespace cobra::trajectory
