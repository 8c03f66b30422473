// Unit tests of continuity.hpp: ContinuousIk accepts the small steps of smooth joint paths (seeded
// random paths on the UR5, the Puma 260 and the I-SUR) and refuses what would swing the arm: a UR5
// elbow or wrist branch change, a step beyond max_velocity · dt, a command across the I-SUR's
// wrist singularity (vertical needle). Also: the branch is free on a singular boundary, solver
// failures pass through, bad input and construction errors, no allocation.

#include "cobra/kinematics/continuity.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <vector>

#include "cobra/kinematics/isur.hpp"
#include "cobra/kinematics/puma260.hpp"
#include "cobra/kinematics/ur5.hpp"
#include "cobra/test_support/counting_new.hpp"
#include "cobra/test_support/test_support.hpp"
#include "kinematics_test_support.hpp"

namespace cobra::kinematics {
namespace {

using cobra::test_support::allocationsDuring;
using cobra::test_support::messageOf;
using test::filled;
using test::isFilled;
using test::joints;
constexpr double kPi = std::numbers::pi;

KDL::Frame poseOf(KinematicsSolver& solver, const KDL::JntArray& q) {
  KDL::Frame pose;
  EXPECT_EQ(solver.forward(q, pose), IkStatus::Ok);
  return pose;
}

double poseError(KinematicsSolver& solver, const KDL::JntArray& q, const KDL::Frame& target) {
  const KDL::Frame reached = poseOf(solver, q);
  return std::max(norm(reached.p - target.p), orientationError(reached.M, target.M));
}

/// A smooth joint path q(t) = q0 + a·sin(ω t + φ) per joint, amplitude `amplitude` (rad, or
/// `amplitude_m` m for prismatic joints), ω in [1, 3] rad/s, that stays on one branch of `solver`
/// (not ambiguous at any of its samples) and inside the limits.
struct SmoothPath {
  KDL::JntArray q0, amplitude, omega, phase;

  KDL::JntArray at(double t) const {
    KDL::JntArray q = q0;
    for (unsigned j = 0; j < q.rows(); ++j) q(j) += amplitude(j) * std::sin(omega(j) * t + phase(j));
    return q;
  }
};

/// Makes a path the I-SUR's redundancy resolution reproduces: its base yaw q4 holds still
/// (yaw_share 0) and the pitch joints q6, q7 move alike (pitch_share 0.5).
void followIsurShares(SmoothPath& path) {
  path.amplitude(3) = 0.0;
  path.amplitude(6) = path.amplitude(5);
  path.omega(6) = path.omega(5);
  path.phase(6) = path.phase(5);
}

SmoothPath randomPathOnOneBranch(KinematicsSolver& solver, std::mt19937& rng, double amplitude, double amplitude_m,
                                 int steps, double dt, void (*shape)(SmoothPath&)) {
  const JointLimits& limits = solver.limits();
  std::uniform_real_distribution<double> omega(1.0, 3.0);
  std::uniform_real_distribution<double> phase(-kPi, kPi);
  for (;;) {
    SmoothPath path{KDL::JntArray(solver.jointCount()), KDL::JntArray(solver.jointCount()),
                    KDL::JntArray(solver.jointCount()), KDL::JntArray(solver.jointCount())};
    for (unsigned j = 0; j < solver.jointCount(); ++j) {
      const double a = limits.types[j] == JointType::Prismatic ? amplitude_m : amplitude;
      const double lo = std::max(limits.lower[j] + a + 1e-3, -3.0);
      const double hi = std::min(limits.upper[j] - a - 1e-3, 3.0);
      path.q0(j) = std::uniform_real_distribution<double>(lo, hi)(rng);
      path.amplitude(j) = a;
      path.omega(j) = omega(rng);
      path.phase(j) = phase(rng);
    }
    if (shape != nullptr) shape(path);
    const KDL::JntArray start = path.at(0.0);
    const IkBranch branch = solver.branch({start.data.data(), start.rows()});
    KDL::Frame pose;
    bool usable = branch.ambiguous == 0 && solver.forward(start, pose) == IkStatus::Ok;
    for (int k = 1; usable && k <= steps; ++k) {
      const KDL::JntArray q = path.at(k * dt);
      // Off a singular configuration by a margin: a path that grazes one is not "smooth" in
      // Cartesian space (the joints' share of a small pose change grows without bound there).
      const IkBranch here = solver.branch({q.data.data(), q.rows()});
      usable = here == branch && solver.forward(q, pose) == IkStatus::Ok;
    }
    if (usable) return path;
  }
}

/// `paths` seeded random smooth paths (shaped by `shape` when given): the Cartesian targets
/// FK(q(t)) every dt are all accepted from the previous accepted joints and give back q(t).
void checkSmoothPathsAccepted(KinematicsSolver& solver, unsigned seed, int paths, double max_velocity,
                              double max_velocity_m, double amplitude_m = 0.0,
                              void (*shape)(SmoothPath&) = nullptr) {
  constexpr int kSteps = 150;
  constexpr double kDt = 0.01;  // s; amplitude 0.2 rad at ω <= 3 rad/s: <= 0.006 rad per step
  std::vector<double> velocity(solver.jointCount());
  for (unsigned j = 0; j < solver.jointCount(); ++j)
    velocity[j] = solver.limits().types[j] == JointType::Prismatic ? max_velocity_m : max_velocity;
  ContinuousIk continuous(solver, velocity, kDt);
  std::mt19937 rng(seed);
  int accepted = 0;
  for (int p = 0; p < paths; ++p) {
    const SmoothPath path = randomPathOnOneBranch(solver, rng, 0.2, amplitude_m, kSteps, kDt, shape);
    KDL::JntArray current = path.at(0.0);
    KDL::JntArray out(solver.jointCount());
    for (int k = 1; k <= kSteps; ++k) {
      const KDL::JntArray q = path.at(k * kDt);
      const KDL::Frame target = poseOf(solver, q);
      const IkStatus status = continuous.solve(target, current, out);
      ASSERT_EQ(status, IkStatus::Ok) << solver.name() << " path " << p << " step " << k << ": joint "
                                      << continuous.lastRefusal().joint + 1 << " step "
                                      << continuous.lastRefusal().step << " > " << continuous.lastRefusal().allowed
                                      << (continuous.lastRefusal().branch_change ? " (branch change)" : "");
      EXPECT_LT(poseError(solver, out, target), 1e-8) << solver.name() << " path " << p << " step " << k;
      for (unsigned j = 0; j < q.rows(); ++j)
        EXPECT_NEAR(out(j), q(j), 1e-7) << solver.name() << " path " << p << " step " << k << " joint " << j + 1;
      current = out;
      ++accepted;
    }
  }
  EXPECT_EQ(accepted, paths * kSteps);
}

TEST(ContinuousIk, SmallStepsAlongRandomSmoothPathsAreAccepted) {
  // 40 paths x 150 steps per robot, seeded.
  Ur5Solver ur5;
  checkSmoothPathsAccepted(ur5, 11, 40, 1.0, 1.0);
  Puma260Solver puma;
  checkSmoothPathsAccepted(puma, 12, 40, 1.0, 1.0);
  // The I-SUR is redundant (yaw and pitch split between two joints each): with the seed-share
  // rule its paths follow the solver's shares, so that the solution is q(t). Sliders: 1 cm.
  IsurGeometry shares;
  shares.base_angle = shares.pitch_difference = std::numeric_limits<double>::quiet_NaN();
  IsurPuncturingSolver isur(shares);
  checkSmoothPathsAccepted(isur, 13, 40, 1.5, 1.0, 0.01, followIsurShares);
}

TEST(ContinuousIk, AStepBeyondMaxVelocityTimesDtIsRefusedAndNamesTheJoint) {
  Ur5Solver ur5;
  ContinuousIk continuous(ur5, std::vector<double>(6, 1.0), 0.01);  // 0.01 rad per period
  const KDL::JntArray current = joints({0.3, -1.2, 1.4, -1.6, -1.5, 0.2});
  KDL::JntArray goal = current;
  goal(1) += 0.05;
  KDL::JntArray out = filled(6, 7.0);
  EXPECT_EQ(continuous.solve(poseOf(ur5, goal), current, out), IkStatus::Discontinuous);
  EXPECT_TRUE(isFilled(out, 7.0));
  EXPECT_FALSE(continuous.lastRefusal().branch_change);
  EXPECT_EQ(continuous.lastRefusal().joint, 1);
  EXPECT_NEAR(continuous.lastRefusal().step, 0.05, 1e-9);
  EXPECT_DOUBLE_EQ(continuous.lastRefusal().allowed, 0.01);
  // The same step over a longer dt is accepted: the rule is a velocity.
  EXPECT_EQ(continuous.solve(poseOf(ur5, goal), current, 0.05, out), IkStatus::Ok);
  EXPECT_NEAR(out(1), goal(1), 1e-9);
}

TEST(ContinuousIk, Ur5ElbowFlipIsRefused) {
  // q3 limited to [-π, 0.3]: at q3 = 0.25 (elbow bit 0), a pose whose elbow-up solution needs
  // q3 = 0.35 is only reachable with the elbow flipped (q3 = -0.35, q2 and q4 far away). The plain
  // nearest-solution IK takes the flip; the continuous one refuses it.
  JointLimits limits = Ur5Solver::defaultLimits();
  limits.lower[2] = -kPi;
  limits.upper[2] = 0.3;
  Ur5Solver ur5(Ur5Parameters{}, limits);
  const KDL::JntArray current = joints({0.2, -1.0, 0.25, -0.8, 1.2, 0.4});
  KDL::JntArray beyond = current;
  beyond(2) = 0.35;
  const KDL::Frame target = poseOf(ur5, beyond);
  KDL::JntArray flipped(6);
  ASSERT_EQ(ur5.inverse(target, current, flipped), IkStatus::Ok);
  EXPECT_LT(flipped(2), 0.0);
  EXPECT_GT(std::abs(flipped(1) - current(1)), 0.3) << "the flip swings the upper arm";

  ContinuousIk continuous(ur5, std::vector<double>(6, 3.14), 0.5);  // even 1.57 rad per period
  KDL::JntArray out = filled(6, 7.0);
  EXPECT_EQ(continuous.solve(target, current, out), IkStatus::Discontinuous);
  EXPECT_TRUE(continuous.lastRefusal().branch_change);
  EXPECT_EQ(continuous.lastRefusal().joint, -1);
  EXPECT_TRUE(isFilled(out, 7.0));
  // The current pose itself is accepted: no flip, no motion.
  EXPECT_EQ(continuous.solve(poseOf(ur5, current), current, out), IkStatus::Ok);
  for (unsigned j = 0; j < 6; ++j) EXPECT_NEAR(out(j), current(j), 1e-9);
}

TEST(ContinuousIk, Ur5WristSingularityCrossingIsRefusedButTheSingularityItselfIsFree) {
  // From q5 = 0.01 to q5 = -0.01 the joints move 0.02 rad, but the wrist changes branch: on the
  // current branch the same pose needs q4 and q6 turned by π. Refused (step of q4 or q6 ~ π).
  Ur5Solver ur5;
  ContinuousIk continuous(ur5, std::vector<double>(6, 3.14), 0.01);
  const KDL::JntArray current = joints({0.1, -1.3, 1.5, -1.7, 0.01, 0.3});
  KDL::JntArray across = current;
  across(4) = -0.01;
  KDL::JntArray out = filled(6, 7.0);
  EXPECT_EQ(continuous.solve(poseOf(ur5, across), current, out), IkStatus::Discontinuous);
  EXPECT_FALSE(continuous.lastRefusal().branch_change);
  EXPECT_TRUE(continuous.lastRefusal().joint == 3 || continuous.lastRefusal().joint == 5);
  EXPECT_NEAR(continuous.lastRefusal().step, kPi, 0.1);
  EXPECT_TRUE(isFilled(out, 7.0));
  // Exactly on the singularity (q5 = 0) the wrist bit is ambiguous: either side may follow.
  KDL::JntArray singular = current;
  singular(4) = 0.0;
  EXPECT_EQ(ur5.branch({singular.data.data(), 6}).ambiguous, 4);
  EXPECT_EQ(continuous.solve(poseOf(ur5, across), singular, out), IkStatus::Ok);
  EXPECT_NEAR(out(4), -0.01, 1e-9);
}

TEST(ContinuousIk, IsurCommandAcrossTheWristSingularityIsRefused) {
  // The needle tilts through the vertical (pitch q6 + q7 from 90° - 0.3° to 90° + 0.3°): 0.005 rad
  // per pitch joint. Kept on its branch the same orientation needs yaw turned by π; the base and
  // micro yaw joints cannot do that in one period. The plain IK takes the other representation.
  IsurPuncturingSolver isur;
  const std::vector<double> velocity = {0.1, 0.1, 0.1, 1.5, 1.5, 1.5, 1.5, 1.5};
  ContinuousIk continuous(isur, velocity, 0.01);
  const KDL::JntArray current = joints({0.1, 0.1, 0.1, 0.2, 0.1, kPi / 4 - 0.005, kPi / 4, 0.3});
  KDL::JntArray across = current;
  across(5) += 0.005;
  across(6) += 0.005;
  ASSERT_GT(std::cos(current(5) + current(6)), 0.0);
  ASSERT_LT(std::cos(across(5) + across(6)), 0.0);
  const KDL::Frame target = poseOf(isur, across);
  KDL::JntArray plain(8);
  ASSERT_EQ(isur.inverse(target, current, plain), IkStatus::Ok);
  EXPECT_LT(poseError(isur, plain, target), 1e-9);
  EXPECT_NE(isur.branch({plain.data.data(), 8}).bits, isur.branch({current.data.data(), 8}).bits);

  KDL::JntArray out = filled(8, 7.0);
  EXPECT_EQ(continuous.solve(target, current, out), IkStatus::Discontinuous);
  EXPECT_TRUE(isFilled(out, 7.0));
  // The current branch reaches the target, but with yaw (q4 + q5) and roll (q8) turned by π.
  const ContinuityRefusal& refusal = continuous.lastRefusal();
  EXPECT_FALSE(refusal.branch_change);
  EXPECT_TRUE(refusal.joint == 3 || refusal.joint == 4 || refusal.joint == 7) << "joint " << refusal.joint + 1;
  EXPECT_GT(refusal.step, 1.0);
  EXPECT_DOUBLE_EQ(refusal.allowed, 0.015);
  KDL::JntArray on_branch(8);
  ASSERT_EQ(isur.inverseOnBranch(target, current, isur.branch({current.data.data(), 8}), on_branch), IkStatus::Ok);
  EXPECT_NEAR(std::abs(wrapToPi(on_branch(3) + on_branch(4) - current(3) - current(4))), kPi, 0.05) << "yaw swing";
  // The vertical needle itself (the boundary) is reachable from either side.
  KDL::JntArray vertical = current;
  vertical(5) += 0.0025;
  vertical(6) += 0.0025;
  EXPECT_EQ(continuous.solve(poseOf(isur, vertical), current, out), IkStatus::Ok);
  EXPECT_LT(poseError(isur, out, poseOf(isur, vertical)), 1e-9);
}

TEST(ContinuousIk, SolverFailuresPassThrough) {
  Ur5Solver ur5;
  ContinuousIk continuous(ur5, std::vector<double>(6, 3.14), 0.01);
  const KDL::JntArray current = joints({0.1, -1.3, 1.5, -1.7, -1.5, 0.3});
  KDL::JntArray out = filled(6, 7.0);
  EXPECT_EQ(continuous.solve(KDL::Frame(KDL::Vector(3.0, 0.0, 0.0)), current, out), IkStatus::Unreachable);
  EXPECT_TRUE(isFilled(out, 7.0));
}

TEST(ContinuousIk, BadInputLeavesTheOutputUntouched) {
  Ur5Solver ur5;
  ContinuousIk continuous(ur5, std::vector<double>(6, 3.14), 0.01);
  const KDL::JntArray current = joints({0.1, -1.3, 1.5, -1.7, -1.5, 0.3});
  const KDL::Frame target = poseOf(ur5, current);
  KDL::JntArray out = filled(6, 7.0);
  EXPECT_EQ(continuous.solve(target, joints({0.1, 0.2}), out), IkStatus::BadInput);
  KDL::JntArray nan_joint = current;
  nan_joint(3) = std::nan("");
  EXPECT_EQ(continuous.solve(target, nan_joint, out), IkStatus::BadInput);
  EXPECT_EQ(continuous.solve(target, current, 0.0, out), IkStatus::BadInput);
  EXPECT_EQ(continuous.solve(target, current, -0.01, out), IkStatus::BadInput);
  EXPECT_EQ(continuous.solve(target, current, std::nan(""), out), IkStatus::BadInput);
  EXPECT_TRUE(isFilled(out, 7.0));
  KDL::JntArray wrong_out(5);
  EXPECT_EQ(continuous.solve(target, current, wrong_out), IkStatus::BadInput);
  EXPECT_STREQ(toString(IkStatus::Discontinuous), "discontinuous");
}

TEST(ContinuousIk, ConstructionErrorsNameTheRobotAndTheJoint) {
  Ur5Solver ur5;
  EXPECT_EQ(messageOf([&] { ContinuousIk(ur5, std::vector<double>(5, 1.0), 0.01); }),
            "UR5: max_velocity has 5 values; the robot has 6 joints: give one limit per joint (rad/s, m/s)");
  EXPECT_EQ(messageOf([&] { ContinuousIk(ur5, {1.0, 1.0, 0.0, 1.0, 1.0, 1.0}, 0.01); }),
            "UR5: max_velocity of joint 3 is 0 rad/s: give a finite value > 0");
  EXPECT_EQ(messageOf([&] { ContinuousIk(ur5, std::vector<double>(6, 1.0), 0.0); }),
            "UR5: continuity period is 0 s: give a finite value > 0");
  IsurPuncturingSolver isur;
  EXPECT_EQ(messageOf([&] { ContinuousIk(isur, {1.0, -1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0}, 0.01); }),
            "I-SUR: max_velocity of joint 2 is -1 m/s: give a finite value > 0");
}

TEST(ContinuousIk, SolveAllocatesNothing) {
  Ur5Solver ur5;
  ContinuousIk on_ur5(ur5, std::vector<double>(6, 3.14), 0.01);
  const KDL::JntArray q = joints({0.1, -1.3, 1.5, -1.7, -1.5, 0.3});
  KDL::JntArray goal = q;
  goal(0) += 0.001;
  const KDL::Frame target = poseOf(ur5, goal);
  KDL::JntArray out(6);
  EXPECT_EQ(allocationsDuring([&] { EXPECT_EQ(on_ur5.solve(target, q, out), IkStatus::Ok); }), 0);
  goal(0) += 1.0;
  const KDL::Frame far = poseOf(ur5, goal);
  EXPECT_EQ(allocationsDuring([&] { EXPECT_EQ(on_ur5.solve(far, q, out), IkStatus::Discontinuous); }), 0);

  IsurPuncturingSolver isur;
  ContinuousIk on_isur(isur, std::vector<double>(8, 1.5), 0.01);
  const KDL::JntArray qi = joints({0.1, 0.1, 0.1, 0.0, 0.0, 0.6, 0.6, 0.0});
  KDL::JntArray out_isur(8);
  const KDL::Frame isur_target = poseOf(isur, qi);
  EXPECT_EQ(allocationsDuring([&] { EXPECT_EQ(on_isur.solve(isur_target, qi, out_isur), IkStatus::Ok); }), 0);
}

}  // namespace
}  // namespace cobra::kinematics
