#include "cobra/planning/robot_adapters.hpp"

#include "cobra/kinematics/geometry.hpp"

#include <cmath>
#include <initializer_list>
#include <limits>
#include <memory>
#include <numbers>
#include <stdexcept>
#include <string>

namespace cobra::planning {

namespace {

using kinematics::IkStatus;

void requireSeed(const KDL::JntArray& q, unsigned joints, const char* robot) {
  bool finite = q.rows() == joints;
  for (unsigned i = 0; finite && i < joints; ++i) finite = std::isfinite(q(i));
  if (!finite)
    throw std::invalid_argument(std::string(robot) + " model: the seed must hold " + std::to_string(joints) +
                                " finite joint values (got " + std::to_string(q.rows()) + ")");
}

KDL::JntArray jointArray(std::initializer_list<double> values) {
  KDL::JntArray q(static_cast<unsigned>(values.size()));
  unsigned i = 0;
  for (const double v : values) q(i++) = v;
  return q;
}

/// Tool poses closer than this to the previous one warm-start from its solution (a step along a
/// path or an edge); farther ones start from the configured seed, so that the answer for a pose
/// does not depend on unrelated poses checked before it (random planner samples).
constexpr double kWarmStartDistance = 0.02;  // m
constexpr double kWarmStartAngle = 0.2;      // rad

bool near(const KDL::Frame& a, const KDL::Frame& b) {
  KDL::Vector axis;
  return (a.p - b.p).Norm() < kWarmStartDistance && (a.M.Inverse() * b.M).GetRotAngle(axis) < kWarmStartAngle;
}

}  // namespace

template <std::size_t Tools>
WarmStart<Tools>::WarmStart(unsigned joints, const KDL::JntArray& seed, const char* robot)
    : robot_(robot), initial_(joints), seed_(joints) {
  setSeed(seed);
}

template <std::size_t Tools>
void WarmStart<Tools>::setSeed(const KDL::JntArray& q) {
  requireSeed(q, initial_.rows(), robot_);
  seed_ = q;
  initial_ = q;
  has_previous_ = false;
}

template <std::size_t Tools>
const KDL::JntArray& WarmStart<Tools>::seedFor(std::span<const KDL::Frame> tools) noexcept {
  bool warm = has_previous_;
  for (std::size_t i = 0; warm && i < Tools; ++i) warm = near(tools[i], previous_[i]);
  if (!warm) seed_.data = initial_.data;
  return seed_;
}

template <std::size_t Tools>
void WarmStart<Tools>::keep(const KDL::JntArray& q, std::span<const KDL::Frame> tools) noexcept {
  seed_.data = q.data;
  for (std::size_t i = 0; i < Tools; ++i) previous_[i] = tools[i];
  has_previous_ = true;
}

template class WarmStart<1>;
template class WarmStart<2>;

KDL::JntArray Ur5Model::defaultSeed() { return jointArray({0.5, -1.9, -1.7, 2.0, -1.5708, 0.0}); }

Ur5Model::Ur5Model(const KDL::Frame& probe, const KDL::JntArray& seed, const kinematics::Ur5Parameters& parameters)
    : solver_(parameters, kinematics::Ur5Solver::defaultLimits(), KDL::Frame::Identity(), probe),
      warm_(6, seed, "UR5"),
      q_(6) {}

Reachability Ur5Model::solve(std::span<const KDL::Frame> tools_in_base, std::span<KDL::Frame> links_in_base) {
  const KDL::JntArray& seed = warm_.seedFor(tools_in_base);
  const KDL::JntArray& initial = warm_.initial();
  if (solver_.allInverse(tools_in_base[0], seed, solutions_) != IkStatus::Ok) return Reachability::Unreachable;
  // The branch of the configured seed: elbow (sign of q3) and wrist (sign of q5) as in `initial`,
  // shoulder (the two q1 solutions) nearest to its q1. A value at 0 (arm stretched, wrist
  // singular) belongs to both sides.
  const auto sameSide = [](double value, double reference) {
    return value == 0.0 || (value > 0.0) == (reference > 0.0);
  };
  std::size_t best = solutions_.size();
  double best_shoulder = std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < solutions_.size(); ++k) {
    const std::span<const double> q = solutions_[k];
    if (!sameSide(q[2], initial(2)) || !sameSide(q[4], initial(4))) continue;
    const double shoulder = std::abs(kinematics::wrapToPi(q[0] - initial(0)));
    if (shoulder < best_shoulder) {
      best_shoulder = shoulder;
      best = k;
    }
  }
  if (best == solutions_.size()) return Reachability::Unreachable;
  // Warm start: each joint's representative (q + 2 pi k, within the limits) nearest to the previous solution.
  const kinematics::JointLimits& limits = solver_.limits();
  const std::span<const double> q = solutions_[best];
  for (unsigned j = 0; j < 6; ++j) {
    double value = seed(j) + kinematics::wrapToPi(q[j] - seed(j));
    if (value > limits.upper[j]) value -= 2.0 * std::numbers::pi;
    if (value < limits.lower[j]) value += 2.0 * std::numbers::pi;
    if (value > limits.upper[j] || value < limits.lower[j]) return Reachability::Unreachable;
    q_(j) = value;
  }
  if (!solver_.model().linkFrames(std::span<const double>(q_.data.data(), 6), links_in_base))
    return Reachability::Unreachable;
  warm_.keep(q_, tools_in_base);
  return Reachability::Reachable;
}

KDL::JntArray IsurPuncturingModel::defaultSeed() { return jointArray({0.1, 0.1, 0.1, 0.0, 0.0, 0.0, 0.0, 0.0}); }

IsurPuncturingModel::IsurPuncturingModel(const kinematics::IsurGeometry& geometry, const KDL::JntArray& seed)
    : solver_(geometry),
      warm_(kinematics::IsurPuncturingSolver::kJoints, seed, "I-SUR"),
      q_(kinematics::IsurPuncturingSolver::kJoints) {}

Reachability IsurPuncturingModel::solve(std::span<const KDL::Frame> tools_in_base,
                                        std::span<KDL::Frame> links_in_base) {
  if (solver_.inverse(tools_in_base[0], warm_.seedFor(tools_in_base), q_) != IkStatus::Ok)
    return Reachability::Unreachable;
  if (solver_.linkFrames(q_, links_in_base) != IkStatus::Ok) return Reachability::Unreachable;
  warm_.keep(q_, tools_in_base);
  return Reachability::Reachable;
}

KDL::JntArray IsurSuturingModel::defaultSeed() {
  return jointArray({0.1, 0.1, 0.1, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.5, -0.5, 0.0, 0.5, 0.0});
}

IsurSuturingModel::IsurSuturingModel(const kinematics::IsurSuturingGeometry& geometry, const KDL::JntArray& seed)
    : solver_(geometry),
      warm_(kinematics::IsurSuturingSolver::kJoints, seed, "I-SUR suturing"),
      q_(kinematics::IsurSuturingSolver::kJoints) {}

Reachability IsurSuturingModel::solve(std::span<const KDL::Frame> tools_in_base, std::span<KDL::Frame> links_in_base) {
  if (solver_.inverse(tools_in_base[0], tools_in_base[1], warm_.seedFor(tools_in_base), q_) != IkStatus::Ok)
    return Reachability::Unreachable;
  if (solver_.linkFrames(q_, links_in_base) != IkStatus::Ok) return Reachability::Unreachable;
  warm_.keep(q_, tools_in_base);
  return Reachability::Reachable;
}

RobotModels makeRobotModels(const SceneDescription& scene) {
  RobotModels models;
  for (const RobotPlacement& robot : scene.robots) {
    if (robot.name == "ur5" && robot.tool_indices.size() == 1) {
      models.emplace(robot.name, std::make_shared<Ur5Model>());
    } else if (robot.name == "isur" && robot.tool_indices.size() == 1) {
      models.emplace(robot.name, std::make_shared<IsurPuncturingModel>());
    } else if (robot.name == "isur" && robot.tool_indices.size() == 2) {
      models.emplace(robot.name, std::make_shared<IsurSuturingModel>());
    } else {
      throw std::invalid_argument("robot models: no kinematics for robot '" + robot.name + "' with " +
                                  std::to_string(robot.tool_indices.size()) +
                                  " tool(s): use 'ur5' (1 tool) or 'isur' (1 tool: puncturing, 2: suturing)");
    }
  }
  return models;
}

}  // namespace cobra::planning
