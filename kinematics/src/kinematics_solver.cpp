#include "cobra/kinematics/kinematics_solver.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace cobra::kinematics {

bool validJointArray(const KDL::JntArray& q, unsigned joints) noexcept {
  // On the control path (every IK and FK call, twice per robot and step): the values through
  // their pointer, not KDL's JntArray::operator() (a call into the shared library per element).
  if (q.rows() != joints) return false;
  const double* v = q.data.data();
  for (unsigned i = 0; i < joints; ++i) {
    if (!std::isfinite(v[i])) return false;
  }
  return true;
}

bool validFrame(const KDL::Frame& frame) noexcept {
  constexpr double kOrthonormalityTolerance = 1e-6;
  // Written out (the loops it replaces were not unrolled: ~350 instructions per call on the
  // control path); the same products in the same order, so the same decisions.
  const double* m = frame.M.data;  // row-major: m[3 * row + column]
  const double* p = frame.p.data;
  for (int i = 0; i < 3; ++i)
    if (!std::isfinite(p[i])) return false;
  for (int i = 0; i < 9; ++i)
    if (!std::isfinite(m[i])) return false;
  // RᵀR = I (column i · column j), and det(R) = +1 (a reflection is not a pose).
  const auto column_dot = [m](int i, int j) { return m[i] * m[j] + m[3 + i] * m[3 + j] + m[6 + i] * m[6 + j]; };
  const auto off = [](double dot, double expected) { return std::abs(dot - expected) > kOrthonormalityTolerance; };
  if (off(column_dot(0, 0), 1.0) || off(column_dot(1, 1), 1.0) || off(column_dot(2, 2), 1.0) ||
      off(column_dot(0, 1), 0.0) || off(column_dot(0, 2), 0.0) || off(column_dot(1, 2), 0.0))
    return false;
  const KDL::Vector x = frame.M.UnitX();
  const KDL::Vector y = frame.M.UnitY();
  return KDL::dot(x * y, frame.M.UnitZ()) > 0.0;
}

SolverKind parseSolverKind(std::string_view text) {
  if (text == "closed_form") return SolverKind::ClosedForm;
  if (text == "kdl_nr") return SolverKind::KdlNewtonRaphson;
  if (text == "kdl_lma") return SolverKind::KdlLevenbergMarquardt;
  throw std::invalid_argument("unknown kinematics solver \"" + std::string(text) +
                              "\": expected closed_form, kdl_nr or kdl_lma");
}

IkBranch KinematicsSolver::branch(std::span<const double> /*q*/) const noexcept { return IkBranch{}; }

IkStatus KinematicsSolver::inverseOnBranch(const KDL::Frame& target, const KDL::JntArray& seed, IkBranch /*branch*/,
                                           KDL::JntArray& q_out) noexcept {
  return inverse(target, seed, q_out);
}

IkStatus AnalyticSolver::inverse(const KDL::Frame& target, const KDL::JntArray& seed, KDL::JntArray& q_out) noexcept {
  return inverseOnBranch(target, seed, IkBranch::any(), q_out);
}

IkStatus AnalyticSolver::inverseOnBranch(const KDL::Frame& target, const KDL::JntArray& seed, IkBranch branch,
                                         KDL::JntArray& q_out) noexcept {
  if (q_out.rows() != jointCount()) return IkStatus::BadInput;
  // allInverse checks the target and the seed.
  const IkStatus status = allInverse(target, seed, scratch_);
  if (status != IkStatus::Ok) return status;
  return selectNearest(scratch_, limits(), seed, q_out, branch);
}

}  // namespace cobra::kinematics
