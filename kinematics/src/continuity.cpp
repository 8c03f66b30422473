#include "cobra/kinematics/continuity.hpp"

#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

namespace cobra::kinematics {

namespace {

/// A step this much above the allowed one is still accepted: max_velocity · dt computed by the
/// caller from a clock and the solver's rounding must not refuse a command exactly at the limit.
constexpr double kRelativeSlack = 1e-9;
constexpr double kAbsoluteSlack = 1e-12;  // rad / m

}  // namespace

void validateMaxVelocity(std::string_view robot, const JointLimits& limits, const std::vector<double>& max_velocity) {
  const std::string who(robot);
  if (max_velocity.size() != limits.size())
    throw std::invalid_argument(who + ": max_velocity has " + std::to_string(max_velocity.size()) +
                                " values; the robot has " + std::to_string(limits.size()) +
                                " joints: give one limit per joint (rad/s, m/s)");
  for (std::size_t i = 0; i < max_velocity.size(); ++i) {
    if (!(std::isfinite(max_velocity[i]) && max_velocity[i] > 0.0))
      throw std::invalid_argument(who + ": max_velocity of joint " + std::to_string(i + 1) + " is " +
                                  formatNumber(max_velocity[i]) + " " + unitOf(limits.types[i]) +
                                  "/s: give a finite value > 0");
  }
}

IkStatus checkJointSteps(const KDL::JntArray& candidate, const KDL::JntArray& current,
                         const std::vector<double>& max_velocity, double dt, ContinuityRefusal& refusal) noexcept {
  // The joint that exceeds its step by the largest factor is the one reported.
  int worst = -1;
  double worst_ratio = 1.0;
  for (unsigned j = 0; j < candidate.rows(); ++j) {
    const double allowed = max_velocity[j] * dt;
    const double step = std::abs(candidate.data(j) - current.data(j));
    if (step <= allowed * (1.0 + kRelativeSlack) + kAbsoluteSlack) continue;
    const double ratio = step / allowed;
    if (ratio > worst_ratio) {
      worst_ratio = ratio;
      worst = static_cast<int>(j);
    }
  }
  if (worst < 0) return IkStatus::Ok;
  const auto j = static_cast<unsigned>(worst);
  refusal = ContinuityRefusal{.branch_change = false,
                              .joint = worst,
                              .step = std::abs(candidate.data(j) - current.data(j)),
                              .allowed = max_velocity[j] * dt};
  return IkStatus::Discontinuous;
}

ContinuousIk::ContinuousIk(KinematicsSolver& solver, std::vector<double> max_velocity, double period)
    : solver_(solver), max_velocity_(std::move(max_velocity)), period_(period), candidate_(solver.jointCount()) {
  validateMaxVelocity(solver.name(), solver.limits(), max_velocity_);
  if (!(std::isfinite(period_) && period_ > 0.0))
    throw std::invalid_argument(std::string(solver.name()) + ": continuity period is " + formatNumber(period_) +
                                " s: give a finite value > 0");
}

IkStatus ContinuousIk::solve(const KDL::Frame& target, const KDL::JntArray& current, KDL::JntArray& q_out) noexcept {
  return solve(target, current, period_, q_out);
}

IkStatus ContinuousIk::solve(const KDL::Frame& target, const KDL::JntArray& current, double dt,
                             KDL::JntArray& q_out) noexcept {
  const unsigned n = solver_.jointCount();
  if (!(std::isfinite(dt) && dt > 0.0) || !validJointArray(current, n) || q_out.rows() != n) return IkStatus::BadInput;
  const std::span<const double> current_values(current.data.data(), n);
  const IkStatus status = solver_.inverseOnBranch(target, current, solver_.branch(current_values), candidate_);
  if (status == IkStatus::Discontinuous) {
    refusal_ = ContinuityRefusal{.branch_change = true, .joint = -1, .step = 0.0, .allowed = 0.0};
    return status;
  }
  if (status != IkStatus::Ok) return status;
  if (checkJointSteps(candidate_, current, max_velocity_, dt, refusal_) != IkStatus::Ok) return IkStatus::Discontinuous;
  for (unsigned j = 0; j < n; ++j) q_out.data(j) = candidate_.data(j);
  return IkStatus::Ok;
}

}  // namespace cobra::kinematics
