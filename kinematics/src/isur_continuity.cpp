#include "cobra/kinematics/isur_continuity.hpp"

#include <cmath>
#include <span>
#include <stdexcept>
#include <string>
#include <utility>

namespace cobra::kinematics {

namespace {
constexpr const char* kRobot = "I-SUR suturing";
}  // namespace

ContinuousIsurSuturingIk::ContinuousIsurSuturingIk(IsurSuturingSolver& solver, std::vector<double> max_velocity,
                                                   double period)
    : solver_(solver),
      max_velocity_(std::move(max_velocity)),
      period_(period),
      candidate_(IsurSuturingSolver::kJoints) {
  validateMaxVelocity(kRobot, solver.limits(), max_velocity_);
  if (!(std::isfinite(period_) && period_ > 0.0))
    throw std::invalid_argument(std::string(kRobot) + ": continuity period is " + formatNumber(period_) +
                                " s: give a finite value > 0");
}

IkStatus ContinuousIsurSuturingIk::solve(const KDL::Frame& stitch_target, const KDL::Frame& gripper_target,
                                         const KDL::JntArray& current, KDL::JntArray& q_out) noexcept {
  return solve(stitch_target, gripper_target, current, period_, q_out);
}

IkStatus ContinuousIsurSuturingIk::solve(const KDL::Frame& stitch_target, const KDL::Frame& gripper_target,
                                         const KDL::JntArray& current, double dt, KDL::JntArray& q_out) noexcept {
  constexpr unsigned n = IsurSuturingSolver::kJoints;
  if (!(std::isfinite(dt) && dt > 0.0) || !validJointArray(current, n) || q_out.rows() != n) return IkStatus::BadInput;
  // Each sub-structure in turn (§5.4.1), each with the rule: the Endo Stitch arm on its branch
  // within the bound (the gripper arm held at the current joints), then the gripper arm from the
  // platform that gives, on its branch, and every joint within the bound. A swing of the Endo
  // Stitch arm is refused as such even when the gripper could not follow the platform anyway.
  const IkBranch branch = solver_.branch(std::span<const double>(current.data.data(), n));
  for (const bool gripper_arm : {false, true}) {
    const IkStatus status =
        gripper_arm ? solver_.inverseGripperArm(gripper_target, candidate_, IsurSuturingSolver::leftBranch(branch),
                                                candidate_)
                    : solver_.inverseEndoStitchArm(stitch_target, current, IsurSuturingSolver::rightBranch(branch),
                                                   candidate_);
    if (status == IkStatus::Discontinuous) {
      refusal_ = ContinuityRefusal{.branch_change = true, .joint = -1, .step = 0.0, .allowed = 0.0};
      return status;
    }
    if (status != IkStatus::Ok) return status;
    if (checkJointSteps(candidate_, current, max_velocity_, dt, refusal_) != IkStatus::Ok)
      return IkStatus::Discontinuous;
  }
  for (unsigned j = 0; j < n; ++j) q_out(j) = candidate_(j);
  return IkStatus::Ok;
}

}  // namespace cobra::kinematics
