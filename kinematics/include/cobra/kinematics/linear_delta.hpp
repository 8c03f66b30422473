#pragma once
/// @file
/// Forward and inverse kinematics of a linear delta robot (thesis §4.3.1: the I-SUR macro unit;
/// M. Bouri, R. Clavel, "The linear delta: developments and applications", ISR/ROBOTIK 2010):
/// three actuated prismatic joints (ball-screw sliders on rails), each connected to a common
/// moving platform by a pair of parallel rods with universal joints at both ends. The parallel
/// rods keep the platform's orientation fixed, so each pair acts as one rod of length L between a
/// point of the slider and a point of the platform, and the platform only translates.
///
/// Kinematics, for actuator i with rail origin bᵢ, unit direction uᵢ, platform joint eᵢ (platform
/// frame) and rod length Lᵢ, platform position p (base frame, m):  |p + eᵢ - (bᵢ + qᵢ uᵢ)| = Lᵢ.
///  - inverse: a quadratic in qᵢ per actuator (two roots: the slider on either side of the rod's
///    sphere); the root taken is the assembly mode (see `LinearDeltaGeometry::platform_side`).
///  - forward: the intersection of three spheres of radius Lᵢ about cᵢ = bᵢ + qᵢ uᵢ - eᵢ (two
///    mirror points about the plane of the centres; the one on `platform_side` is taken).

#include <array>
#include <span>
#include <string_view>

#include <Eigen/Core>
#include <kdl/frames.hpp>

#include "cobra/kinematics/kinematics_solver.hpp"

namespace cobra::kinematics {

/// One actuated leg of the linear delta.
struct LinearDeltaActuator {
  KDL::Vector rail_origin;     ///< slider-side rod joint at q = 0, base frame, m
  KDL::Vector rail_direction;  ///< direction of positive travel, base frame (normalised at construction)
  KDL::Vector platform_joint;  ///< platform-side rod joint relative to the platform origin, m
  double rod_length = 0.0;     ///< distance between the two rod joints, m
  double lower = 0.0;          ///< stroke limit, m
  double upper = 0.0;          ///< stroke limit, m
};

/// Geometry of a linear delta (the immutable model).
struct LinearDeltaGeometry {
  std::array<LinearDeltaActuator, 3> actuators;
  /// Assembly mode: the platform hangs on this side of its sliders. Inverse: each slider takes the
  /// root that makes its rod point most along this direction; forward: the platform is the
  /// intersection point on this side of the plane through the three sphere centres. Unit vector,
  /// base frame; must not be perpendicular to any rail.
  KDL::Vector platform_side = KDL::Vector(0.0, 0.0, -1.0);

  /// The I-SUR macro unit as modelled here. The thesis gives no dimensions, so these are
  /// documented plausible values of a surgical-size linear delta: three rails at 120° (azimuths
  /// 90°, 210°, 330°) starting 0.30 m from the vertical axis at z = 0 and running down and inwards
  /// at 30° from the vertical; 0.25 m stroke [0, 0.25] m; rods 0.35 m; platform joints 0.06 m from
  /// the platform centre at the same azimuths; platform below the sliders. Over the stroke the
  /// platform spans z ∈ [-0.55, -0.26] m (-0.38 m with all sliders at 0.1 m) and |x|, |y| ≲ 0.2 m.
  static LinearDeltaGeometry isurMacro();
};

/// Closed-form linear delta solver. Joint values: the three slider travels qᵢ (m). Tool pose:
/// the platform origin in the base frame, with the identity rotation (the platform translates only).
class LinearDeltaSolver final : public KinematicsSolver {
 public:
  /// @throws std::invalid_argument naming the actuator (1-based) and the fault, e.g.
  /// "linear delta: actuator 2 rod length -0.1 m: must be > 0", for a zero rail direction, a
  /// non-positive rod length, non-finite values, invalid stroke limits, a rail perpendicular to
  /// platform_side, or a platform_side of zero length.
  explicit LinearDeltaSolver(const LinearDeltaGeometry& geometry = LinearDeltaGeometry::isurMacro(),
                             std::string_view name = "linear delta");

  std::string_view name() const noexcept override { return name_; }
  unsigned jointCount() const noexcept override { return 3; }
  const JointLimits& limits() const noexcept override { return limits_; }
  const LinearDeltaGeometry& geometry() const noexcept { return geometry_; }

  /// Platform position for slider travels `q` (m). Unreachable when the rods cannot meet (the
  /// three spheres do not intersect); Singular when the sphere centres are (nearly) collinear.
  /// Ignores the stroke limits (FK of a measured position must not fail). No allocation.
  IkStatus forwardPosition(std::span<const double, 3> q, KDL::Vector& position) const noexcept;
  /// Slider travels (m) that put the platform at `position`: Unreachable when a rod cannot reach
  /// its rail, JointLimits when a travel is outside its stroke. `q` untouched unless Ok.
  IkStatus inversePosition(const KDL::Vector& position, std::span<double, 3> q) const noexcept;

  /// Jacobian dp/dq (3 × 3, m/m) at slider travels `q`: column i is the platform velocity per unit
  /// travel speed of actuator i. From the rod constraints, rᵢ·ṗ = (rᵢ·uᵢ) q̇ᵢ with rᵢ the rod vector,
  /// so J⁻¹ has rows rᵢᵀ / (rᵢ·uᵢ). Singular when a rod is perpendicular to its rail (rᵢ·uᵢ = 0)
  /// or the rods are coplanar (det [r₁ r₂ r₃] = 0); errors of forwardPosition otherwise.
  IkStatus jacobian(std::span<const double, 3> q, Eigen::Matrix3d& dp_dq) const noexcept;

  IkStatus forward(const KDL::JntArray& q, KDL::Frame& pose) noexcept override;
  /// Unreachable also when the target's rotation is not the identity (within 1e-9 rad). The seed
  /// is not needed (the assembly mode fixes the solution) but must have 3 finite values.
  IkStatus inverse(const KDL::Frame& target, const KDL::JntArray& seed, KDL::JntArray& q_out) noexcept override;

 private:
  LinearDeltaGeometry geometry_;
  std::string name_;
  JointLimits limits_;
};

}  // namespace cobra::kinematics
