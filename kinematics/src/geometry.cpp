#include "cobra/kinematics/geometry.hpp"

#include <cmath>

namespace cobra::kinematics {

Eigen::Matrix3d skew(const Eigen::Vector3d& p) noexcept {
  Eigen::Matrix3d s;
  s << 0.0, -p.z(), p.y(),  //
      p.z(), 0.0, -p.x(),   //
      -p.y(), p.x(), 0.0;
  return s;
}

Matrix6d wrenchAdjointTranspose(const KDL::Frame& g_bc) noexcept {
  const Eigen::Matrix3d r_t = toEigen(g_bc.M).transpose();
  Matrix6d ad = Matrix6d::Zero();
  ad.topLeftCorner<3, 3>() = r_t;
  ad.bottomLeftCorner<3, 3>() = -r_t * skew(toEigen(g_bc.p));
  ad.bottomRightCorner<3, 3>() = r_t;
  return ad;
}

KDL::Wrench equivalentWrench(const KDL::Frame& g_bc, const KDL::Wrench& w_b, WrenchChange change) noexcept {
  KDL::Wrench w = w_b;
  // Torque about C's origin: τ_C = τ_B + (o_B - o_C) × f = τ_B - p_bc × f (both in B's axes).
  if (change.application_point) w.torque = w_b.torque - g_bc.p * w_b.force;
  if (change.reference_frame) {
    const KDL::Rotation r_cb = g_bc.M.Inverse();
    w.force = r_cb * w.force;
    w.torque = r_cb * w.torque;
  }
  return w;
}

double orientationError(const KDL::Rotation& a, const KDL::Rotation& b) noexcept {
  // Residual E = aᵀ b: sin(angle) from its skew part, cos(angle) from its trace.
  const KDL::Rotation e = a.Inverse() * b;
  const double sin_norm = 0.5 * std::hypot(e(2, 1) - e(1, 2), e(0, 2) - e(2, 0), e(1, 0) - e(0, 1));
  const double cos_angle = 0.5 * (e(0, 0) + e(1, 1) + e(2, 2) - 1.0);
  return std::atan2(sin_norm, cos_angle);
}

double norm(const KDL::Vector& v) noexcept { return std::hypot(v.x(), v.y(), v.z()); }

KDL::Vector rotationVector(const KDL::Rotation& r) noexcept {
  const KDL::Vector sin_axis(0.5 * (r(2, 1) - r(1, 2)), 0.5 * (r(0, 2) - r(2, 0)), 0.5 * (r(1, 0) - r(0, 1)));
  const double sin_angle = norm(sin_axis);
  const double angle = std::atan2(sin_angle, 0.5 * (r(0, 0) + r(1, 1) + r(2, 2) - 1.0));
  constexpr double kSmall = 1e-8;  // rad: below it angle / sin(angle) = 1 to double precision
  return sin_angle < kSmall ? sin_axis : sin_axis * (angle / sin_angle);
}

Eigen::Vector3d toEigen(const KDL::Vector& v) noexcept { return {v.x(), v.y(), v.z()}; }

Eigen::Matrix3d toEigen(const KDL::Rotation& r) noexcept {
  Eigen::Matrix3d m;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) m(i, j) = r(i, j);
  return m;
}

Eigen::Isometry3d toEigen(const KDL::Frame& f) noexcept {
  Eigen::Isometry3d iso = Eigen::Isometry3d::Identity();
  iso.linear() = toEigen(f.M);
  iso.translation() = toEigen(f.p);
  return iso;
}

Eigen::Quaterniond toEigenQuaternion(const KDL::Rotation& r) noexcept {
  double x = 0.0, y = 0.0, z = 0.0, w = 1.0;
  r.GetQuaternion(x, y, z, w);
  return Eigen::Quaterniond(w, x, y, z);
}

Vector6d toEigen(const KDL::Twist& t) noexcept {
  Vector6d v;
  v << t.vel.x(), t.vel.y(), t.vel.z(), t.rot.x(), t.rot.y(), t.rot.z();
  return v;
}

Vector6d toEigen(const KDL::Wrench& w) noexcept {
  Vector6d v;
  v << w.force.x(), w.force.y(), w.force.z(), w.torque.x(), w.torque.y(), w.torque.z();
  return v;
}

KDL::Vector toKdl(const Eigen::Vector3d& v) noexcept { return KDL::Vector(v.x(), v.y(), v.z()); }

KDL::Rotation toKdl(const Eigen::Matrix3d& r) noexcept {
  return KDL::Rotation(r(0, 0), r(0, 1), r(0, 2), r(1, 0), r(1, 1), r(1, 2), r(2, 0), r(2, 1), r(2, 2));
}

KDL::Rotation toKdl(const Eigen::Quaterniond& q) noexcept {
  const Eigen::Quaterniond n = q.normalized();
  return KDL::Rotation::Quaternion(n.x(), n.y(), n.z(), n.w());
}

KDL::Frame toKdl(const Eigen::Isometry3d& f) noexcept {
  return KDL::Frame(toKdl(Eigen::Matrix3d(f.linear())), toKdl(Eigen::Vector3d(f.translation())));
}

KDL::Twist toKdlTwist(const Vector6d& v) noexcept {
  return KDL::Twist(KDL::Vector(v(0), v(1), v(2)), KDL::Vector(v(3), v(4), v(5)));
}

KDL::Wrench toKdlWrench(const Vector6d& v) noexcept {
  return KDL::Wrench(KDL::Vector(v(0), v(1), v(2)), KDL::Vector(v(3), v(4), v(5)));
}

}  // namespace cobra::kinematics
