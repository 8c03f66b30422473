#include "cobra/kinematics/linear_delta.hpp"

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include <Eigen/LU>

#include "cobra/kinematics/geometry.hpp"

namespace cobra::kinematics {

namespace {

constexpr double kPi = std::numbers::pi;
/// Sphere centres closer to collinear than this (m, as a distance) make the forward problem singular.
constexpr double kCollinear = 1e-9;
/// Relative size (to L²) of the rounding error of squared lengths, below which a negative value is 0.
constexpr double kRounding = 1e-12;
/// |u·side| below this: the rail is perpendicular to the platform side and the branch is undefined.
constexpr double kMinSideComponent = 1e-3;

bool finite(const KDL::Vector& v) { return std::isfinite(v.x()) && std::isfinite(v.y()) && std::isfinite(v.z()); }

}  // namespace

LinearDeltaGeometry LinearDeltaGeometry::isurMacro() {
  constexpr double kRailRadius = 0.30;      // m, rail start from the vertical axis
  constexpr double kRailTilt = kPi / 6.0;   // rad from the vertical, inwards
  constexpr double kPlatformRadius = 0.06;  // m
  constexpr double kRod = 0.35;             // m
  constexpr double kStroke = 0.25;          // m
  LinearDeltaGeometry g;
  for (int i = 0; i < 3; ++i) {
    const double azimuth = kPi / 2.0 + i * 2.0 * kPi / 3.0;
    const KDL::Vector radial(std::cos(azimuth), std::sin(azimuth), 0.0);
    g.actuators[static_cast<std::size_t>(i)] = LinearDeltaActuator{
        .rail_origin = kRailRadius * radial,
        .rail_direction = -std::sin(kRailTilt) * radial + KDL::Vector(0.0, 0.0, -std::cos(kRailTilt)),
        .platform_joint = kPlatformRadius * radial,
        .rod_length = kRod,
        .lower = 0.0,
        .upper = kStroke};
  }
  return g;
}

LinearDeltaSolver::LinearDeltaSolver(const LinearDeltaGeometry& geometry, std::string_view name)
    : geometry_(geometry), name_(name) {
  const double side_norm = norm(geometry_.platform_side);
  if (!finite(geometry_.platform_side) || side_norm == 0.0)
    throw std::invalid_argument(name_ + ": platform_side must be a finite non-zero vector");
  geometry_.platform_side = geometry_.platform_side / side_norm;
  for (std::size_t i = 0; i < 3; ++i) {
    LinearDeltaActuator& a = geometry_.actuators[i];
    const std::string who = name_ + ": actuator " + std::to_string(i + 1);
    if (!finite(a.rail_origin) || !finite(a.rail_direction) || !finite(a.platform_joint))
      throw std::invalid_argument(who + ": rail origin, rail direction and platform joint must be finite (m)");
    const double length = norm(a.rail_direction);
    if (length == 0.0) throw std::invalid_argument(who + " rail direction is zero: give the direction of travel");
    a.rail_direction = a.rail_direction / length;
    if (!(a.rod_length > 0.0) || !std::isfinite(a.rod_length))
      throw std::invalid_argument(who + " rod length " + formatNumber(a.rod_length) + " m: must be > 0");
    if (std::abs(KDL::dot(a.rail_direction, geometry_.platform_side)) < kMinSideComponent)
      throw std::invalid_argument(who + " rail is perpendicular to platform_side: the assembly mode is undefined");
    limits_.types.push_back(JointType::Prismatic);
    limits_.lower.push_back(a.lower);
    limits_.upper.push_back(a.upper);
  }
  validateLimits(name_, limits_, 3);
}

IkStatus LinearDeltaSolver::forwardPosition(std::span<const double, 3> q, KDL::Vector& position) const noexcept {
  std::array<KDL::Vector, 3> c;
  std::array<double, 3> r{};
  for (std::size_t i = 0; i < 3; ++i) {
    if (!std::isfinite(q[i])) return IkStatus::BadInput;
    const LinearDeltaActuator& a = geometry_.actuators[i];
    c[i] = a.rail_origin + q[i] * a.rail_direction - a.platform_joint;
    r[i] = a.rod_length;
  }
  // Trilateration in the frame (ex, ey, ez) with origin c0, ex towards c1, c2 in the (ex, ey) plane.
  const KDL::Vector c01 = c[1] - c[0];
  const KDL::Vector c02 = c[2] - c[0];
  const double d = norm(c01);
  if (d < kCollinear) return IkStatus::Singular;
  const KDL::Vector ex = c01 / d;
  const double i = KDL::dot(ex, c02);
  const KDL::Vector ey_raw = c02 - i * ex;
  const double j = norm(ey_raw);
  if (j < kCollinear) return IkStatus::Singular;
  const KDL::Vector ey = ey_raw / j;
  const KDL::Vector ez = ex * ey;
  const double x = (r[0] * r[0] - r[1] * r[1] + d * d) / (2.0 * d);
  const double y = (r[0] * r[0] - r[2] * r[2] + i * i + j * j - 2.0 * i * x) / (2.0 * j);
  double z_squared = r[0] * r[0] - x * x - y * y;
  if (z_squared < 0.0) {
    if (z_squared < -kRounding * r[0] * r[0]) return IkStatus::Unreachable;
    z_squared = 0.0;  // tangent spheres: the workspace boundary, negative only by rounding
  }
  const double z = KDL::dot(ez, geometry_.platform_side) >= 0.0 ? std::sqrt(z_squared) : -std::sqrt(z_squared);
  position = c[0] + x * ex + y * ey + z * ez;
  return IkStatus::Ok;
}

IkStatus LinearDeltaSolver::inversePosition(const KDL::Vector& position, std::span<double, 3> q) const noexcept {
  if (!finite(position)) return IkStatus::BadInput;
  std::array<double, 3> travel{};
  for (std::size_t i = 0; i < 3; ++i) {
    const LinearDeltaActuator& a = geometry_.actuators[i];
    // |d - q u| = L with d from the rail origin to the platform joint: q² - 2 q (u·d) + |d|² - L² = 0.
    const KDL::Vector d = position + a.platform_joint - a.rail_origin;
    const double ud = KDL::dot(a.rail_direction, d);
    double discriminant = ud * ud - KDL::dot(d, d) + a.rod_length * a.rod_length;
    if (discriminant < 0.0) {
      if (discriminant < -kRounding * a.rod_length * a.rod_length) return IkStatus::Unreachable;
      discriminant = 0.0;  // rod tangent to the rail's line: negative only by rounding
    }
    // The rod d - q u points most along platform_side for the root with the smaller q·(u·side).
    const double root = std::sqrt(discriminant);
    travel[i] = KDL::dot(a.rail_direction, geometry_.platform_side) > 0.0 ? ud - root : ud + root;
  }
  if (!limits_.contains(travel)) return IkStatus::JointLimits;
  for (std::size_t i = 0; i < 3; ++i) q[i] = travel[i];
  return IkStatus::Ok;
}

IkStatus LinearDeltaSolver::jacobian(std::span<const double, 3> q, Eigen::Matrix3d& dp_dq) const noexcept {
  constexpr double kSingular = 1e-9;  // relative to |r|·|u| (= L) and |r|³ (= L³)
  KDL::Vector p;
  const IkStatus status = forwardPosition(q, p);
  if (status != IkStatus::Ok) return status;
  Eigen::Matrix3d inverse_jacobian;  // dq/dp
  for (std::size_t i = 0; i < 3; ++i) {
    const LinearDeltaActuator& a = geometry_.actuators[i];
    const KDL::Vector rod = p + a.platform_joint - (a.rail_origin + q[i] * a.rail_direction);
    const double along_rail = KDL::dot(rod, a.rail_direction);
    if (std::abs(along_rail) < kSingular * a.rod_length) return IkStatus::Singular;
    inverse_jacobian.row(static_cast<Eigen::Index>(i)) = toEigen(rod).transpose() / along_rail;
  }
  const double scale = geometry_.actuators[0].rod_length;
  if (std::abs(inverse_jacobian.determinant()) < kSingular / (scale * scale * scale)) return IkStatus::Singular;
  dp_dq = inverse_jacobian.inverse();
  return IkStatus::Ok;
}

IkStatus LinearDeltaSolver::forward(const KDL::JntArray& q, KDL::Frame& pose) noexcept {
  if (!validJointArray(q, 3)) return IkStatus::BadInput;
  KDL::Vector position;
  const IkStatus status = forwardPosition(std::span<const double, 3>(q.data.data(), 3), position);
  if (status == IkStatus::Ok) pose = KDL::Frame(KDL::Rotation::Identity(), position);
  return status;
}

IkStatus LinearDeltaSolver::inverse(const KDL::Frame& target, const KDL::JntArray& seed,
                                    KDL::JntArray& q_out) noexcept {
  constexpr double kFixedOrientationTolerance = 1e-9;  // rad
  if (!validFrame(target) || !validJointArray(seed, 3) || q_out.rows() != 3) return IkStatus::BadInput;
  if (orientationError(target.M, KDL::Rotation::Identity()) > kFixedOrientationTolerance) return IkStatus::Unreachable;
  return inversePosition(target.p, std::span<double, 3>(q_out.data.data(), 3));
}

}  // namespace cobra::kinematics
