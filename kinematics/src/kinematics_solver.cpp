#include "cobra/kinematics/kinematics_solver.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace cobra::kinematics {

bool validJointArray(const KDL::JntArray& q, unsigned joints) noexcept {
  if (q.rows() != joints) return false;
  for (unsigned i = 0; i < joints; ++i) {
    if (!std::isfinite(q(i))) return false;
  }
  return true;
}

bool validFrame(const KDL::Frame& frame) noexcept {
  constexpr double kOrthonormalityTolerance = 1e-6;
  for (int i = 0; i < 3; ++i) {
    if (!std::isfinite(frame.p(i))) return false;
    for (int j = 0; j < 3; ++j) {
      if (!std::isfinite(frame.M(i, j))) return false;
    }
  }
  // RᵀR = I, and det(R) = +1 (a reflection is not a pose).
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      double dot = 0.0;
      for (int k = 0; k < 3; ++k) dot += frame.M(k, i) * frame.M(k, j);
      if (std::abs(dot - (i == j ? 1.0 : 0.0)) > kOrthonormalityTolerance) return false;
    }
  }
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
