#include "cobra/kinematics/types.hpp"

#include <charconv>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

namespace cobra::kinematics {

const char* toString(IkStatus status) noexcept {
  switch (status) {
    case IkStatus::Ok:
      return "ok";
    case IkStatus::Unreachable:
      return "unreachable";
    case IkStatus::JointLimits:
      return "joint limits";
    case IkStatus::Singular:
      return "singular";
    case IkStatus::NoConvergence:
      return "no convergence";
    case IkStatus::BadInput:
      return "bad input";
    case IkStatus::Discontinuous:
      return "discontinuous";
  }
  return "unknown";
}

const char* unitOf(JointType type) noexcept { return type == JointType::Revolute ? "rad" : "m"; }

bool JointLimits::contains(std::span<const double> q, double tolerance) const noexcept {
  if (q.size() != lower.size()) return false;
  for (std::size_t i = 0; i < q.size(); ++i) {
    if (!(q[i] >= lower[i] - tolerance && q[i] <= upper[i] + tolerance)) return false;
  }
  return true;
}

bool JointLimits::contains(const KDL::JntArray& q, double tolerance) const noexcept {
  return contains(std::span<const double>(q.data.data(), q.rows()), tolerance);
}

std::string formatNumber(double value) {
  std::array<char, 32> buffer{};
  const auto result = std::to_chars(buffer.data(), buffer.data() + buffer.size(), value);
  return std::string(buffer.data(), result.ptr);
}

void validateLimits(std::string_view robot, const JointLimits& limits, std::size_t expected_joints) {
  const std::string who(robot);
  if (limits.lower.size() != expected_joints || limits.upper.size() != expected_joints ||
      limits.types.size() != expected_joints) {
    throw std::invalid_argument(who + ": joint limits have " + std::to_string(limits.lower.size()) + " lower, " +
                                std::to_string(limits.upper.size()) + " upper bounds and " +
                                std::to_string(limits.types.size()) + " joint types; the robot has " +
                                std::to_string(expected_joints) + " joints: give one of each per joint");
  }
  for (std::size_t i = 0; i < expected_joints; ++i) {
    const std::string range =
        "[" + formatNumber(limits.lower[i]) + ", " + formatNumber(limits.upper[i]) + "] " + unitOf(limits.types[i]);
    const std::string joint = who + ": joint " + std::to_string(i + 1) + " limits " + range;
    if (!std::isfinite(limits.lower[i]) || !std::isfinite(limits.upper[i]))
      throw std::invalid_argument(joint + ": both bounds must be finite numbers");
    if (limits.lower[i] > limits.upper[i]) throw std::invalid_argument(joint + ": min must be <= max");
  }
}

JointLimits revoluteLimits(std::size_t joints, double lower, double upper) {
  return JointLimits{std::vector<JointType>(joints, JointType::Revolute), std::vector<double>(joints, lower),
                     std::vector<double>(joints, upper)};
}

void IkSolutionSet::reset(std::size_t joints) noexcept {
  count_ = 0;
  joints_ = joints < kMaxJoints ? joints : kMaxJoints;
}

bool IkSolutionSet::push(std::span<const double> q, IkBranch branch) noexcept {
  if (count_ == kMaxSolutions || q.size() != joints_) return false;
  for (std::size_t j = 0; j < joints_; ++j) solutions_[count_][j] = q[j];
  branches_[count_] = branch;
  ++count_;
  return true;
}

void IkSolutionSet::copyTo(std::size_t i, KDL::JntArray& q) const {
  if (q.rows() != joints_) q.resize(static_cast<unsigned>(joints_));
  for (std::size_t j = 0; j < joints_; ++j) q(static_cast<unsigned>(j)) = solutions_[i][j];
}

double wrapToPi(double angle) noexcept {
  constexpr double kTwoPi = 2.0 * std::numbers::pi;
  double wrapped = std::remainder(angle, kTwoPi);  // in [-π, π]
  if (wrapped <= -std::numbers::pi) wrapped += kTwoPi;
  return wrapped;
}

namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;
/// rad: a solution exactly on a limit stays valid.
constexpr double kLimitTolerance = 1e-12;

/// `best` (outside [lo, hi]) moved by the multiple of 2π that brings it nearest inside; false when
/// none fits.
bool stepIntoLimits(double best, double lo, double hi, double& out) noexcept {
  if (best < lo) {
    best += kTwoPi * std::ceil((lo - best) / kTwoPi);
  } else {
    best -= kTwoPi * std::ceil((best - hi) / kTwoPi);
  }
  if (best < lo || best > hi) return false;
  out = best;
  return true;
}

/// The representative q + 2πk inside [lower, upper] (widened by kLimitTolerance) nearest to
/// `seed`, into `out`; false when none fits. Revolute joints only. Solutions and seeds are
/// usually within a few turns of each other: a short loop then replaces the libm rounding calls
/// (std::round, std::ceil are not inlined on baseline x86-64), which dominated the selection.
inline bool nearestRepresentative(double q, double seed, double lower, double upper, double& out) noexcept {
  double best = q;
  const double gap = seed - q;
  if (gap > std::numbers::pi || gap < -std::numbers::pi) {
    if (!(std::abs(gap) <= 4.0 * kTwoPi)) {
      best = q + kTwoPi * std::round(gap / kTwoPi);
    } else {
      while (best - seed > std::numbers::pi) best -= kTwoPi;
      while (seed - best > std::numbers::pi) best += kTwoPi;
    }
  }
  const double lo = lower - kLimitTolerance;
  const double hi = upper + kLimitTolerance;
  if (best >= lo && best <= hi) {
    out = best;
    return true;
  }
  // Outside: the nearest representative inside lies on the side of the limits.
  return stepIntoLimits(best, lo, hi, out);
}

}  // namespace

bool wrapIntoLimits(std::span<double> q, const JointLimits& limits, std::span<const double> seed) noexcept {
  for (std::size_t j = 0; j < q.size(); ++j) {
    if (limits.types[j] == JointType::Prismatic) {
      if (q[j] < limits.lower[j] - kLimitTolerance || q[j] > limits.upper[j] + kLimitTolerance) return false;
      continue;
    }
    if (!nearestRepresentative(q[j], seed[j], limits.lower[j], limits.upper[j], q[j])) return false;
  }
  return true;
}

IkStatus selectNearest(const IkSolutionSet& solutions, const JointLimits& limits, const KDL::JntArray& seed,
                       KDL::JntArray& out, IkBranch branch) noexcept {
  const std::size_t n = solutions.jointCount();
  if (seed.rows() != n || out.rows() != n || limits.size() != n || n > IkSolutionSet::kMaxJoints)
    return IkStatus::BadInput;
  if (solutions.empty()) return IkStatus::Unreachable;
  const double* seed_values = seed.data.data();
  // Writes solution i's representatives nearest to the seed into `values` and returns the squared
  // distance, or stops (returning a value >= `bound`) as soon as it exceeds `bound`; -1 when a
  // joint has no representative in its limits.
  const auto measure = [&](std::size_t i, double bound, double* values) noexcept {
    const auto solution = solutions[i];
    double distance = 0.0;
    for (std::size_t j = 0; j < n; ++j) {
      double& value = values[j];
      if (limits.types[j] == JointType::Prismatic) {
        value = solution[j];
        if (value < limits.lower[j] - kLimitTolerance || value > limits.upper[j] + kLimitTolerance) return -1.0;
      } else if (!nearestRepresentative(solution[j], seed_values[j], limits.lower[j], limits.upper[j], value)) {
        return -1.0;
      }
      distance += (value - seed_values[j]) * (value - seed_values[j]);
      if (distance >= bound) return distance;
    }
    return distance;
  };
  std::array<double, IkSolutionSet::kMaxJoints> scratch{};
  std::size_t best = solutions.size();
  double best_distance = std::numeric_limits<double>::infinity();
  bool any_in_limits = false;
  for (std::size_t i = 0; i < solutions.size(); ++i) {
    const bool on_branch = branch.compatibleWith(solutions.branch(i));
    // Off the branch, a solution only matters to tell Discontinuous from JointLimits.
    if (!on_branch && any_in_limits) continue;
    // Once some solution fits, a candidate farther than the best cannot win (limits aside).
    const double bound = on_branch && any_in_limits ? best_distance : std::numeric_limits<double>::infinity();
    const double distance = measure(i, bound, scratch.data());
    if (distance < 0.0) continue;
    any_in_limits = true;
    if (on_branch && distance < best_distance) {
      best_distance = distance;
      best = i;
    }
  }
  if (best == solutions.size()) return any_in_limits ? IkStatus::Discontinuous : IkStatus::JointLimits;
  measure(best, std::numeric_limits<double>::infinity(), scratch.data());
  for (std::size_t j = 0; j < n; ++j) out(static_cast<unsigned>(j)) = scratch[j];
  return IkStatus::Ok;
}

}  // namespace cobra::kinematics
