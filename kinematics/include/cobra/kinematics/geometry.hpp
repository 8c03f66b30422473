#pragma once
/// @file
/// Geometry helpers: the equivalent wrench of thesis §6.2.3 (change of application point and/or
/// reference frame through the adjoint, eq. 6.1–6.3) and conversions between KDL and Eigen.
/// Wrench and twist vectors are ordered as in KDL: [force (N); torque (N·m)] and
/// [linear (m/s); angular (rad/s)]. All functions are real-time safe (no allocation, noexcept).

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <kdl/frames.hpp>

namespace cobra::kinematics {

using Vector6d = Eigen::Matrix<double, 6, 1>;
using Matrix6d = Eigen::Matrix<double, 6, 6>;

/// The skew-symmetric matrix p̂ of eq. 6.3: p̂ v = p × v.
Eigen::Matrix3d skew(const Eigen::Vector3d& p) noexcept;

/// Ad^T_{g_bc} of eq. 6.2 for wrenches ordered [f; τ]: [[Rᵀ, 0], [-Rᵀp̂, Rᵀ]], where
/// g_bc = (p_bc, R_bc) is the pose of frame C relative to frame B (m, rotation matrix).
Matrix6d wrenchAdjointTranspose(const KDL::Frame& g_bc) noexcept;

/// What to change when moving a wrench from frame B to frame C (the two properties of the
/// thesis' Equivalent Wrench component).
struct WrenchChange {
  bool application_point = true;  ///< move the point the torque is taken about from B's to C's origin
  bool reference_frame = true;    ///< express the components in C's axes instead of B's
};

/// The wrench `w_b` (measured at B's origin, in B's axes; N, N·m) as seen at C, where `g_bc` is
/// the pose of C relative to B. With both changes this is eq. 6.1, F_c = Ad^T_{g_bc} F_b:
/// f_c = Rᵀ f_b, τ_c = Rᵀ (τ_b - p × f_b). Application point only: f = f_b, τ = τ_b - p × f_b
/// (B's axes). Reference frame only: f = Rᵀ f_b, τ = Rᵀ τ_b (about B's origin).
KDL::Wrench equivalentWrench(const KDL::Frame& g_bc, const KDL::Wrench& w_b,
                             WrenchChange change = WrenchChange{}) noexcept;

/// Angle of the rotation that takes `a` to `b` (rad, in [0, π]); accurate near zero, where
/// KDL's GetRotAngle rounds angles below 1e-6 rad to 0.
double orientationError(const KDL::Rotation& a, const KDL::Rotation& b) noexcept;

/// Euclidean norm of `v`. Use it instead of KDL::Vector::Norm, which returns 0 for every vector
/// whose components are all below KDL::epsilon (1e-6): residuals would vanish.
double norm(const KDL::Vector& v) noexcept;

/// Rotation vector (axis × angle, rad) of `r`, accurate near the identity (angles up to π - 1e-6).
KDL::Vector rotationVector(const KDL::Rotation& r) noexcept;

/// @name KDL <-> Eigen
/// Element-for-element copies; a KDL::Rotation is a row-major 3×3 matrix, an Eigen one column-major.
/// (KDL::JntArray and KDL::Jacobian already hold Eigen matrices: use their `data` member.)
///@{
Eigen::Vector3d toEigen(const KDL::Vector& v) noexcept;
Eigen::Matrix3d toEigen(const KDL::Rotation& r) noexcept;
Eigen::Isometry3d toEigen(const KDL::Frame& f) noexcept;
Eigen::Quaterniond toEigenQuaternion(const KDL::Rotation& r) noexcept;
/// [vel; rot] (m/s; rad/s).
Vector6d toEigen(const KDL::Twist& t) noexcept;
/// [force; torque] (N; N·m).
Vector6d toEigen(const KDL::Wrench& w) noexcept;

KDL::Vector toKdl(const Eigen::Vector3d& v) noexcept;
/// Copies the 3×3 matrix as is: give a rotation matrix (KDL does not re-orthonormalise).
KDL::Rotation toKdl(const Eigen::Matrix3d& r) noexcept;
KDL::Rotation toKdl(const Eigen::Quaterniond& q) noexcept;
KDL::Frame toKdl(const Eigen::Isometry3d& f) noexcept;
KDL::Twist toKdlTwist(const Vector6d& v) noexcept;
KDL::Wrench toKdlWrench(const Vector6d& v) noexcept;
///@}

}  // namespace cobra::kinematics
