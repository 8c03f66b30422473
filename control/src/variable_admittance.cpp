#include "cobra/control/variable_admittance.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

namespace cobra::control {
namespace {

constexpr double kSymmetryTolerance = 1e-9;

bool finite(const KDL::Vector& v) { return std::isfinite(v.x()) && std::isfinite(v.y()) && std::isfinite(v.z()); }

/// Exp of a rotation vector (rad) as a KDL rotation.
KDL::Rotation expRotation(const Vector6& x) {
  const KDL::Vector r(x(3), x(4), x(5));
  const double angle = r.Norm();
  return angle < 1e-15 ? KDL::Rotation::Identity() : KDL::Rotation::Rot2(r / angle, angle);
}

/// Left Jacobian of SO(3) at the rotation vector φ (rad): with R = R_ref Exp(φ), the angular
/// velocity of R relative to R_ref is R_ref J_l(φ) φ̇ (base frame). So the torque τ (reference axes)
/// does work τᵀ J_l(φ) φ̇, and the generalised force conjugate to φ is J_l(φ)ᵀ τ: the port
/// (F_ext, ẋ̃) of eq. 4.10 is then the physical (wrench, twist) port, at any rotation error < π.
Eigen::Matrix3d leftJacobian(const Eigen::Vector3d& phi) {
  const double angle = phi.norm();
  Eigen::Matrix3d hat;
  hat << 0.0, -phi.z(), phi.y(), phi.z(), 0.0, -phi.x(), -phi.y(), phi.x(), 0.0;
  // Taylor expansions below 1e-4 rad keep the coefficients exact to double precision.
  const double a = angle < 1e-4 ? 0.5 - angle * angle / 24.0 : (1.0 - std::cos(angle)) / (angle * angle);
  const double b =
      angle < 1e-4 ? 1.0 / 6.0 - angle * angle / 120.0 : (angle - std::sin(angle)) / (angle * angle * angle);
  return Eigen::Matrix3d::Identity() + a * hat + b * hat * hat;
}

/// m·v; with `diagonal` (every parameter matrix is diagonal, the usual case) only m's diagonal is
/// used: the same bits, since the products of the zeros add exact zeros.
Vector6 times(const Matrix6& m, const Vector6& v, bool diagonal) noexcept {
  if (diagonal) return m.diagonal().cwiseProduct(v);
  return m * v;
}

/// Shortest decimal form of a number for messages ("-1", "0.5", "2e+04").
std::string shortNumber(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", value);
  return text;
}

/// Smallest eigenvalue of a symmetric matrix (fixed size: no allocation).
double smallestEigenvalue(const Matrix6& m) {
  const Eigen::SelfAdjointEigenSolver<Matrix6> solver(m, Eigen::EigenvaluesOnly);
  return solver.eigenvalues()(0);
}

bool symmetricAtLeast(const Matrix6& m, const Matrix6& floor, bool strictly) {
  if (!m.allFinite()) return false;
  if ((m - m.transpose()).cwiseAbs().maxCoeff() > kSymmetryTolerance * (1.0 + m.cwiseAbs().maxCoeff())) return false;
  const double lowest = smallestEigenvalue(m - floor);
  return strictly ? lowest > 0.0 : lowest >= -1e-12;
}

/// A matrix parameter for messages: its name and the units of its translation and rotation entries.
struct MatrixName {
  const char* name;
  const char* translation_unit;
  const char* rotation_unit;
};

/// Checks m > floor (m >= floor when `semidefinite`), symmetric and finite. A diagonal m and floor (the
/// usual case: the component's properties are diagonals) are checked entry by entry, so the message
/// names the entry, its unit and the bound, e.g. "damping[3] = -1 N·m·s/rad: must be > 0".
void requireAbove(const Matrix6& m, const Matrix6& floor, const MatrixName& what, const char* floor_name,
                  bool semidefinite) {
  const std::string prefix = std::string("VariableAdmittance: ") + what.name;
  const char* relation = semidefinite ? ">= " : "> ";
  if (m.isDiagonal(0.0) && floor.isDiagonal(0.0)) {
    for (int i = 0; i < 6; ++i) {
      const double value = m(i, i), bound = floor(i, i);
      if (std::isfinite(value) && (semidefinite ? value >= bound : value > bound)) continue;
      const std::string unit = i < 3 ? what.translation_unit : what.rotation_unit;
      const std::string index = "[" + std::to_string(i) + "]";
      const std::string limit =
          floor_name ? std::string(floor_name) + index + " = " + shortNumber(bound) + " " + unit : std::string("0");
      throw std::invalid_argument(prefix + index + " = " + shortNumber(value) + " " + unit + ": must be " + relation +
                                  limit + " (entries 0-2 translation, 3-5 rotation)");
    }
    return;
  }
  const std::string units = std::string(" (") + what.translation_unit + ", " + what.rotation_unit + ")";
  if (!m.allFinite()) throw std::invalid_argument(prefix + units + " has a value that is not finite");
  if ((m - m.transpose()).cwiseAbs().maxCoeff() > kSymmetryTolerance * (1.0 + m.cwiseAbs().maxCoeff()))
    throw std::invalid_argument(prefix + units + " must be symmetric");
  const double lowest = smallestEigenvalue(m - floor);
  if (semidefinite ? lowest < -1e-12 : lowest <= 0.0)
    throw std::invalid_argument(prefix + units + (floor_name ? std::string(" - ") + floor_name : std::string()) +
                                " must be positive " + (semidefinite ? "semidefinite" : "definite") +
                                " (smallest eigenvalue " + shortNumber(lowest) + ")");
}

}  // namespace

VariableAdmittance::VariableAdmittance(const AdmittanceParameters& p) : parameters_(p) {
  requireAbove(p.constant_inertia, Matrix6::Zero(), {"constant_inertia", "kg", "kg·m²"}, nullptr, false);
  requireAbove(p.constant_stiffness, Matrix6::Zero(), {"constant_stiffness", "N/m", "N·m/rad"}, nullptr, true);
  requireAbove(p.damping, Matrix6::Zero(), {"damping", "N·s/m", "N·m·s/rad"}, nullptr, false);
  requireAbove(p.inertia, p.constant_inertia, {"inertia", "kg", "kg·m²"}, "constant_inertia", true);
  requireAbove(p.stiffness, p.constant_stiffness, {"stiffness", "N/m", "N·m/rad"}, "constant_stiffness", true);
  const TankParameters& t = p.tank;
  if (!(t.min_energy > 0.0) || !(t.initial_energy > t.min_energy) || !(t.max_energy >= t.initial_energy))
    throw std::invalid_argument("VariableAdmittance: tank energies must satisfy 0 < min_energy < initial_energy <= "
                                "max_energy (J), got " + std::to_string(t.min_energy) + ", " +
                                std::to_string(t.initial_energy) + ", " + std::to_string(t.max_energy));
  variable_inertia_ = parameters_.inertia - parameters_.constant_inertia;
  variable_stiffness_ = parameters_.stiffness - parameters_.constant_stiffness;
  diagonal_ = allDiagonal();
  reset();
}

bool VariableAdmittance::allDiagonal() const noexcept {
  const AdmittanceParameters& p = parameters_;
  return p.constant_inertia.isDiagonal(0.0) && p.constant_stiffness.isDiagonal(0.0) && p.inertia.isDiagonal(0.0) &&
         p.damping.isDiagonal(0.0) && p.stiffness.isDiagonal(0.0);
}

void VariableAdmittance::reset() noexcept {
  x_.setZero();
  v_.setZero();
  dissipated_power_ = 0.0;
  tank_ = parameters_.tank.initial_energy;
  error_jacobian_known_ = false;
  audit_ = EnergyAudit{};
  audit_.tank = tank_;
}

AdmittanceStatus VariableAdmittance::setParameters(const Matrix6& inertia, const Matrix6& damping,
                                                   const Matrix6& stiffness) noexcept {
  if (!symmetricAtLeast(inertia, parameters_.constant_inertia, false) ||
      !symmetricAtLeast(stiffness, parameters_.constant_stiffness, false) ||
      !symmetricAtLeast(damping, Matrix6::Zero(), true))
    return AdmittanceStatus::BadParameters;
  parameters_.inertia = inertia;
  parameters_.damping = damping;
  parameters_.stiffness = stiffness;
  variable_inertia_ = parameters_.inertia - parameters_.constant_inertia;
  variable_stiffness_ = parameters_.stiffness - parameters_.constant_stiffness;
  diagonal_ = allDiagonal();
  ++revision_;
  return AdmittanceStatus::Ok;
}

double VariableAdmittance::constantEnergy(const Vector6& x, const Vector6& v) const noexcept {
  return 0.5 * v.dot(times(parameters_.constant_inertia, v, diagonal_)) +
         0.5 * x.dot(times(parameters_.constant_stiffness, x, diagonal_));
}

void VariableAdmittance::integrate(const Matrix6& M, const Matrix6& K, const Vector6& force, double dt,
                                   Factorisation& factor, Vector6& x_next, Vector6& v_next) const noexcept {
  // The same parameters and dt give the same system matrix bit for bit, hence the same
  // factorisation: it is worked out again only when one of them changed.
  // A diagonal system is solved entry by entry (its Cholesky factor would be its square root).
  if (!factor.known || factor.revision != revision_ || factor.dt != dt) {
    if (diagonal_)
      factor.diagonal = M.diagonal() + dt * parameters_.damping.diagonal() + dt * dt * K.diagonal();
    else
      factor.llt.compute(M + dt * parameters_.damping + dt * dt * K);
    factor.revision = revision_;
    factor.dt = dt;
    factor.known = true;
  }
  const Vector6 rhs = times(M, v_, diagonal_) + dt * (force - times(K, x_, diagonal_));
  v_next = diagonal_ ? Vector6(rhs.cwiseQuotient(factor.diagonal)) : Vector6(factor.llt.solve(rhs));
  x_next = x_ + dt * v_next;
}

void VariableAdmittance::rebase(const KDL::Frame& old_reference, const KDL::Frame& new_reference) noexcept {
  // Same output pose: p_new + x̃'_p = p_old + x̃_p and R_new Exp(x̃'_r) = R_old Exp(x̃_r).
  const KDL::Vector dp = old_reference.p - new_reference.p;
  x_(0) += dp.x();
  x_(1) += dp.y();
  x_(2) += dp.z();
  const KDL::Rotation relative = new_reference.M.Inverse() * old_reference.M * expRotation(x_);
  const KDL::Vector r = relative.GetRot();  // axis times angle in [0, π], rad
  x_(3) = r.x();
  x_(4) = r.y();
  x_(5) = r.z();
  error_jacobian_known_ = false;
  audit_.stored = constantEnergy(x_, v_);
}

void VariableAdmittance::resync(const KDL::Frame& held, const KDL::Wrench& wrench, KDL::Frame& reference) noexcept {
  reference = held;
  if (!finite(held.p) || !finite(wrench.force) || !finite(wrench.torque)) return;
  // At rest in equilibrium with the wrench: Kd x̃ = (F, τ), τ in the held pose's axes.
  const KDL::Vector torque = held.M.Inverse(wrench.torque);
  Vector6 force;
  force << wrench.force.x(), wrench.force.y(), wrench.force.z(), torque.x(), torque.y(), torque.z();
  Vector6 x = Vector6::Zero();
  if (diagonal_) {
    for (int i = 0; i < 6; ++i) {
      const double k = parameters_.stiffness(i, i);
      x(i) = k > 0.0 ? force(i) / k : 0.0;
    }
  } else {
    const Eigen::LLT<Matrix6> stiffness(parameters_.stiffness);
    if (stiffness.info() == Eigen::Success) x = stiffness.solve(force);
  }
  const Vector6 rest = Vector6::Zero();
  double stored = constantEnergy(x, rest);
  const double needed = stored - audit_.stored;  // J the new state stores more than the old
  if (needed > 0.0 && parameters_.use_tank) {
    if (tank_ - needed >= parameters_.tank.min_energy) {
      tank_ -= needed;
    } else {
      x.setZero();
      stored = 0.0;
    }
  }
  audit_.resync_removed += audit_.stored - stored;
  audit_.stored = stored;
  audit_.tank = tank_;
  x_ = x;
  v_.setZero();
  dissipated_power_ = 0.0;
  error_jacobian_known_ = false;
  // Output pose p_ref + x̃_p = p_held and R_ref Exp(x̃_r) = R_held.
  reference.p = held.p - KDL::Vector(x_(0), x_(1), x_(2));
  reference.M = held.M * expRotation(x_).Inverse();
}

AdmittanceStatus VariableAdmittance::step(const KDL::Frame& reference, const KDL::Twist& reference_twist,
                                          const KDL::Wrench& wrench, double dt, KDL::Frame& pose,
                                          KDL::Twist& twist) noexcept {
  if (!(dt > 0.0) || !std::isfinite(dt) || !finite(reference.p) || !finite(wrench.force) || !finite(wrench.torque) ||
      !finite(reference_twist.vel) || !finite(reference_twist.rot))
    return AdmittanceStatus::BadInput;
  // Generalised force conjugate to x̃: the force (base frame), and J_l(φ)ᵀ times the torque in the
  // reference's axes (see leftJacobian), evaluated at the start of the step.
  const KDL::Vector torque = reference.M.Inverse(wrench.torque);
  Vector6 force;
  force.head<3>() = Eigen::Vector3d(wrench.force.x(), wrench.force.y(), wrench.force.z());
  if (!error_jacobian_known_) error_jacobian_ = leftJacobian(x_.tail<3>());
  force.tail<3>() = error_jacobian_.transpose() * Eigen::Vector3d(torque.x(), torque.y(), torque.z());

  const double sigma = tank_ <= parameters_.tank.max_energy ? 1.0 : 0.0;  // eq. 4.7
  // H_c(x̃, ẋ̃) now: what the last step, rebase or reset stored for this very x̃ and ẋ̃.
  const double energy_before = audit_.stored;
  Vector6 x_next, v_next;
  integrate(parameters_.inertia, parameters_.stiffness, force, dt, variable_factor_, x_next, v_next);
  Vector6 w = -times(variable_stiffness_, x_next, diagonal_) -
              times(variable_inertia_, (v_next - v_) / dt, diagonal_);  // eq. 4.11
  Vector6 dx = x_next - x_;
  double energy_after = constantEnergy(x_next, v_next);
  double delta = (force + w).dot(dx) - (energy_after - energy_before);
  double tank_next = tank_ + sigma * delta - w.dot(dx);
  AdmittanceStatus status = AdmittanceStatus::Ok;
  if (parameters_.use_tank && tank_next < parameters_.tank.min_energy) {
    // The tank cannot pay for w: implement the constant parts only (w = 0).
    integrate(parameters_.constant_inertia, parameters_.constant_stiffness, force, dt, constant_factor_, x_next,
              v_next);
    w.setZero();
    dx = x_next - x_;
    energy_after = constantEnergy(x_next, v_next);
    delta = force.dot(dx) - (energy_after - energy_before);
    tank_next = tank_ + sigma * delta;
    status = AdmittanceStatus::TankEmpty;
  }
  audit_.from_environment += force.dot(dx);
  audit_.dissipated += delta;
  audit_.injected_by_w += w.dot(dx);
  x_ = x_next;
  v_ = v_next;
  // What leaves the controller as dissipation (W): the share of δ its own tank does not store
  // (all of it while the tank is full, σ = 0, or without a tank). Routing all of ẋ̃ᵀDẋ̃ to a
  // teleoperation tank too would count the energy the admittance's tank already stored twice.
  dissipated_power_ = (parameters_.use_tank ? 1.0 - sigma : 1.0) * std::max(delta, 0.0) / dt;
  tank_ = tank_next;
  audit_.stored = energy_after;
  audit_.tank = tank_;

  pose.p = reference.p + KDL::Vector(x_(0), x_(1), x_(2));
  pose.M = reference.M * expRotation(x_);
  twist.vel = reference_twist.vel + KDL::Vector(v_(0), v_(1), v_(2));
  error_jacobian_ = leftJacobian(x_.tail<3>());
  error_jacobian_known_ = true;
  const Eigen::Vector3d relative_rate = error_jacobian_ * v_.tail<3>();  // rad/s, reference axes
  twist.rot = reference_twist.rot + reference.M * KDL::Vector(relative_rate.x(), relative_rate.y(), relative_rate.z());
  return status;
}

}  // namespace cobra::control
