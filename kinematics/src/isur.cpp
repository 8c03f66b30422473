#include "cobra/kinematics/isur.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>
#include <utility>

#include "cobra/kinematics/frame_product.hpp"
#include "cobra/kinematics/geometry.hpp"

#include "checks.hpp"

namespace cobra::kinematics {

namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kTwoPi = 2.0 * kPi;

/// Splits the joint-angle sum `total` (rad) between joints a and b: a = seed_a + share·(change of
/// the sum), clamped to the interval where both a and b = total - a respect their limits. The sum
/// is an angle: total ± 2π is tried (nearest first) when total itself does not fit.
/// The interval [lo, hi] of `a` where both joints respect their limits is returned too.
bool splitSum(double total, double seed_a, double seed_b, double share, double lower_a, double upper_a, double lower_b,
              double upper_b, double& a, double& b, double& lo, double& hi) noexcept {
  const double seed_total = seed_a + seed_b;
  const double step = total >= seed_total ? -kTwoPi : kTwoPi;
  for (const double candidate : {total, total + step, total - step}) {
    lo = std::max(lower_a, candidate - upper_b);
    hi = std::min(upper_a, candidate - lower_b);
    if (lo > hi) continue;
    a = std::clamp(seed_a + share * (candidate - seed_total), lo, hi);
    b = candidate - a;
    return true;
  }
  return false;
}

/// Largest change [rad] per solve of a redundant joint towards the redundancy rule (base_angle,
/// pitch_difference) from a seed that is off it: 0.5 rad/s at 1 kHz, a third of the micro joints'
/// velocity limits, so a robot started (or left by another controller) off the rule is brought
/// back to it continuously while it follows its Cartesian commands.
constexpr double kRedundancyReturnStep = 5e-4;
/// A seed within this of the rule [rad] is on it.
constexpr double kOnRule = 1e-9;

/// The redundant joint's value for this solve: `rule` (its value for the target, within [lo, hi])
/// when the seed's value `seed` is on the rule at the seed (`seed_rule`), so that the solution is
/// a function of the target alone; otherwise the seed's value moved towards `rule` by at most
/// kRedundancyReturnStep.
double towardsRule(double seed, double seed_rule, double rule, double lo, double hi) noexcept {
  if (std::abs(seed - seed_rule) <= kOnRule) return rule;
  return std::clamp(seed + std::clamp(rule - seed, -kRedundancyReturnStep, kRedundancyReturnStep), lo, hi);
}

/// Step [rad] of the search for a pitch split the delta can reach (IsurPuncturingSolver::solveCandidate).
constexpr double kSplitSearchStep = 0.01;
/// Bisection steps refining the first reachable split towards the preferred one (0.01 / 2^12 rad).
constexpr int kSplitBisections = 12;

/// The representative of `angle` + 2πk inside [lower, upper] nearest to `seed`; false if none.
bool nearestInLimits(double angle, double seed, double lower, double upper, double& out) noexcept {
  const double base = seed + wrapToPi(angle - seed);
  double best = std::numeric_limits<double>::infinity();
  for (const double candidate : {base, base - kTwoPi, base + kTwoPi}) {
    if (candidate >= lower && candidate <= upper && std::abs(candidate - seed) < std::abs(best - seed))
      best = candidate;
  }
  if (!std::isfinite(best)) return false;
  out = best;
  return true;
}

}  // namespace

KDL::Chain cartesianMacroChain(const IsurMicroArm& m) {
  using KDL::Joint;
  using KDL::Segment;
  KDL::Chain chain;
  chain.addSegment(Segment(Joint(Joint::RotZ)));
  chain.addSegment(Segment(Joint(Joint::TransX)));
  chain.addSegment(Segment(Joint(Joint::TransY)));
  chain.addSegment(Segment(Joint(Joint::TransZ), KDL::Frame(m.mount)));
  chain.addSegment(Segment(Joint(Joint::RotZ), KDL::Frame(m.shoulder)));
  chain.addSegment(Segment(Joint(Joint::RotY), KDL::Frame(KDL::Vector(m.upper_arm, 0, 0))));
  chain.addSegment(Segment(Joint(Joint::RotY), KDL::Frame(KDL::Vector(m.forearm, 0, 0))));
  chain.addSegment(Segment(Joint(Joint::RotX), KDL::Frame(m.tool)));
  return chain;
}

IsurPuncturingSolver::IsurPuncturingSolver(const IsurGeometry& geometry, std::string_view name)
    : geometry_(geometry), name_(name), delta_(geometry.macro, std::string(name) + " macro") {
  const IsurMicroArm& m = geometry_.micro;
  using Named = std::pair<const char*, KDL::Vector>;
  for (const auto& [what, v] : std::array<Named, 3>{Named{"micro.mount", m.mount}, Named{"micro.shoulder", m.shoulder},
                                                    Named{"micro.tool", m.tool}}) {
    detail::requireFinite(name_, std::string(what) + ".x", v.x(), "m");
    detail::requireFinite(name_, std::string(what) + ".y", v.y(), "m");
    detail::requireFinite(name_, std::string(what) + ".z", v.z(), "m");
  }
  detail::requireFinite(name_, "micro.upper_arm", m.upper_arm, "m");
  detail::requireFinite(name_, "micro.forearm", m.forearm, "m");
  using Share = std::pair<const char*, double>;
  for (const auto& [what, share] :
       std::array<Share, 2>{Share{"yaw_share", geometry_.yaw_share}, Share{"pitch_share", geometry_.pitch_share}}) {
    if (!(share >= 0.0 && share <= 1.0))
      throw std::invalid_argument(name_ + ": parameter " + what + " is " + formatNumber(share) +
                                  ": give a value in [0, 1]");
  }
  limits_ = delta_.limits();
  for (std::size_t i = 0; i < 5; ++i) {
    limits_.types.push_back(JointType::Revolute);
    limits_.lower.push_back(geometry_.lower[i]);
    limits_.upper.push_back(geometry_.upper[i]);
  }
  validateLimits(name_, limits_, kJoints);
}

KDL::Frame IsurPuncturingSolver::microForward(double q5, double q6, double q7, double q8) const noexcept {
  // mount · Rz(q5) · shoulder · Ry(q6) · upper arm · Ry(q7) · forearm · Rx(q8) · tool, each factor
  // a pure rotation about an axis or a pure translation: written out instead of nine general frame
  // products (the control path runs it three times per step). The cross-check against KDL's chain
  // (cartesianMacroChain) is in isur_test.
  const IsurMicroArm& m = geometry_.micro;
  const double c5 = std::cos(q5), s5 = std::sin(q5);
  const double c6 = std::cos(q6), s6 = std::sin(q6);
  const double c7 = std::cos(q7), s7 = std::sin(q7);
  const double c8 = std::cos(q8), s8 = std::sin(q8);
  // Position, from the tool inwards: v = Rx(q8)·tool + forearm, then Ry(q7)·v + upper arm, ...
  double x = m.tool.x() + m.forearm;
  double y = c8 * m.tool.y() - s8 * m.tool.z();
  double z = s8 * m.tool.y() + c8 * m.tool.z();
  double t = c7 * x + s7 * z;
  z = c7 * z - s7 * x;
  x = t + m.upper_arm;
  t = c6 * x + s6 * z;
  z = c6 * z - s6 * x + m.shoulder.z();
  x = t + m.shoulder.x();
  y += m.shoulder.y();
  const KDL::Vector p(c5 * x - s5 * y + m.mount.x(), s5 * x + c5 * y + m.mount.y(), z + m.mount.z());
  // Rotation Rz(q5)·Ry(q6 + q7)·Rx(q8).
  const double cb = c6 * c7 - s6 * s7, sb = s6 * c7 + c6 * s7;
  return KDL::Frame(KDL::Rotation(c5 * cb, c5 * sb * s8 - s5 * c8, c5 * sb * c8 + s5 * s8,  //
                                  s5 * cb, s5 * sb * s8 + c5 * c8, s5 * sb * c8 - c5 * s8,  //
                                  -sb, cb * s8, cb * c8),
                    p);
}

IkStatus IsurPuncturingSolver::platformPose(const KDL::JntArray& q, KDL::Frame& pose) const noexcept {
  if (!validJointArray(q, kJoints)) return IkStatus::BadInput;
  KDL::Vector p_delta;
  const IkStatus status = delta_.forwardPosition(std::span<const double, 3>(q.data.data(), 3), p_delta);
  if (status != IkStatus::Ok) return status;
  const KDL::Rotation base_turn = KDL::Rotation::RotZ(q.data(3));
  pose = KDL::Frame(base_turn, base_turn * p_delta);  // Rz(q4) · Trans(p_delta)
  return IkStatus::Ok;
}

IkStatus IsurPuncturingSolver::linkFrames(const KDL::JntArray& q, std::span<KDL::Frame> frames) const noexcept {
  if (frames.size() != kLinks) return IkStatus::BadInput;
  KDL::Frame platform;
  const IkStatus status = platformPose(q, platform);
  if (status != IkStatus::Ok) return status;
  const IsurMicroArm& m = geometry_.micro;
  frames[0] = KDL::Frame(KDL::Rotation::RotZ(q.data(3)));
  frames[1] = platform;
  frames[2] = platform * KDL::Frame(m.mount) * KDL::Frame(KDL::Rotation::RotZ(q.data(4)));
  frames[3] = frames[2] * KDL::Frame(m.shoulder) * KDL::Frame(KDL::Rotation::RotY(q.data(5)));
  frames[4] = frames[3] * KDL::Frame(KDL::Vector(m.upper_arm, 0.0, 0.0)) * KDL::Frame(KDL::Rotation::RotY(q.data(6)));
  frames[5] = frames[4] * KDL::Frame(KDL::Vector(m.forearm, 0.0, 0.0)) * KDL::Frame(KDL::Rotation::RotX(q.data(7))) *
              KDL::Frame(m.tool);
  return IkStatus::Ok;
}

IkStatus IsurPuncturingSolver::forward(const KDL::JntArray& q, KDL::Frame& pose) noexcept {
  KDL::Frame platform;
  const IkStatus status = platformPose(q, platform);
  if (status != IkStatus::Ok) return status;
  pose = frameProduct(platform, microForward(q.data(4), q.data(5), q.data(6), q.data(7)));
  return IkStatus::Ok;
}

IkStatus IsurPuncturingSolver::solveCandidate(const KDL::Frame& target, double yaw, double pitch, double roll,
                                              const KDL::JntArray& seed, std::array<double, kJoints>& q,
                                              bool search_elbow) const noexcept {
  const JointLimits& l = limits_;
  const Eigen::VectorXd& s = seed.data;  // not KDL's JntArray::operator(), a library call per element
  // Orientation: yaw = q4 + q5, pitch = q6 + q7, roll = q8 (thesis §5.4.1).
  const double yaw_total = s(3) + s(4) + wrapToPi(yaw - s(3) - s(4));
  double lo = 0.0;
  double hi = 0.0;
  if (!splitSum(yaw_total, s(3), s(4), geometry_.yaw_share, l.lower[3], l.upper[3], l.lower[4], l.upper[4], q[3],
                q[4], lo, hi))
    return IkStatus::JointLimits;
  if (std::isfinite(geometry_.base_angle)) {
    const double sum = q[3] + q[4];  // yaw_total, or yaw_total ± 2π where only that fits the limits
    // The rule at the seed's own yaw: is the seed on it?
    q[3] = towardsRule(s(3), baseOnRule(s(3) + s(4)), std::clamp(geometry_.base_angle, lo, hi), lo, hi);
    q[4] = sum - q[3];
  }
  const double pitch_total = s(5) + s(6) + wrapToPi(pitch - s(5) - s(6));
  if (!splitSum(pitch_total, s(5), s(6), geometry_.pitch_share, l.lower[5], l.upper[5], l.lower[6], l.upper[6],
                q[5], q[6], lo, hi))
    return IkStatus::JointLimits;
  if (std::isfinite(geometry_.pitch_difference)) {
    // On the rule the elbow q6 - q7 is pitch_difference (or, deep, the search below moves it).
    const double seed_difference = s(5) - s(6);
    const double difference = towardsRule(seed_difference, geometry_.pitch_difference, geometry_.pitch_difference,
                                          -std::numeric_limits<double>::infinity(),
                                          std::numeric_limits<double>::infinity());
    q[5] = std::clamp(0.5 * (pitch_total + difference), lo, hi);
    q[6] = pitch_total - q[5];
  }
  if (!nearestInLimits(roll, s(7), l.lower[7], l.upper[7], q[7])) return IkStatus::JointLimits;
  const IkStatus preferred = placePlatform(target, q);
  if (preferred == IkStatus::Ok || preferred == IkStatus::BadInput || !search_elbow) return preferred;
  // The delta cannot place its platform for the preferred split (a slider at its end, e.g. deep
  // in a needle insertion): the pitch split is the redundancy that moves the micro arm's offset
  // (the elbow), so take the split nearest the preferred one for which the delta reaches. The
  // boundary of the reachable splits moves continuously with the target, so along a path the
  // split changes continuously (and slowly: the elbow moves only as far as the delta lacks).
  // Only the upper arm's term of the micro arm's offset depends on the split a = q6 (the forearm
  // and tool follow the pitch sum): offset(a) = fixed + Rz(q5)·Ry(a)·(upper_arm, 0, 0), so the
  // delta's target is p(a) = Rz(q4)ᵀ·target.p - fixed - upper_arm·(cos a·cos q5, cos a·sin q5,
  // -sin a), one sincos per trial.
  const double preferred_a = q[5];
  const IsurMicroArm& m = geometry_.micro;
  const double c5 = std::cos(q[4]), s5 = std::sin(q[4]);
  const KDL::Vector upper_term = KDL::Rotation::RotZ(q[4]) * KDL::Rotation::RotY(preferred_a) * KDL::Vector(m.upper_arm, 0, 0);
  const KDL::Vector base_target = KDL::Rotation::RotZ(-q[3]) * target.p - (microForward(q[4], q[5], q[6], q[7]).p - upper_term);
  std::array<double, 3> sliders{};
  const auto reachable = [&](double a) noexcept {
    const double ca = std::cos(a), sa = std::sin(a);
    const KDL::Vector p_delta = base_target - m.upper_arm * KDL::Vector(ca * c5, ca * s5, -sa);
    return delta_.inversePosition(p_delta, std::span<double, 3>(sliders)) == IkStatus::Ok;
  };
  for (double distance = kSplitSearchStep; preferred_a - distance >= lo || preferred_a + distance <= hi;
       distance += kSplitSearchStep) {
    for (const double direction : {-1.0, 1.0}) {
      const double a = preferred_a + direction * distance;
      if (a < lo || a > hi || !reachable(a)) continue;
      // Refine between the last unreachable split and this one, keeping the reachable end.
      double outside = preferred_a + direction * (distance - kSplitSearchStep);
      double inside = a;
      for (int i = 0; i < kSplitBisections; ++i) {
        const double middle = 0.5 * (outside + inside);
        (reachable(middle) ? inside : outside) = middle;
      }
      q[5] = inside;
      q[6] = pitch_total - inside;
      return placePlatform(target, q);
    }
  }
  return preferred;
}

IkStatus IsurPuncturingSolver::placePlatform(const KDL::Frame& target, std::array<double, kJoints>& q) const noexcept {
  // Position: target.p = Rz(q4)·(p_delta + micro offset), so the delta places its platform at
  // Rz(q4)ᵀ·target.p - offset (closed form).
  const KDL::Vector offset = microForward(q[4], q[5], q[6], q[7]).p;
  const KDL::Vector p_delta = KDL::Rotation::RotZ(-q[3]) * target.p - offset;
  return delta_.inversePosition(p_delta, std::span<double, 3>(q.data(), 3));
}

IkStatus IsurPuncturingSolver::inverse(const KDL::Frame& target, const KDL::JntArray& seed,
                                       KDL::JntArray& q_out) noexcept {
  return inverseOnBranch(target, seed, IkBranch::any(), q_out);
}

IkBranch IsurPuncturingSolver::pitchBranch(double pitch) noexcept {
  // The pitch representation: cos(pitch) < 0 is the second one (π - θ). Within the wrist band the
  // needle passes through the vertical from one representation to the other continuously (q6 + q7
  // crosses ±90°): either side is this branch.
  IkBranch branch;
  const double cos_pitch = std::cos(pitch);
  if (cos_pitch < 0.0) branch.bits = 1;
  if (std::abs(cos_pitch) < kWristBand) branch.ambiguous = 1;
  return branch;
}

double IsurPuncturingSolver::baseOnRule(double yaw) const noexcept {
  const JointLimits& l = limits_;
  return std::clamp(geometry_.base_angle, std::max(l.lower[3], yaw - l.upper[4]), std::min(l.upper[3], yaw - l.lower[4]));
}

IkBranch IsurPuncturingSolver::branch(std::span<const double> q) const noexcept {
  if (q.size() != kJoints) return IkBranch{};
  return pitchBranch(q[5] + q[6]);
}

IkStatus IsurPuncturingSolver::inverseOnBranch(const KDL::Frame& target, const KDL::JntArray& seed,
                                               IkBranch on_branch, KDL::JntArray& q_out) noexcept {
  if (!validFrame(target) || !validJointArray(seed, kJoints) || q_out.rows() != kJoints) return IkStatus::BadInput;
  // ZYX angles of the target: R = Rz(yaw)·Ry(pitch)·Rx(roll).
  const KDL::Rotation& r = target.M;
  const double cos_pitch = std::hypot(r(0, 0), r(1, 0));
  std::array<std::array<double, 3>, 2> representations{};
  int count = 2;
  if (cos_pitch > IsurPuncturingSolver::kWristBand) {
    const double yaw = std::atan2(r(1, 0), r(0, 0));
    const double pitch = std::atan2(-r(2, 0), cos_pitch);
    const double roll = std::atan2(r(2, 1), r(2, 2));
    representations[0] = {yaw, pitch, roll};
    representations[1] = {yaw + kPi, kPi - pitch, roll + kPi};
  } else {
    // Within kWristBand (header) of pitch ±90° the yaw of the target is ill-conditioned (a tilt of the
    // needle in any direction turns it by up to π): the yaw q4 + q5 stays the seed's and the wrist
    // follows the target's tilt in that yaw plane, R' = Rz(-yaw)·R ≈ Ry(pitch)·Rx(roll). The
    // tilt across the plane (R'(1,0), at most kWristBand rad) is not followed.
    const double yaw = seed.data(3) + seed.data(4);
    const KDL::Rotation in_plane = KDL::Rotation::RotZ(-yaw) * r;
    const double pitch = std::atan2(-in_plane(2, 0), in_plane(0, 0));
    const double roll = std::atan2(-in_plane(1, 2), in_plane(1, 1));
    // Only this representation: the other (yaw + π) is the arm turned half a turn about the
    // vertical, never a continuous step. The pitch passes ±90° in the seed's plane here.
    representations[0] = {yaw, pitch, roll};
    count = 1;
  }

  IkStatus status = IkStatus::Unreachable;
  double best_distance = std::numeric_limits<double>::infinity();
  std::array<double, kJoints> best{};
  // The representations on the caller's branch first. One the caller excludes (the control
  // path's continuity rule) is solved only when none of those solves, and without the elbow
  // search: only to tell a refusal (Discontinuous) from an unreachable target. (The outcome does
  // not depend on the order: a solution on the branch wins, then Discontinuous, then JointLimits.)
  for (const bool on_branch_pass : {true, false}) {
    if (!on_branch_pass && status == IkStatus::Ok) break;
    for (int i = 0; i < count; ++i) {
      std::array<double, kJoints> q{};
      const auto& [yaw, pitch, roll] = representations[static_cast<std::size_t>(i)];
      // The representation's branch is known from its pitch before solving (branch()).
      const bool searched = on_branch.compatibleWith(pitchBranch(pitch));
      if (searched != on_branch_pass) continue;
      const IkStatus candidate = solveCandidate(target, yaw, pitch, roll, seed, q, searched);
      if (candidate != IkStatus::Ok) {
        if (status != IkStatus::Ok && status != IkStatus::Discontinuous && candidate == IkStatus::JointLimits)
          status = IkStatus::JointLimits;
        continue;
      }
      if (!on_branch.compatibleWith(branch(q))) {
        if (status != IkStatus::Ok) status = IkStatus::Discontinuous;
        continue;
      }
      double distance = 0.0;
      for (unsigned j = 0; j < kJoints; ++j) distance += (q[j] - seed.data(j)) * (q[j] - seed.data(j));
      if (distance < best_distance) {
        best_distance = distance;
        best = q;
        status = IkStatus::Ok;
      }
    }
  }
  if (status != IkStatus::Ok) return status;
  for (unsigned j = 0; j < kJoints; ++j) q_out.data(j) = best[j];
  return IkStatus::Ok;
}

IsurSuturingSolver::IsurSuturingSolver(const IsurSuturingGeometry& geometry)
    : right_(geometry.right),
      left_(geometry.left, geometry.left_limits, KDL::Frame::Identity(), KDL::Frame::Identity(), "I-SUR left arm"),
      left_mount_(geometry.left_mount),
      q_right_(IsurPuncturingSolver::kJoints),
      seed_right_(IsurPuncturingSolver::kJoints),
      q_left_(6),
      seed_left_(6) {
  if (!validFrame(left_mount_))
    throw std::invalid_argument(
        "I-SUR: left_mount is not a pose: its translation must be finite and its rotation orthonormal");
  limits_ = right_.limits();
  for (std::size_t i = 0; i < 6; ++i) {
    limits_.types.push_back(JointType::Revolute);
    limits_.lower.push_back(left_.limits().lower[i]);
    limits_.upper.push_back(left_.limits().upper[i]);
  }
}

IkStatus IsurSuturingSolver::forward(const KDL::JntArray& q, KDL::Frame& stitch_tool, KDL::Frame& gripper) noexcept {
  if (!validJointArray(q, kJoints)) return IkStatus::BadInput;
  for (unsigned j = 0; j < IsurPuncturingSolver::kJoints; ++j) q_right_(j) = q(j);
  for (unsigned j = 0; j < 6; ++j) q_left_(j) = q(IsurPuncturingSolver::kJoints + j);
  KDL::Frame platform;
  KDL::Frame stitch;
  KDL::Frame left_tool;
  IkStatus status = right_.platformPose(q_right_, platform);
  if (status == IkStatus::Ok) status = right_.forward(q_right_, stitch);
  if (status == IkStatus::Ok) status = left_.forward(q_left_, left_tool);
  if (status != IkStatus::Ok) return status;
  stitch_tool = stitch;
  gripper = platform * left_mount_ * left_tool;
  return IkStatus::Ok;
}

IkStatus IsurSuturingSolver::linkFrames(const KDL::JntArray& q, std::span<KDL::Frame> frames) noexcept {
  if (!validJointArray(q, kJoints) || frames.size() != kLinks) return IkStatus::BadInput;
  for (unsigned j = 0; j < IsurPuncturingSolver::kJoints; ++j) q_right_(j) = q(j);
  std::array<KDL::Frame, IsurPuncturingSolver::kLinks> right{};
  const IkStatus status = right_.linkFrames(q_right_, right);
  if (status != IkStatus::Ok) return status;
  // The 6-DOF arm's frames: DH frame 0 at platform·left_mount, then its DH frames 1..6 and tool.
  std::array<KDL::Frame, 8> left{};
  std::array<double, 6> q_left{};
  for (unsigned j = 0; j < 6; ++j) q_left[j] = q(IsurPuncturingSolver::kJoints + j);
  if (!left_.model().linkFrames(q_left, left)) return IkStatus::BadInput;
  const KDL::Frame left_base = right[1] * left_mount_;
  for (std::size_t i = 0; i < right.size(); ++i) frames[i] = right[i];
  for (std::size_t i = 1; i <= 5; ++i) frames[5 + i] = left_base * left[i];
  frames[11] = left_base * left[7];
  return IkStatus::Ok;
}

IkStatus IsurSuturingSolver::inverse(const KDL::Frame& stitch_target, const KDL::Frame& gripper_target,
                                     const KDL::JntArray& seed, KDL::JntArray& q_out) noexcept {
  return inverseOnBranch(stitch_target, gripper_target, seed, IkBranch::any(), q_out);
}

IkBranch IsurSuturingSolver::branch(std::span<const double> q) const noexcept {
  if (q.size() != kJoints) return IkBranch{};
  const IkBranch right = right_.branch(q.first(kRightJoints));
  const IkBranch left = left_.branch(q.subspan(kRightJoints, kLeftJoints));
  return IkBranch{static_cast<std::uint8_t>(right.bits | (left.bits << kLeftBranchShift)),
                  static_cast<std::uint8_t>(right.ambiguous | (left.ambiguous << kLeftBranchShift))};
}

IkBranch IsurSuturingSolver::rightBranch(IkBranch branch) noexcept {
  constexpr std::uint8_t kRightMask = (1u << kLeftBranchShift) - 1u;
  return IkBranch{static_cast<std::uint8_t>(branch.bits & kRightMask),
                  static_cast<std::uint8_t>(branch.ambiguous & kRightMask)};
}

IkBranch IsurSuturingSolver::leftBranch(IkBranch branch) noexcept {
  return IkBranch{static_cast<std::uint8_t>(branch.bits >> kLeftBranchShift),
                  static_cast<std::uint8_t>(branch.ambiguous >> kLeftBranchShift)};
}

IkStatus IsurSuturingSolver::inverseOnBranch(const KDL::Frame& stitch_target, const KDL::Frame& gripper_target,
                                             const KDL::JntArray& seed, IkBranch on_branch,
                                             KDL::JntArray& q_out) noexcept {
  if (!validJointArray(seed, kJoints) || q_out.rows() != kJoints || !validFrame(gripper_target))
    return IkStatus::BadInput;
  for (unsigned j = 0; j < kRightJoints; ++j) seed_right_(j) = seed(j);
  for (unsigned j = 0; j < kLeftJoints; ++j) seed_left_(j) = seed(kRightJoints + j);
  IkStatus status = right_.inverseOnBranch(stitch_target, seed_right_, rightBranch(on_branch), q_right_);
  if (status == IkStatus::Ok) status = solveGripperArm(gripper_target, leftBranch(on_branch));
  if (status != IkStatus::Ok) return status;
  for (unsigned j = 0; j < kRightJoints; ++j) q_out(j) = q_right_(j);
  for (unsigned j = 0; j < kLeftJoints; ++j) q_out(kRightJoints + j) = q_left_(j);
  return IkStatus::Ok;
}

IkStatus IsurSuturingSolver::inverseEndoStitchArm(const KDL::Frame& stitch_target, const KDL::JntArray& q,
                                                  IkBranch right_branch, KDL::JntArray& q_out) noexcept {
  if (!validJointArray(q, kJoints) || q_out.rows() != kJoints) return IkStatus::BadInput;
  for (unsigned j = 0; j < kRightJoints; ++j) seed_right_(j) = q(j);
  const IkStatus status = right_.inverseOnBranch(stitch_target, seed_right_, right_branch, q_right_);
  if (status != IkStatus::Ok) return status;
  for (unsigned j = 0; j < kLeftJoints; ++j) q_out(kRightJoints + j) = q(kRightJoints + j);
  for (unsigned j = 0; j < kRightJoints; ++j) q_out(j) = q_right_(j);
  return IkStatus::Ok;
}

IkStatus IsurSuturingSolver::solveGripperArm(const KDL::Frame& gripper_target, IkBranch left_branch) noexcept {
  KDL::Frame platform;
  const IkStatus status = right_.platformPose(q_right_, platform);
  if (status != IkStatus::Ok) return status;
  return left_.inverseOnBranch((platform * left_mount_).Inverse() * gripper_target, seed_left_, left_branch, q_left_);
}

IkStatus IsurSuturingSolver::inverseGripperArm(const KDL::Frame& gripper_target, const KDL::JntArray& q,
                                               IkBranch left_branch, KDL::JntArray& q_out) noexcept {
  if (!validJointArray(q, kJoints) || q_out.rows() != kJoints || !validFrame(gripper_target)) return IkStatus::BadInput;
  for (unsigned j = 0; j < kRightJoints; ++j) q_right_(j) = q(j);
  for (unsigned j = 0; j < kLeftJoints; ++j) seed_left_(j) = q(kRightJoints + j);
  const IkStatus status = solveGripperArm(gripper_target, left_branch);
  if (status != IkStatus::Ok) return status;
  for (unsigned j = 0; j < kRightJoints; ++j) q_out(j) = q(j);
  for (unsigned j = 0; j < kLeftJoints; ++j) q_out(kRightJoints + j) = q_left_(j);
  return IkStatus::Ok;
}

}  // namespace cobra::kinematics
