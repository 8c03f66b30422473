#include "cobra/planning/robot_adapters.hpp"

#include "cobra/kinematics/geometry.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>
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

/// One singular set's side: `at` (the signed distance of a state to it) on the side of `start`'s
/// and at least `margin` from it, or half the start's or goal's distance when that is smaller.
bool sameSide(double at, double start, double goal, double margin) {
  const double needed = std::min({margin, 0.5 * std::abs(start), 0.5 * std::abs(goal)});
  return (start >= 0.0 ? at : -at) >= needed;
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
      q_(6),
      seed_(6) {}

Reachability Ur5Model::pickBranch(std::span<const double> reference, std::span<const double> near,
                                  std::span<double> q_out) const {
  // Elbow (sign of q3) and wrist (sign of q5) as in `reference`, shoulder (the two q1 solutions)
  // nearest to its q1. A value at 0 (arm stretched, wrist singular) belongs to both sides.
  const auto sameSide = [](double value, double reference_value) {
    return value == 0.0 || (value > 0.0) == (reference_value > 0.0);
  };
  std::size_t best = solutions_.size();
  double best_shoulder = std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < solutions_.size(); ++k) {
    const std::span<const double> q = solutions_[k];
    if (!sameSide(q[2], reference[2]) || !sameSide(q[4], reference[4])) continue;
    const double shoulder = std::abs(kinematics::wrapToPi(q[0] - reference[0]));
    if (shoulder < best_shoulder) {
      best_shoulder = shoulder;
      best = k;
    }
  }
  if (best == solutions_.size()) return solutions_.size() > 0 ? Reachability::OtherBranch : Reachability::Unreachable;
  // Each joint's representative (q + 2 pi k, within the limits) nearest to `near`.
  const kinematics::JointLimits& limits = solver_.limits();
  const std::span<const double> q = solutions_[best];
  for (unsigned j = 0; j < 6; ++j) {
    double value = near[j] + kinematics::wrapToPi(q[j] - near[j]);
    if (value > limits.upper[j]) value -= 2.0 * std::numbers::pi;
    if (value < limits.lower[j]) value += 2.0 * std::numbers::pi;
    if (value > limits.upper[j] || value < limits.lower[j]) return Reachability::Unreachable;
    q_out[j] = value;
  }
  return Reachability::Reachable;
}

Reachability Ur5Model::solve(std::span<const KDL::Frame> tools_in_base, std::span<KDL::Frame> links_in_base) {
  // The branch of the configured seed (`initial`), the representatives nearest the warm start.
  const KDL::JntArray& seed = warm_.seedFor(tools_in_base);
  if (solver_.allInverse(tools_in_base[0], seed, solutions_) != IkStatus::Ok) return Reachability::Unreachable;
  const std::span<double> q(q_.data.data(), 6);
  if (pickBranch(std::span<const double>(warm_.initial().data.data(), 6), std::span<const double>(seed.data.data(), 6),
                 q) != Reachability::Reachable)
    return Reachability::Unreachable;
  if (!solver_.model().linkFrames(q, links_in_base)) return Reachability::Unreachable;
  warm_.keep(q_, tools_in_base);
  return Reachability::Reachable;
}

void Ur5Model::jointLimits(std::span<double> lower, std::span<double> upper, std::span<double> max_velocity) const {
  const kinematics::JointLimits& limits = solver_.limits();
  for (std::size_t j = 0; j < 6; ++j) {
    lower[j] = limits.lower[j];
    upper[j] = limits.upper[j];
    max_velocity[j] = kMaxJointVelocity;
  }
}

bool Ur5Model::linkFramesAt(std::span<const double> q, std::span<KDL::Frame> links_in_base) {
  return solver_.limits().contains(q, 1e-9) && solver_.model().linkFrames(q, links_in_base);
}

Reachability Ur5Model::inverseNear(std::span<const KDL::Frame> tools_in_base, std::span<const double> seed,
                                   std::span<double> q) {
  // Exactly the control path's rule (kinematics::ContinuousIk): the solution nearest the seed on
  // the seed's branch as Ur5Solver::branch defines it (shoulder: the wrist point's side of the
  // base axis, elbow: sign of sin q3, wrist: sign of sin q5).
  for (unsigned j = 0; j < 6; ++j) seed_(j) = seed[j];
  switch (solver_.inverseOnBranch(tools_in_base[0], seed_, solver_.branch(seed), q_)) {
    case IkStatus::Ok:
      for (unsigned j = 0; j < 6; ++j) q[j] = q_(j);
      return Reachability::Reachable;
    case IkStatus::Discontinuous:
      return Reachability::OtherBranch;
    default:
      return Reachability::Unreachable;
  }
}

namespace {

/// Ur5Solver::branch's shoulder quantity: the wrist point's coordinate along x1 [m].
double ur5Lateral(const kinematics::Ur5Parameters& p, std::span<const double> q) {
  return p.a2 * std::cos(q[1]) + p.a3 * std::cos(q[1] + q[2]) + p.d5 * std::sin(q[1] + q[2] + q[3]);
}

}  // namespace

bool Ur5Model::keepsBranch(std::span<const double> q, std::span<const double> start,
                           std::span<const double> goal) const {
  const kinematics::Ur5Parameters& p = solver_.parameters();
  return sameSide(std::sin(q[2]), std::sin(start[2]), std::sin(goal[2]), kElbowMargin) &&
         sameSide(std::sin(q[4]), std::sin(start[4]), std::sin(goal[4]), kWristMargin) &&
         sameSide(ur5Lateral(p, q), ur5Lateral(p, start), ur5Lateral(p, goal), kShoulderMargin);
}

void Ur5Model::seedJoints(std::span<double> q) const {
  for (unsigned j = 0; j < 6; ++j) q[j] = warm_.initial()(j);
}

void Ur5Model::coordinateBounds(std::span<const double> start, std::span<const double>, std::span<double> lower,
                                std::span<double> upper) const {
  const kinematics::JointLimits& limits = solver_.limits();
  for (std::size_t j = 0; j < 6; ++j) {
    lower[j] = std::max(limits.lower[j], start[j] - std::numbers::pi);
    upper[j] = std::min(limits.upper[j], start[j] + std::numbers::pi);
  }
}

KDL::JntArray IsurPuncturingModel::defaultSeed() {
  // On the default geometry's redundancy rule: base at base_angle 0, elbow q6 - q7 = pitch_difference.
  const double elbow = kinematics::IsurGeometry{}.pitch_difference;
  return jointArray({0.1, 0.1, 0.1, 0.0, 0.0, 0.5 * elbow, -0.5 * elbow, 0.0});
}

IsurPuncturingModel::IsurPuncturingModel(const kinematics::IsurGeometry& geometry, const KDL::JntArray& seed)
    : solver_(geometry),
      warm_(kinematics::IsurPuncturingSolver::kJoints, seed, "I-SUR"),
      q_(kinematics::IsurPuncturingSolver::kJoints),
      seed_(kinematics::IsurPuncturingSolver::kJoints) {}

Reachability IsurPuncturingModel::solve(std::span<const KDL::Frame> tools_in_base,
                                        std::span<KDL::Frame> links_in_base) {
  if (solver_.inverse(tools_in_base[0], warm_.seedFor(tools_in_base), q_) != IkStatus::Ok)
    return Reachability::Unreachable;
  if (solver_.linkFrames(q_, links_in_base) != IkStatus::Ok) return Reachability::Unreachable;
  warm_.keep(q_, tools_in_base);
  return Reachability::Reachable;
}

void IsurPuncturingModel::jointLimits(std::span<double> lower, std::span<double> upper,
                                      std::span<double> max_velocity) const {
  const kinematics::JointLimits& limits = solver_.limits();
  for (std::size_t j = 0; j < kinematics::IsurPuncturingSolver::kJoints; ++j) {
    lower[j] = limits.lower[j];
    upper[j] = limits.upper[j];
    max_velocity[j] = j < 3 ? kMaxSliderVelocity : kMaxRevoluteVelocity;
  }
}

bool IsurPuncturingModel::linkFramesAt(std::span<const double> q, std::span<KDL::Frame> links_in_base) {
  for (unsigned j = 0; j < kinematics::IsurPuncturingSolver::kJoints; ++j) q_(j) = q[j];
  return solver_.limits().contains(q_, 1e-9) && solver_.linkFrames(q_, links_in_base) == IkStatus::Ok;
}

Reachability IsurPuncturingModel::inverseNear(std::span<const KDL::Frame> tools_in_base, std::span<const double> seed,
                                              std::span<double> q) {
  // The solver keeps the seed's yaw within its wrist band (the needle vertical): what the control
  // path's IK does, so a planned path through the vertical is followed as verified.
  constexpr unsigned kJoints = kinematics::IsurPuncturingSolver::kJoints;
  for (unsigned j = 0; j < kJoints; ++j) seed_(j) = seed[j];
  if (solver_.inverse(tools_in_base[0], seed_, q_) != IkStatus::Ok) return Reachability::Unreachable;
  for (unsigned j = 0; j < kJoints; ++j) q[j] = q_(j);
  return Reachability::Reachable;
}

Reachability IsurPuncturingModel::verticalGoal(std::span<const KDL::Frame> tools_in_base, std::span<const double> start,
                                               std::span<double> q) {
  // The needle vertical: only yaw ∓ roll is defined. Keep the start's yaw (no turn of the arm about
  // the vertical) unless that leaves the roll within kRollMargin of a limit, where any rounding in
  // the commands of the next motion (a descent along the needle) would need the roll past it: then
  // turn yaw and roll together so that the roll lies kRollMargin inside.
  const Reachability kept = inverseNear(tools_in_base, start, q);
  if (kept != Reachability::Reachable) return kept;
  const kinematics::JointLimits& l = solver_.limits();
  const double excess = std::max(q[7] - (l.upper[7] - kRollMargin), (l.lower[7] + kRollMargin) - q[7]);
  if (excess <= 0.0) return kept;
  const double into = q[7] > 0.5 * (l.lower[7] + l.upper[7]) ? -excess : excess;  // roll change wanted
  std::array<double, kinematics::IsurPuncturingSolver::kJoints> seed{}, turned{};
  for (const double sign : {1.0, -1.0}) {  // yaw - roll (needle down) or yaw + roll (up) is fixed
    std::copy(start.begin(), start.end(), seed.begin());
    seed[4] += sign * into;
    seed[7] = q[7] + into;
    if (inverseNear(tools_in_base, seed, turned) != Reachability::Reachable) continue;
    if (std::abs(turned[7] - (q[7] + into)) > 1e-6) continue;
    std::copy(turned.begin(), turned.end(), q.begin());
    return Reachability::Reachable;
  }
  return kept;
}

bool IsurPuncturingModel::onRule(const KDL::Frame& target, double yaw, double pitch, double roll,
                                 std::span<const double> seed, std::span<double> q) {
  const kinematics::JointLimits& l = solver_.limits();
  const kinematics::IsurGeometry& g = solver_.geometry();
  const double yaw_sum = seed[3] + seed[4] + kinematics::wrapToPi(yaw - seed[3] - seed[4]);
  q[3] = seed[3] + g.yaw_share * (yaw_sum - seed[3] - seed[4]);
  q[4] = yaw_sum - q[3];
  const std::array<double, 7> c{seed[0], seed[1], seed[2], q[3], q[4],
                                seed[5] + seed[6] + kinematics::wrapToPi(pitch - seed[5] - seed[6]),
                                seed[7] + kinematics::wrapToPi(roll - seed[7])};
  jointsOf(c, seed, q);
  if (q[7] > l.upper[7]) q[7] -= 2.0 * std::numbers::pi;
  if (q[7] < l.lower[7]) q[7] += 2.0 * std::numbers::pi;
  for (std::size_t j = 3; j < kinematics::IsurPuncturingSolver::kJoints; ++j)
    if (q[j] < l.lower[j] || q[j] > l.upper[j]) return false;
  // Position: target.p = Rz(q4) (p_delta + the micro arm's offset), the delta's closed form.
  for (unsigned j = 0; j < kinematics::IsurPuncturingSolver::kJoints; ++j) q_(j) = q[j];
  KDL::Frame tool, platform;
  if (solver_.forward(q_, tool) != IkStatus::Ok || solver_.platformPose(q_, platform) != IkStatus::Ok) return false;
  const KDL::Rotation back = KDL::Rotation::RotZ(-q[3]);
  return solver_.macro().inversePosition(back * target.p - back * (tool.p - platform.p),
                                         std::span<double, 3>(q.data(), 3)) == IkStatus::Ok;
}

Reachability IsurPuncturingModel::goalChoices(std::span<const KDL::Frame> tools_in_base, std::span<const double> start,
                                              std::span<double> preferred, std::span<double> alternative,
                                              bool& has_alternative) {
  constexpr unsigned kJoints = kinematics::IsurPuncturingSolver::kJoints;
  has_alternative = false;
  const KDL::Rotation& r = tools_in_base[0].M;
  const double cos_pitch = std::hypot(r(0, 0), r(1, 0));
  if (cos_pitch < kinematics::IsurPuncturingSolver::kWristBand) return verticalGoal(tools_in_base, start, preferred);
  const double yaw = std::atan2(r(1, 0), r(0, 0)), pitch = std::atan2(-r(2, 0), cos_pitch);
  const double roll = std::atan2(r(2, 1), r(2, 2));
  double rule_distance = std::numeric_limits<double>::infinity();
  std::array<double, kJoints> candidate{};
  for (const auto& [y, p, ro] : {std::array<double, 3>{yaw, pitch, roll},
                                  std::array<double, 3>{yaw + std::numbers::pi, std::numbers::pi - pitch,
                                                        roll + std::numbers::pi}}) {
    if (!onRule(tools_in_base[0], y, p, ro, start, candidate)) continue;
    double distance = 0.0;
    for (unsigned j = 3; j < kJoints; ++j) distance += (candidate[j] - start[j]) * (candidate[j] - start[j]);
    if (distance < rule_distance) {
      rule_distance = distance;
      std::copy(candidate.begin(), candidate.end(), preferred.begin());
    }
  }
  const kinematics::IkBranch start_branch = solver_.branch(start);
  const bool on_rule = std::isfinite(rule_distance);
  if (on_rule && start_branch.compatibleWith(solver_.branch(std::span<const double>(preferred.data(), kJoints))))
    return Reachability::Reachable;
  // The rule reaches the goal only on the other wrist representation than the start's (the
  // needle's pitch across ±90°, the yaw turned half a turn: suturing query 29 of the random
  // queries, the base turntable turned 2.3 rad and the arms in contact) or not at all: the
  // control path's IK on the start's representation competes, which moves the elbow off the rule
  // to the nearest split the delta reaches (at the end of its stroke), as the controllers do. The
  // farther of the two is the alternative.
  for (unsigned j = 0; j < kJoints; ++j) seed_(j) = start[j];
  if (solver_.inverseOnBranch(tools_in_base[0], seed_, start_branch, q_) == IkStatus::Ok) {
    double distance = 0.0;
    for (unsigned j = 3; j < kJoints; ++j) distance += (q_(j) - start[j]) * (q_(j) - start[j]);
    if (!on_rule) {
      for (unsigned j = 0; j < kJoints; ++j) preferred[j] = q_(j);
      return Reachability::Reachable;
    }
    has_alternative = true;
    if (distance < rule_distance) {
      std::copy_n(preferred.begin(), kJoints, alternative.begin());
      for (unsigned j = 0; j < kJoints; ++j) preferred[j] = q_(j);
    } else {
      for (unsigned j = 0; j < kJoints; ++j) alternative[j] = q_(j);
    }
    return Reachability::Reachable;
  }
  return on_rule ? Reachability::Reachable : inverseNear(tools_in_base, start, preferred);
}

Reachability IsurPuncturingModel::inverseGoal(std::span<const KDL::Frame> tools_in_base, std::span<const double> start,
                                              std::span<double> q) {
  bool has_alternative = false;
  return goalChoices(tools_in_base, start, q, alternative_, has_alternative);
}

Reachability IsurPuncturingModel::inverseGoalAlternative(std::span<const KDL::Frame> tools_in_base,
                                                         std::span<const double> start, std::span<double> q) {
  bool has_alternative = false;
  const Reachability reached = goalChoices(tools_in_base, start, preferred_, q, has_alternative);
  return reached == Reachability::Reachable && has_alternative ? Reachability::Reachable : Reachability::Unreachable;
}

namespace {

/// The interval of s where `offset + slope * s` lies in [lower, upper], intersected into [low, high].
void constrain(double offset, double slope, double lower, double upper, double& low, double& high) {
  if (slope == 0.0) {
    if (offset < lower || offset > upper) high = low - 1.0;  // empty
    return;
  }
  double a = (lower - offset) / slope, b = (upper - offset) / slope;
  if (a > b) std::swap(a, b);
  low = std::max(low, a);
  high = std::min(high, b);
}

/// Bounds of the sum s = qa + qb when qa = seed_a + share (s - seed_a - seed_b) and qb = s - qa
/// must stay within their limits.
void sumBounds(double seed_a, double seed_b, double share, double lower_a, double upper_a, double lower_b,
               double upper_b, double& low, double& high) {
  const double seed_sum = seed_a + seed_b;
  low = -std::numeric_limits<double>::infinity();
  high = std::numeric_limits<double>::infinity();
  constrain(seed_a - share * seed_sum, share, lower_a, upper_a, low, high);
  constrain(-seed_a + share * seed_sum, 1.0 - share, lower_b, upper_b, low, high);
}

}  // namespace

void IsurPuncturingModel::coordinateBounds(std::span<const double> start, std::span<const double> goal,
                                           std::span<double> lower, std::span<double> upper) const {
  const kinematics::JointLimits& l = solver_.limits();
  const kinematics::IsurGeometry& g = solver_.geometry();
  for (std::size_t j = 0; j < 3; ++j) {
    lower[j] = l.lower[j];
    upper[j] = l.upper[j];
  }
  if (std::isfinite(g.base_angle)) {
    // Only the yaw c[3] + c[4] counts (jointsOf splits it): c[3] is base_angle (OMPL wants a
    // bound of some width), c[4] the rest of the yaw within both joints' limits.
    lower[3] = g.base_angle;
    upper[3] = g.base_angle + kBaseCoordinateWidth;
    lower[4] = l.lower[3] + l.lower[4] - g.base_angle;
    upper[4] = l.upper[3] + l.upper[4] - g.base_angle;
  } else {
    // The base turntable only where the IK moves it: between its start and goal angles (it turns
    // only when the micro yaw reaches a limit).
    lower[3] = std::min(start[3], goal[3]);
    upper[3] = std::max(start[3], goal[3]);
    lower[4] = l.lower[4];
    upper[4] = l.upper[4];
  }
  if (std::isfinite(g.pitch_difference)) {
    // Every pitch the two joints reach: where (pitch ± d) / 2 would leave a joint's limits the
    // split is clamped (jointsOf), as the solver clamps it.
    lower[5] = l.lower[5] + l.lower[6];
    upper[5] = l.upper[5] + l.upper[6];
  } else {
    sumBounds(start[5], start[6], g.pitch_share, l.lower[5], l.upper[5], l.lower[6], l.upper[6], lower[5], upper[5]);
  }
  lower[6] = l.lower[7];
  upper[6] = l.upper[7];
}

void IsurPuncturingModel::jointsOf(std::span<const double> c, std::span<const double> start,
                                   std::span<double> q) const {
  const kinematics::IsurGeometry& g = solver_.geometry();
  for (std::size_t j = 0; j < 5; ++j) q[j] = c[j];
  if (std::isfinite(g.base_angle)) {
    // The yaw c[3] + c[4] split as the solver splits it: the base at base_angle as far as the
    // micro yaw's limits allow.
    const double yaw = c[3] + c[4];
    q[3] = solver_.baseOnRule(yaw);
    q[4] = yaw - q[3];
  }
  if (std::isfinite(g.pitch_difference)) {
    // The elbow q6 - q7 at pitch_difference, the split clamped where a joint would leave its
    // limits (the pitch within a share's reach of a limit: IsurPuncturingSolver clamps it so too).
    const kinematics::JointLimits& l = solver_.limits();
    const double lo = std::max(l.lower[5], c[5] - l.upper[6]), hi = std::min(l.upper[5], c[5] - l.lower[6]);
    q[5] = std::clamp(0.5 * (c[5] + g.pitch_difference), lo, std::max(lo, hi));
  } else {
    q[5] = start[5] + g.pitch_share * (c[5] - start[5] - start[6]);
  }
  q[6] = c[5] - q[5];
  q[7] = c[6];
}

void IsurPuncturingModel::seedJoints(std::span<double> q) const {
  for (unsigned j = 0; j < kinematics::IsurPuncturingSolver::kJoints; ++j) q[j] = warm_.initial()(j);
}

void IsurPuncturingModel::coordinateScales(std::span<double> scale) const {
  for (std::size_t j = 0; j < 7; ++j) scale[j] = j < 3 ? kMaxSliderVelocity : kMaxRevoluteVelocity;
}

bool IsurPuncturingModel::singularCrossing(std::span<const double> a, std::span<const double> b,
                                           std::span<double> before, std::span<double> after) const {
  const double pitch_a = a[5] + a[6], pitch_b = b[5] + b[6];
  const double share = std::isfinite(solver_.geometry().pitch_difference) ? 0.5 : solver_.geometry().pitch_share;
  const auto atLock = [](double pitch) {
    return std::abs(std::cos(pitch)) < kinematics::IsurPuncturingSolver::kWristBand;
  };
  const auto movePitch = [&](std::span<double> q, double by) {
    q[5] += share * by;
    q[6] += (1.0 - share) * by;
  };
  // An end at the lock: the Cartesian segment must leave (or reach) the vertical in that end's yaw
  // plane, so the waypoint next to it is that end with the pitch kCrossingMargin towards the other.
  if (atLock(pitch_a) != atLock(pitch_b)) {
    std::copy(a.begin(), a.end(), before.begin());
    std::copy(b.begin(), b.end(), after.begin());
    if (atLock(pitch_a)) {
      std::copy(a.begin(), a.end(), after.begin());
      movePitch(after, std::copysign(kCrossingMargin, pitch_b - pitch_a));
    } else {
      std::copy(b.begin(), b.end(), before.begin());
      movePitch(before, std::copysign(kCrossingMargin, pitch_a - pitch_b));
    }
    return true;
  }
  if (atLock(pitch_a)) return false;  // both ends vertical: the yaw is kept all along
  for (const double lock : {std::numbers::pi / 2, -std::numbers::pi / 2}) {
    if ((pitch_a - lock) * (pitch_b - lock) >= 0.0) continue;
    const double t = (lock - pitch_a) / (pitch_b - pitch_a);
    for (std::size_t j = 0; j < kinematics::IsurPuncturingSolver::kJoints; ++j) before[j] = a[j] + t * (b[j] - a[j]);
    std::copy(before.begin(), before.end(), after.begin());
    const double step = std::copysign(kCrossingMargin, pitch_b - pitch_a);
    movePitch(before, -step);
    movePitch(after, step);
    return true;
  }
  return false;
}

void IsurPuncturingModel::coordinatesOf(std::span<const double> q, std::span<double> c) const {
  for (std::size_t j = 0; j < 5; ++j) c[j] = q[j];
  if (std::isfinite(solver_.geometry().base_angle)) {  // the yaw as base_angle + the rest (jointsOf)
    c[3] = solver_.geometry().base_angle;
    c[4] = q[3] + q[4] - c[3];
  }
  c[5] = q[5] + q[6];
  c[6] = q[7];
}

KDL::JntArray IsurSuturingModel::defaultSeed() {
  // The Endo Stitch sub-structure on the default geometry's redundancy rule, as IsurPuncturingModel's.
  const double elbow = kinematics::IsurGeometry{}.pitch_difference;
  return jointArray({0.1, 0.1, 0.1, 0.0, 0.0, 0.5 * elbow, -0.5 * elbow, 0.0, 0.0, 0.5, -0.5, 0.0, 0.5, 0.0});
}

namespace {

KDL::JntArray rightPart(const KDL::JntArray& q) {
  KDL::JntArray right(kinematics::IsurSuturingSolver::kRightJoints);
  for (unsigned j = 0; j < right.rows(); ++j) right(j) = q(j);
  return right;
}

/// The interval [low, high] between two consecutive zeros of sin(x + offset) that holds `x`
/// (a Puma-type arm's elbow or wrist branch: its sign), `margin` inside them.
void branchInterval(double x, double offset, double margin, double& low, double& high) {
  const double k = std::floor((x + offset) / std::numbers::pi);
  low = k * std::numbers::pi - offset + margin;
  high = (k + 1.0) * std::numbers::pi - offset - margin;
}

}  // namespace

IsurSuturingModel::IsurSuturingModel(const kinematics::IsurSuturingGeometry& geometry, const KDL::JntArray& seed)
    : solver_(geometry),
      right_(geometry.right, rightPart(seed.rows() == kinematics::IsurSuturingSolver::kJoints ? seed : defaultSeed())),
      left_parameters_(geometry.left),
      warm_(kinematics::IsurSuturingSolver::kJoints, seed, "I-SUR suturing"),
      q_(kinematics::IsurSuturingSolver::kJoints),
      seed_(kinematics::IsurSuturingSolver::kJoints) {}

Reachability IsurSuturingModel::solve(std::span<const KDL::Frame> tools_in_base, std::span<KDL::Frame> links_in_base) {
  if (solver_.inverse(tools_in_base[0], tools_in_base[1], warm_.seedFor(tools_in_base), q_) != IkStatus::Ok)
    return Reachability::Unreachable;
  if (solver_.linkFrames(q_, links_in_base) != IkStatus::Ok) return Reachability::Unreachable;
  warm_.keep(q_, tools_in_base);
  return Reachability::Reachable;
}

void IsurSuturingModel::jointLimits(std::span<double> lower, std::span<double> upper,
                                    std::span<double> max_velocity) const {
  const kinematics::JointLimits& limits = solver_.limits();
  for (std::size_t j = 0; j < jointCount(); ++j) {
    lower[j] = limits.lower[j];
    upper[j] = limits.upper[j];
    max_velocity[j] =
        j < 3 ? IsurPuncturingModel::kMaxSliderVelocity : IsurPuncturingModel::kMaxRevoluteVelocity;
  }
}

bool IsurSuturingModel::linkFramesAt(std::span<const double> q, std::span<KDL::Frame> links_in_base) {
  for (unsigned j = 0; j < kinematics::IsurSuturingSolver::kJoints; ++j) q_(j) = q[j];
  return solver_.limits().contains(q_, 1e-9) && solver_.linkFrames(q_, links_in_base) == IkStatus::Ok;
}

void IsurSuturingModel::seedJoints(std::span<double> q) const {
  for (unsigned j = 0; j < kinematics::IsurSuturingSolver::kJoints; ++j) q[j] = warm_.initial()(j);
}

Reachability IsurSuturingModel::reachability(IkStatus status) const {
  if (status == IkStatus::Ok) return Reachability::Reachable;
  return status == IkStatus::Discontinuous ? Reachability::OtherBranch : Reachability::Unreachable;
}

Reachability IsurSuturingModel::inverseNear(std::span<const KDL::Frame> tools_in_base, std::span<const double> seed,
                                            std::span<double> q) {
  constexpr unsigned kJoints = kinematics::IsurSuturingSolver::kJoints;
  for (unsigned j = 0; j < kJoints; ++j) seed_(j) = seed[j];
  const IkStatus status =
      solver_.inverseOnBranch(tools_in_base[0], tools_in_base[1], seed_, solver_.branch(seed), q_);
  if (status != IkStatus::Ok) return reachability(status);
  for (unsigned j = 0; j < kJoints; ++j) q[j] = q_(j);
  return Reachability::Reachable;
}

Reachability IsurSuturingModel::inverseGoal(std::span<const KDL::Frame> tools_in_base, std::span<const double> start,
                                            std::span<double> q) {
  return withGripperArm(right_.inverseGoal(tools_in_base.first(1), start.first(kRightJoints),
                                           std::span<double>(seed_.data.data(), kRightJoints)),
                        tools_in_base, start, q);
}

Reachability IsurSuturingModel::inverseGoalAlternative(std::span<const KDL::Frame> tools_in_base,
                                                       std::span<const double> start, std::span<double> q) {
  return withGripperArm(right_.inverseGoalAlternative(tools_in_base.first(1), start.first(kRightJoints),
                                                      std::span<double>(seed_.data.data(), kRightJoints)),
                        tools_in_base, start, q);
}

Reachability IsurSuturingModel::withGripperArm(Reachability right, std::span<const KDL::Frame> tools_in_base,
                                               std::span<const double> start, std::span<double> q) {
  constexpr unsigned kJoints = kinematics::IsurSuturingSolver::kJoints;
  if (right != Reachability::Reachable) return right;
  for (unsigned j = kRightJoints; j < kJoints; ++j) seed_(j) = start[j];
  const IkStatus status = solver_.inverseGripperArm(
      tools_in_base[1], seed_, kinematics::IsurSuturingSolver::leftBranch(solver_.branch(start)), q_);
  if (status != IkStatus::Ok) return reachability(status);
  for (unsigned j = 0; j < kJoints; ++j) q[j] = q_(j);
  return Reachability::Reachable;
}

bool IsurSuturingModel::singularCrossing(std::span<const double> a, std::span<const double> b,
                                         std::span<double> before, std::span<double> after) const {
  if (!right_.singularCrossing(a.first(kRightJoints), b.first(kRightJoints), before.first(kRightJoints),
                               after.first(kRightJoints)))
    return false;
  // The 6-DOF arm on the segment where the Endo Stitch's pitch is (the fraction of its change).
  const double pitch_a = a[5] + a[6], pitch_b = b[5] + b[6];
  for (const std::span<double> q : {before, after}) {
    const double t = pitch_b == pitch_a ? 0.5 : std::clamp((q[5] + q[6] - pitch_a) / (pitch_b - pitch_a), 0.0, 1.0);
    for (std::size_t j = kRightJoints; j < jointCount(); ++j) q[j] = a[j] + t * (b[j] - a[j]);
  }
  return true;
}

void IsurSuturingModel::coordinateScales(std::span<double> scale) const {
  right_.coordinateScales(scale.first(kRightCoordinates));
  for (std::size_t i = kRightCoordinates; i < coordinateCount(); ++i)
    scale[i] = IsurPuncturingModel::kMaxRevoluteVelocity;
}

void IsurSuturingModel::coordinateBounds(std::span<const double> start, std::span<const double> goal,
                                         std::span<double> lower, std::span<double> upper) const {
  right_.coordinateBounds(start.first(kRightJoints), goal.first(kRightJoints), lower.first(kRightCoordinates),
                          upper.first(kRightCoordinates));
  const kinematics::JointLimits& limits = solver_.limits();
  for (std::size_t j = 0; j < kLeftJoints; ++j) {
    lower[kRightCoordinates + j] = limits.lower[kRightJoints + j];
    upper[kRightCoordinates + j] = limits.upper[kRightJoints + j];
  }
  // The elbow (Puma260Solver::branch bit 1: sin(q3 + atan2(d4, a3))) and the wrist (bit 2: sin q5)
  // stay on the start's side of their singularities.
  const double elbow_offset = std::atan2(left_parameters_.d4, left_parameters_.a3);
  using JointOffset = std::pair<std::size_t, double>;
  for (const auto& [joint, offset] : {JointOffset{2, elbow_offset}, JointOffset{4, 0.0}}) {
    double low = 0.0, high = 0.0;
    branchInterval(start[kRightJoints + joint], offset, kBranchBoundMargin, low, high);
    lower[kRightCoordinates + joint] = std::max(lower[kRightCoordinates + joint], low);
    upper[kRightCoordinates + joint] = std::min(upper[kRightCoordinates + joint], high);
  }
}

void IsurSuturingModel::jointsOf(std::span<const double> c, std::span<const double> start,
                                 std::span<double> q) const {
  right_.jointsOf(c.first(kRightCoordinates), start.first(kRightJoints), q.first(kRightJoints));
  for (std::size_t j = 0; j < kLeftJoints; ++j) q[kRightJoints + j] = c[kRightCoordinates + j];
}

void IsurSuturingModel::coordinatesOf(std::span<const double> q, std::span<double> c) const {
  right_.coordinatesOf(q.first(kRightJoints), c.first(kRightCoordinates));
  for (std::size_t j = 0; j < kLeftJoints; ++j) c[kRightCoordinates + j] = q[kRightJoints + j];
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
