#pragma once
// Motion on SO(3) through the exponential map, shared by the Cartesian trajectory and stop: for a
// rotation R(t) = Exp(r(t)) R_fixed given r, its first and second time derivatives, the rotation
// and its angular velocity and acceleration in the base frame. Real-time safe.

#include <cmath>

#include <kdl/frames.hpp>

namespace cobra::trajectory::detail {

/// omega = J_l(r) r_dot with J_l(r) = I + c1 [r]x + c2 [r]x^2 the left Jacobian of SO(3),
/// c1 = (1 - cos x) / x^2, c2 = (x - sin x) / x^3 at x = |r|; alpha is its time derivative. Series
/// below small angles keep everything exact to rounding (KDL::Rotation::Rot rounds rotations below
/// its epsilon of 1e-6 rad to the identity, which is not good enough for velocities).
inline KDL::Rotation exponentialMotion(const KDL::Vector& r, const KDL::Vector& r_dot, const KDL::Vector& r_ddot,
                                       KDL::Vector& angular_velocity, KDL::Vector& angular_acceleration) {
  const double x = r.Norm();
  const double x2 = x * x;
  // sin(x) / x, c1, c2, and c1' / x, c2' / x (derivatives with respect to x); series at small x,
  // where the closed forms cancel catastrophically.
  double sinc = 1.0 - x2 / 6.0, c1 = 0.5 - x2 / 24.0, c2 = 1.0 / 6.0 - x2 / 120.0;
  double dc1 = -1.0 / 12.0 + x2 / 180.0, dc2 = -1.0 / 60.0 + x2 / 1260.0;
  if (x > 1e-4) {
    const double s = std::sin(x), c = std::cos(x);
    sinc = s / x;
    c1 = (1.0 - c) / x2;
    c2 = (x - s) / (x2 * x);
    if (x > 1e-2) {
      dc1 = (x * s - 2.0 * (1.0 - c)) / (x2 * x2);
      dc2 = ((1.0 - c) * x - 3.0 * (x - s)) / (x2 * x2 * x);
    }
  }
  const KDL::Vector r_x_rdot = r * r_dot;
  const KDL::Vector r_x_r_x_rdot = r * r_x_rdot;
  angular_velocity = r_dot + c1 * r_x_rdot + c2 * r_x_r_x_rdot;
  const double r_dot_rdot = KDL::dot(r, r_dot);  // x * dx/dt, so dc/dt = (c'(x) / x) * this
  angular_acceleration = r_ddot + dc1 * r_dot_rdot * r_x_rdot + c1 * (r * r_ddot) + dc2 * r_dot_rdot * r_x_r_x_rdot +
                         c2 * (r_dot * r_x_rdot + r * (r * r_ddot));
  const double a = r.x(), b = r.y(), z = r.z();
  return KDL::Rotation(1.0 - c1 * (b * b + z * z), -sinc * z + c1 * a * b, sinc * b + c1 * a * z,  //
                       sinc * z + c1 * a * b, 1.0 - c1 * (a * a + z * z), -sinc * a + c1 * b * z,  //
                       -sinc * b + c1 * a * z, sinc * a + c1 * b * z, 1.0 - c1 * (a * a + b * b));
}

}  // namespace cobra::trajectory::detail
