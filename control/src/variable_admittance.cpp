#include "cobra/control/variable_admittance.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <cmath>
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

/// Smallest eigenvalue of a symmetric matrix (fixed size: no allocation).
double smallestEigenvalue(const Matrix6& m) {
  const Eigen::SelfAdjointEigenSolver<Matrix6> solver(m, Eigen::EigenvaluesOnly);
  return solver.eigenvalues()(0);
}

bool symmetricAtLeast(const Matrix6& m, const Matrix6& floor, bool strictly) {
  if (!m.allFinite() || (m - m.transpose()).cwiseAbs().maxCoeff() > kSymmetryTolerance * (1.0 + m.cwiseAbs().maxCoeff()))
    return false;
  const double lowest = smallestEigenvalue(m - floor);
  return strictly ? lowest > 0.0 : lowest >= -1e-12;
}

}  // namespace

void requireSymmetricPositive(const Matrix6& m, const char* name, bool semidefinite) {
  if (!m.allFinite()) throw std::invalid_argument(std::string("VariableAdmittance: ") + name + " has a value that is not finite");
  if ((m - m.transpose()).cwiseAbs().maxCoeff() > kSymmetryTolerance * (1.0 + m.cwiseAbs().maxCoeff()))
    throw std::invalid_argument(std::string("VariableAdmittance: ") + name + " must be symmetric");
  const double lowest = smallestEigenvalue(m);
  if (semidefinite ? lowest < -1e-12 : lowest <= 0.0)
    throw std::invalid_argument(std::string("VariableAdmittance: ") + name + " must be positive " +
                                (semidefinite ? "semidefinite" : "definite") + " (smallest eigenvalue " +
                                std::to_string(lowest) + ")");
}

VariableAdmittance::VariableAdmittance(const AdmittanceParameters& p) : parameters_(p) {
  requireSymmetricPositive(p.constant_inertia, "constant_inertia (kg, kg·m²)", false);
  requireSymmetricPositive(p.constant_stiffness, "constant_stiffness (N/m, N·m/rad)", true);
  requireSymmetricPositive(p.damping, "damping (N·s/m, N·m·s/rad)", false);
  if (!symmetricAtLeast(p.inertia, p.constant_inertia, false))
    throw std::invalid_argument("VariableAdmittance: inertia must be symmetric and at least constant_inertia (Λd ≥ Λc)");
  if (!symmetricAtLeast(p.stiffness, p.constant_stiffness, false))
    throw std::invalid_argument("VariableAdmittance: stiffness must be symmetric and at least constant_stiffness (Kd ≥ Kc)");
  const TankParameters& t = p.tank;
  if (!(t.min_energy > 0.0) || !(t.initial_energy > t.min_energy) || !(t.max_energy >= t.initial_energy))
    throw std::invalid_argument("VariableAdmittance: tank energies must satisfy 0 < min_energy < initial_energy <= "
                                "max_energy (J), got " + std::to_string(t.min_energy) + ", " +
                                std::to_string(t.initial_energy) + ", " + std::to_string(t.max_energy));
  reset();
}

void VariableAdmittance::reset() noexcept {
  x_.setZero();
  v_.setZero();
  tank_ = parameters_.tank.initial_energy;
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
  return AdmittanceStatus::Ok;
}

double VariableAdmittance::constantEnergy(const Vector6& x, const Vector6& v) const noexcept {
  return 0.5 * v.dot(parameters_.constant_inertia * v) + 0.5 * x.dot(parameters_.constant_stiffness * x);
}

void VariableAdmittance::integrate(const Matrix6& M, const Matrix6& K, const Vector6& force, double dt,
                                   Vector6& x_next, Vector6& v_next) const noexcept {
  const Matrix6 system = M + dt * parameters_.damping + dt * dt * K;
  const Vector6 rhs = M * v_ + dt * (force - K * x_);
  v_next = Eigen::LLT<Matrix6>(system).solve(rhs);
  x_next = x_ + dt * v_next;
}

AdmittanceStatus VariableAdmittance::step(const KDL::Frame& reference, const KDL::Twist& reference_twist,
                                          const KDL::Wrench& wrench, double dt, KDL::Frame& pose,
                                          KDL::Twist& twist) noexcept {
  if (!(dt > 0.0) || !std::isfinite(dt) || !finite(reference.p) || !finite(wrench.force) || !finite(wrench.torque) ||
      !finite(reference_twist.vel) || !finite(reference_twist.rot))
    return AdmittanceStatus::BadInput;
  // Generalised force conjugate to x̃: force in the base frame, torque in the reference's axes.
  const KDL::Vector torque = reference.M.Inverse(wrench.torque);
  Vector6 force;
  force << wrench.force.x(), wrench.force.y(), wrench.force.z(), torque.x(), torque.y(), torque.z();

  const double sigma = tank_ <= parameters_.tank.max_energy ? 1.0 : 0.0;  // eq. 4.7
  const double energy_before = constantEnergy(x_, v_);
  Vector6 x_next, v_next;
  integrate(parameters_.inertia, parameters_.stiffness, force, dt, x_next, v_next);
  const Matrix6 variable_inertia = parameters_.inertia - parameters_.constant_inertia;
  const Matrix6 variable_stiffness = parameters_.stiffness - parameters_.constant_stiffness;
  Vector6 w = -variable_stiffness * x_next - variable_inertia * ((v_next - v_) / dt);  // eq. 4.11
  Vector6 dx = x_next - x_;
  double delta = (force + w).dot(dx) - (constantEnergy(x_next, v_next) - energy_before);
  double tank_next = tank_ + sigma * delta - w.dot(dx);
  AdmittanceStatus status = AdmittanceStatus::Ok;
  if (parameters_.use_tank && tank_next < parameters_.tank.min_energy) {
    // The tank cannot pay for w: implement the constant parts only (w = 0).
    integrate(parameters_.constant_inertia, parameters_.constant_stiffness, force, dt, x_next, v_next);
    w.setZero();
    dx = x_next - x_;
    delta = force.dot(dx) - (constantEnergy(x_next, v_next) - energy_before);
    tank_next = tank_ + sigma * delta;
    status = AdmittanceStatus::TankEmpty;
  }
  audit_.from_environment += force.dot(dx);
  audit_.dissipated += delta;
  audit_.injected_by_w += w.dot(dx);
  x_ = x_next;
  v_ = v_next;
  tank_ = tank_next;
  audit_.stored = constantEnergy(x_, v_);
  audit_.tank = tank_;

  pose.p = reference.p + KDL::Vector(x_(0), x_(1), x_(2));
  pose.M = reference.M * expRotation(x_);
  twist.vel = reference_twist.vel + KDL::Vector(v_(0), v_(1), v_(2));
  twist.rot = reference_twist.rot + reference.M * KDL::Vector(v_(3), v_(4), v_(5));  // exact for small errors
  return status;
}

}  // namespace cobra::control
