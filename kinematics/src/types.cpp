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

bool IkSolutionSet::push(std::span<const double> q) noexcept {
  if (count_ == kMaxSolutions || q.size() != joints_) return false;
  for (std::size_t j = 0; j < joints_; ++j) solutions_[count_][j] = q[j];
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

bool wrapIntoLimits(std::span<double> q, const JointLimits& limits, std::span<const double> seed) noexcept {
  constexpr double kTwoPi = 2.0 * std::numbers::pi;
  constexpr double kTolerance = 1e-12;  // rad: a solution exactly on a limit stays valid
  for (std::size_t j = 0; j < q.size(); ++j) {
    const double lo = limits.lower[j] - kTolerance;
    const double hi = limits.upper[j] + kTolerance;
    if (limits.types[j] == JointType::Prismatic) {
      if (q[j] < lo || q[j] > hi) return false;
      continue;
    }
    // Nearest representative q + 2πk to the seed, then step towards the limits if it is outside.
    double best = q[j] + kTwoPi * std::round((seed[j] - q[j]) / kTwoPi);
    if (best < lo) best += kTwoPi * std::ceil((lo - best) / kTwoPi);
    if (best > hi) best -= kTwoPi * std::ceil((best - hi) / kTwoPi);
    if (best < lo || best > hi) return false;
    // The representative one period away may be nearer to the seed and still inside.
    for (const double other : {best - kTwoPi, best + kTwoPi}) {
      if (other >= lo && other <= hi && std::abs(other - seed[j]) < std::abs(best - seed[j])) best = other;
    }
    q[j] = best;
  }
  return true;
}

IkStatus selectNearest(const IkSolutionSet& solutions, const JointLimits& limits, const KDL::JntArray& seed,
                       KDL::JntArray& out) noexcept {
  const std::size_t n = solutions.jointCount();
  if (seed.rows() != n || out.rows() != n || limits.size() != n || n > IkSolutionSet::kMaxJoints)
    return IkStatus::BadInput;
  if (solutions.empty()) return IkStatus::Unreachable;
  const std::span<const double> seed_values(seed.data.data(), n);
  std::array<double, IkSolutionSet::kMaxJoints> candidate{};
  std::array<double, IkSolutionSet::kMaxJoints> best{};
  double best_distance = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < solutions.size(); ++i) {
    const auto solution = solutions[i];
    for (std::size_t j = 0; j < n; ++j) candidate[j] = solution[j];
    if (!wrapIntoLimits(std::span<double>(candidate.data(), n), limits, seed_values)) continue;
    double distance = 0.0;
    for (std::size_t j = 0; j < n; ++j) distance += (candidate[j] - seed_values[j]) * (candidate[j] - seed_values[j]);
    if (distance < best_distance) {
      best_distance = distance;
      best = candidate;
    }
  }
  if (!std::isfinite(best_distance)) return IkStatus::JointLimits;
  for (std::size_t j = 0; j < n; ++j) out(static_cast<unsigned>(j)) = best[j];
  return IkStatus::Ok;
}

}  // namespace cobra::kinematics
