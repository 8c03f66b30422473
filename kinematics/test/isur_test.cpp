// Unit tests of isur.hpp: the I-SUR puncturing robot (delta + base revolute + 4-DOF micro arm) —
// FK against a KDL chain built joint by joint, the thesis' ZYX relations (yaw = q4 + q5, pitch =
// q6 + q7, roll = q8), IK round trips on seeded random configurations, the redundancy shares,
// continuity in the seed, the gimbal lock, unreachable and out-of-limit targets, construction
// errors, no allocation — and the 14-DOF suturing robot (second, 6-DOF arm solved in closed form
// from the platform pose).

#include "cobra/kinematics/isur.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <kdl/chainfksolverpos_recursive.hpp>
#include <limits>
#include <numbers>
#include <random>
#include <utility>

#include "cobra/kinematics/geometry.hpp"
#include "cobra/test_support/counting_new.hpp"
#include "cobra/test_support/test_support.hpp"
#include "kinematics_test_support.hpp"

namespace cobra::kinematics {
namespace {

using cobra::test_support::allocationsDuring;
using cobra::test_support::messageOf;
constexpr double kPi = std::numbers::pi;

/// Joints of a needle pointing straight down: pitch q6 + q7 exactly +90° with `isur`'s default
/// elbow q6 - q7, yaw q4 + q5 = -0.1 rad, roll q8 = 0.7 rad (sliders 0.1, 0.12, 0.08 m).
KDL::JntArray atTheGimbalLock(const IsurPuncturingSolver& isur) {
  KDL::JntArray q(8);
  q(0) = 0.1;
  q(1) = 0.12;
  q(2) = 0.08;
  q(3) = 0.2;
  q(4) = -0.3;
  q(5) = 0.5 * (kPi / 2 + isur.geometry().pitch_difference);
  q(6) = kPi / 2 - q(5);
  q(7) = 0.7;
  return q;
}

KDL::JntArray randomJoints(const JointLimits& limits, std::mt19937& rng, double margin_fraction = 0.1) {
  KDL::JntArray q(static_cast<unsigned>(limits.size()));
  for (unsigned i = 0; i < q.rows(); ++i) {
    const double margin = margin_fraction * (limits.upper[i] - limits.lower[i]);
    std::uniform_real_distribution<double> value(limits.lower[i] + margin, limits.upper[i] - margin);
    q(i) = value(rng);
  }
  return q;
}

/// The seed-share redundancy rule (base_angle and pitch_difference NaN): the rule whose round trip
/// gives any configuration back.
IsurGeometry seedShareGeometry() {
  IsurGeometry geometry;
  geometry.base_angle = std::numeric_limits<double>::quiet_NaN();
  geometry.pitch_difference = std::numeric_limits<double>::quiet_NaN();
  return geometry;
}

// 1000 seeded random configurations: FK equals KDL's FK of the equivalent serial chain fed with
// the delta's platform position, and the needle orientation is Rz(q4 + q5)·Ry(q6 + q7)·Rx(q8).
TEST(IsurPuncturing, ForwardMatchesKdlAndTheThesisZyxRelations) {
  IsurPuncturingSolver isur;
  const KDL::Chain chain = cartesianMacroChain(isur.geometry().micro);
  KDL::ChainFkSolverPos_recursive kdl(chain);
  std::mt19937 rng(41);
  for (int i = 0; i < 1000; ++i) {
    const KDL::JntArray q = randomJoints(isur.limits(), rng, 0.0);
    KDL::Frame pose;
    ASSERT_EQ(isur.forward(q, pose), IkStatus::Ok);
    KDL::Vector p_delta;
    ASSERT_EQ(isur.macro().forwardPosition(std::span<const double, 3>(q.data.data(), 3), p_delta), IkStatus::Ok);
    KDL::JntArray chain_q(8);
    chain_q(0) = q(3);
    chain_q(1) = p_delta.x();
    chain_q(2) = p_delta.y();
    chain_q(3) = p_delta.z();
    for (unsigned j = 4; j < 8; ++j) chain_q(j) = q(j);
    KDL::Frame by_kdl;
    ASSERT_GE(kdl.JntToCart(chain_q, by_kdl), 0);
    EXPECT_LT(norm(pose.p - by_kdl.p), 1e-12);
    EXPECT_LT(orientationError(pose.M, by_kdl.M), 1e-12);
    const KDL::Rotation zyx =
        KDL::Rotation::RotZ(q(3) + q(4)) * KDL::Rotation::RotY(q(5) + q(6)) * KDL::Rotation::RotX(q(7));
    EXPECT_LT(orientationError(pose.M, zyx), 1e-12);
  }
}

// 2000 seeded random configurations in the limits: IK of their pose seeded with them gives them
// back (1e-9), and seeded 0.05 rad / 5 mm away reaches the pose within 1e-9 m / 1e-9 rad, within
// the limits, with a configuration that moved little (the decomposition is continuous in the seed).
TEST(IsurPuncturing, RandomPosesRoundTrip) {
  IsurPuncturingSolver isur(seedShareGeometry());
  std::mt19937 rng(42);
  std::uniform_real_distribution<double> noise(-1.0, 1.0);
  KDL::JntArray out(8);
  int solved_near = 0;
  for (int i = 0; i < 2000; ++i) {
    const KDL::JntArray q = randomJoints(isur.limits(), rng);
    KDL::Frame target;
    ASSERT_EQ(isur.forward(q, target), IkStatus::Ok);
    ASSERT_EQ(isur.inverse(target, q, out), IkStatus::Ok) << "pose " << i;
    for (unsigned j = 0; j < 8; ++j) EXPECT_NEAR(out(j), q(j), 1e-9) << "pose " << i << " joint " << j + 1;

    KDL::JntArray seed = q;
    for (unsigned j = 0; j < 3; ++j) seed(j) += 0.005 * noise(rng);
    for (unsigned j = 3; j < 8; ++j) seed(j) += 0.05 * noise(rng);
    const IkStatus status = isur.inverse(target, seed, out);
    if (status != IkStatus::Ok) {
      EXPECT_EQ(status, IkStatus::JointLimits) << "pose " << i;  // the new split may push the delta out of stroke
      continue;
    }
    ++solved_near;
    KDL::Frame reached;
    ASSERT_EQ(isur.forward(out, reached), IkStatus::Ok);
    EXPECT_LT(norm(reached.p - target.p), 1e-9) << "pose " << i;
    // Within the wrist band (needle vertical) the tilt across the seed's yaw plane is not followed.
    const bool vertical = std::abs(std::cos(q(5) + q(6))) < IsurPuncturingSolver::kWristBand;
    EXPECT_LT(orientationError(reached.M, target.M), vertical ? IsurPuncturingSolver::kWristBand : 1e-9)
        << "pose " << i;
    EXPECT_TRUE(isur.limits().contains(out, 1e-12));
    for (unsigned j = 3; j < 8; ++j) EXPECT_LT(std::abs(out(j) - q(j)), 0.11) << "pose " << i << " joint " << j + 1;
  }
  EXPECT_GE(solved_near, 1900);
}

// The shares decide which joint of each redundant pair moves: yaw_share 1 turns the base revolute
// only, 0 the micro yaw joint only; pitch_share 0.5 moves q6 and q7 by the same amount.
TEST(IsurPuncturing, RedundancySharesChooseTheMovingJoint) {
  KDL::JntArray seed(8);
  seed(0) = seed(1) = seed(2) = 0.1;
  seed(5) = 0.3;
  seed(6) = 0.4;
  for (const double yaw_share : {0.0, 1.0}) {
    IsurGeometry geometry = seedShareGeometry();
    geometry.yaw_share = yaw_share;
    IsurPuncturingSolver isur(geometry);
    KDL::JntArray moved = seed;
    moved(3) += 0.2 * yaw_share;
    moved(4) += 0.2 * (1.0 - yaw_share);
    moved(5) += 0.1;
    moved(6) += 0.1;
    KDL::Frame target;
    ASSERT_EQ(isur.forward(moved, target), IkStatus::Ok);
    KDL::JntArray out(8);
    ASSERT_EQ(isur.inverse(target, seed, out), IkStatus::Ok);
    for (unsigned j = 0; j < 8; ++j)
      EXPECT_NEAR(out(j), moved(j), 1e-9) << "yaw_share " << yaw_share << " joint " << j + 1;
  }
}

TEST(IsurPuncturing, AtTheGimbalLockTheSeedsYawIsKeptAndTheRollTurns) {
  IsurPuncturingSolver isur;
  const KDL::JntArray q = atTheGimbalLock(isur);
  KDL::Frame target;
  ASSERT_EQ(isur.forward(q, target), IkStatus::Ok);
  // The seed's yaw q4 + q5 is 0.2 rad off the target's: the yaw stays the seed's, the roll makes
  // up for it (at the lock only yaw - roll is defined), and the pose is reached exactly.
  KDL::JntArray seed = q;
  seed(4) = -0.1;
  KDL::JntArray out(8);
  ASSERT_EQ(isur.inverse(target, seed, out), IkStatus::Ok);
  EXPECT_NEAR(out(3) + out(4), seed(3) + seed(4), 1e-12);
  EXPECT_NEAR(out(7), 0.7 + 0.2, 1e-9);
  KDL::Frame reached;
  isur.forward(out, reached);
  EXPECT_LT(norm(reached.p - target.p), 1e-9);
  EXPECT_LT(orientationError(reached.M, target.M), 1e-9);
}

TEST(IsurPuncturing, NearTheGimbalLockATiltAcrossTheYawPlaneDoesNotTurnTheYaw) {
  // A needle 1e-4 rad from vertical, tilted across the seed's yaw plane in a random direction
  // (what rounding in an admittance's output does): outside the band the yaw would follow the
  // tilt's direction (up to π); inside it stays the seed's, the orientation error is the dropped
  // tilt only (<= 1e-3 rad), and the position is exact. Seeded, 200 directions.
  IsurPuncturingSolver isur;
  const KDL::JntArray seed = atTheGimbalLock(isur);
  KDL::Frame vertical;
  ASSERT_EQ(isur.forward(seed, vertical), IkStatus::Ok);
  std::mt19937 rng(15);
  std::uniform_real_distribution<double> direction(-kPi, kPi);
  KDL::JntArray out(8);
  for (int i = 0; i < 200; ++i) {
    const double a = direction(rng);
    const KDL::Frame target(KDL::Rotation::Rot(KDL::Vector(std::cos(a), std::sin(a), 0.0), 1e-4) * vertical.M,
                            vertical.p);
    ASSERT_EQ(isur.inverse(target, seed, out), IkStatus::Ok) << "direction " << a;
    EXPECT_NEAR(out(3) + out(4), seed(3) + seed(4), 1e-12) << "direction " << a;
    KDL::Frame reached;
    isur.forward(out, reached);
    EXPECT_LT(norm(reached.p - target.p), 1e-9) << "direction " << a;
    EXPECT_LE(orientationError(reached.M, target.M), 1e-4 + 1e-9) << "direction " << a;
  }
}

TEST(IsurPuncturing, UnreachableAndOutOfLimitTargetsLeaveTheOutputUntouched) {
  KDL::JntArray seed(8);
  seed(0) = seed(1) = seed(2) = 0.1;
  KDL::JntArray out = test::filled(8, 42.0);
  IsurPuncturingSolver isur;
  EXPECT_EQ(isur.inverse(KDL::Frame(KDL::Vector(0.0, 0.0, -3.0)), seed, out), IkStatus::Unreachable);
  // Roll limited to ±0.5 rad: a needle rolled by 2 rad (or, flipped, by 2 - π) cannot be held.
  IsurGeometry narrow;
  narrow.lower[4] = -0.5;
  narrow.upper[4] = 0.5;
  IsurPuncturingSolver limited(narrow);
  KDL::JntArray q = seed;
  q(7) = 2.0;
  KDL::Frame target;
  ASSERT_EQ(isur.forward(q, target), IkStatus::Ok);
  EXPECT_EQ(limited.inverse(target, seed, out), IkStatus::JointLimits);
  EXPECT_TRUE(test::isFilled(out, 42.0));
  EXPECT_EQ(isur.inverse(target, KDL::JntArray(7), out), IkStatus::BadInput);
}

TEST(IsurPuncturing, ConstructionErrorsNameTheElement) {
  IsurGeometry g;
  g.yaw_share = 2.0;
  EXPECT_EQ(messageOf([&] { IsurPuncturingSolver{g}; }), "I-SUR: parameter yaw_share is 2: give a value in [0, 1]");
  g = IsurGeometry{};
  g.lower[1] = 1.0;
  g.upper[1] = 0.0;
  EXPECT_EQ(messageOf([&] { IsurPuncturingSolver{g}; }), "I-SUR: joint 5 limits [1, 0] rad: min must be <= max");
  g = IsurGeometry{};
  g.macro.actuators[1].rod_length = 0.0;
  EXPECT_EQ(messageOf([&] { IsurPuncturingSolver{g}; }), "I-SUR macro: actuator 2 rod length 0 m: must be > 0");
  g = IsurGeometry{};
  g.micro.forearm = std::nan("");
  EXPECT_EQ(messageOf([&] { IsurPuncturingSolver{g}; }),
            "I-SUR: parameter micro.forearm is nan: give a finite value in m");
}

TEST(IsurPuncturing, RealTimeCallsAllocateNothing) {
  IsurPuncturingSolver isur;
  KDL::JntArray q(8);
  q(0) = 0.1;
  q(1) = 0.12;
  q(2) = 0.08;
  q(5) = 0.4;
  KDL::JntArray out(8);
  KDL::Frame pose;
  EXPECT_EQ(allocationsDuring([&] { isur.forward(q, pose); }), 0);
  EXPECT_EQ(allocationsDuring([&] { EXPECT_EQ(isur.inverse(pose, q, out), IkStatus::Ok); }), 0);
}

// The puncturing setup's rule (default geometry): on the rule, the solution is a function of the
// pose alone (seeds on the rule anywhere give the same joints); a seed off the rule is brought
// back by at most 5e-4 rad per solve; beyond the delta's stroke the elbow moves, continuously
// along a path, and comes back to pitch_difference. Seeded, 300 poses.
TEST(IsurPuncturing, OnTheRuleTheSolutionIsAFunctionOfThePose) {
  IsurPuncturingSolver isur;
  const IsurGeometry& g = isur.geometry();
  std::mt19937 rng(44);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const auto onRule = [&](double yaw, double pitch, double roll, const KDL::JntArray& sliders) {
    KDL::JntArray q = sliders;
    q(3) = std::clamp(g.base_angle, yaw - g.upper[1], yaw - g.lower[1]);
    q(4) = yaw - q(3);
    q(5) = 0.5 * (pitch + g.pitch_difference);
    q(6) = 0.5 * (pitch - g.pitch_difference);
    q(7) = roll;
    return q;
  };
  KDL::JntArray out(8), again(8);
  int compared = 0;
  for (int i = 0; i < 300; ++i) {
    KDL::JntArray sliders(8);
    for (unsigned j = 0; j < 3; ++j) sliders(j) = 0.1 + 0.05 * unit(rng);
    const KDL::JntArray q = onRule(2.5 * unit(rng), 1.2 * unit(rng), 2.0 * unit(rng), sliders);
    KDL::Frame pose;
    if (isur.forward(q, pose) != IkStatus::Ok || !isur.limits().contains(q, 0.0)) continue;
    // Another seed on the rule, 0.2 rad of yaw and pitch and 2 cm away.
    const KDL::JntArray seed = onRule(q(3) + q(4) + 0.2 * unit(rng), q(5) + q(6) + 0.2 * unit(rng), q(7), sliders);
    ASSERT_EQ(isur.inverse(pose, q, out), IkStatus::Ok) << "pose " << i;
    ASSERT_EQ(isur.inverse(pose, seed, again), IkStatus::Ok) << "pose " << i;
    for (unsigned j = 0; j < 8; ++j) {
      EXPECT_NEAR(out(j), q(j), 1e-9) << "pose " << i << " joint " << j + 1;
      EXPECT_NEAR(again(j), q(j), 1e-9) << "pose " << i << " joint " << j + 1;
    }
    ++compared;
  }
  EXPECT_GE(compared, 150);
}

TEST(IsurPuncturing, ASeedOffTheRuleIsBroughtBackByAtMostHalfAMilliradianPerSolve) {
  IsurPuncturingSolver isur;
  KDL::JntArray q(8);
  q(0) = q(1) = q(2) = 0.1;
  q(3) = 0.3;  // base off its angle (0) while the micro yaw is far from its limits
  q(4) = -0.1;
  q(5) = 0.9;  // elbow q6 - q7 = 0.6, not 0.3
  q(6) = 0.3;
  KDL::Frame pose;
  ASSERT_EQ(isur.forward(q, pose), IkStatus::Ok);
  KDL::JntArray seed = q, out(8);
  for (int step = 0; step < 2000; ++step) {
    ASSERT_EQ(isur.inverse(pose, seed, out), IkStatus::Ok) << "step " << step;
    for (unsigned j = 3; j < 8; ++j) EXPECT_LE(std::abs(out(j) - seed(j)), 5e-4 + 1e-12) << "step " << step;
    KDL::Frame reached;
    isur.forward(out, reached);
    EXPECT_LT(norm(reached.p - pose.p), 1e-9);
    EXPECT_LT(orientationError(reached.M, pose.M), 1e-9);
    seed = out;
  }
  EXPECT_NEAR(out(3), 0.0, 1e-12);
  EXPECT_NEAR(out(5) - out(6), isur.geometry().pitch_difference, 1e-12);
}

TEST(IsurPuncturing, BeyondTheDeltasStrokeTheElbowMovesContinuouslyAndComesBack) {
  IsurPuncturingSolver isur;
  KDL::JntArray q(8);
  q(0) = q(1) = q(2) = 0.2;
  q(5) = 0.5 * (1.2 + isur.geometry().pitch_difference);
  q(6) = 0.5 * (1.2 - isur.geometry().pitch_difference);
  KDL::Frame start;
  ASSERT_EQ(isur.forward(q, start), IkStatus::Ok);
  // Down along the needle 6 cm in 0.1 mm steps (the sliders' stroke ends at 0.25 m), and back:
  // no joint steps more than 20 mrad (or 20 mm) per 0.1 mm of the needle, steepest where the elbow
  // has nearly run out too (at an insertion speed of 5 mm/s: 1 rad/s, within the micro joints' 1.5).
  KDL::JntArray seed = q, out(8);
  double deepest_elbow = isur.geometry().pitch_difference;
  for (int k = -600; k <= 600; ++k) {
    const double depth = 1e-4 * (600 - std::abs(k));
    const KDL::Frame target(start.M, start.p + start.M * KDL::Vector(depth, 0.0, 0.0));
    ASSERT_EQ(isur.inverse(target, seed, out), IkStatus::Ok) << "depth " << depth;
    for (unsigned j = 0; j < 8; ++j) EXPECT_LE(std::abs(out(j) - seed(j)), 2e-2) << "depth " << depth << " joint " << j + 1;
    deepest_elbow = std::max(deepest_elbow, std::abs(out(5) - out(6) - isur.geometry().pitch_difference));
    seed = out;
  }
  EXPECT_GT(deepest_elbow, 0.05);  // the elbow did take over from the delta
  // Back at the start pose the elbow returns at 5e-4 rad per solve (kRedundancyReturnStep), then
  // it is the start configuration again.
  for (int hold = 0; hold < 2000; ++hold) {
    ASSERT_EQ(isur.inverse(start, seed, out), IkStatus::Ok);
    seed = out;
  }
  for (unsigned j = 0; j < 8; ++j) EXPECT_NEAR(out(j), q(j), 1e-9) << "joint " << j + 1;
}

// 1000 seeded random configurations of the 14-DOF suturing robot: IK of both tool poses, seeded
// with the configuration, gives it back; seeded nearby, both poses are reached.
TEST(IsurSuturing, RandomPosesRoundTrip) {
  IsurSuturingGeometry geometry;
  geometry.right = seedShareGeometry();
  IsurSuturingSolver isur(geometry);
  std::mt19937 rng(43);
  std::uniform_real_distribution<double> noise(-0.02, 0.02);
  KDL::JntArray out(14);
  int solved_near = 0;
  for (int i = 0; i < 1000; ++i) {
    const KDL::JntArray q = randomJoints(isur.limits(), rng);
    KDL::Frame stitch;
    KDL::Frame gripper;
    ASSERT_EQ(isur.forward(q, stitch, gripper), IkStatus::Ok);
    ASSERT_EQ(isur.inverse(stitch, gripper, q, out), IkStatus::Ok) << "pose " << i;
    for (unsigned j = 0; j < 14; ++j) EXPECT_NEAR(out(j), q(j), 1e-7) << "pose " << i << " joint " << j + 1;

    KDL::JntArray seed = q;
    for (unsigned j = 3; j < 14; ++j) seed(j) += noise(rng);
    if (isur.inverse(stitch, gripper, seed, out) != IkStatus::Ok) continue;
    ++solved_near;
    KDL::Frame stitch_reached;
    KDL::Frame gripper_reached;
    ASSERT_EQ(isur.forward(out, stitch_reached, gripper_reached), IkStatus::Ok);
    EXPECT_LT(norm(stitch_reached.p - stitch.p), 1e-9);
    EXPECT_LT(norm(gripper_reached.p - gripper.p), 1e-9);
    EXPECT_LT(orientationError(gripper_reached.M, gripper.M), 1e-9);
  }
  EXPECT_GE(solved_near, 900);
}

// The gripper arm hangs from the platform: moving the macro moves the gripper (thesis §5.4.1).
TEST(IsurSuturing, MacroMotionMovesBothTools) {
  IsurSuturingSolver isur;
  KDL::JntArray q(14);
  q(0) = q(1) = q(2) = 0.1;
  q(9) = 0.5;
  q(10) = -0.5;
  KDL::Frame stitch_a, gripper_a, stitch_b, gripper_b;
  ASSERT_EQ(isur.forward(q, stitch_a, gripper_a), IkStatus::Ok);
  q(0) = q(1) = q(2) = 0.15;  // all sliders down: the platform translates straight down
  ASSERT_EQ(isur.forward(q, stitch_b, gripper_b), IkStatus::Ok);
  const KDL::Vector stitch_shift = stitch_b.p - stitch_a.p;
  EXPECT_LT(norm(stitch_shift - (gripper_b.p - gripper_a.p)), 1e-12);
  EXPECT_LT(stitch_shift.z(), -0.01);
  EXPECT_LT(std::hypot(stitch_shift.x(), stitch_shift.y()), 1e-12);
}

TEST(IsurSuturing, ConstructionErrorsNameTheArm) {
  IsurSuturingGeometry g;
  g.left_limits.lower[1] = 1.0;
  g.left_limits.upper[1] = 0.5;
  EXPECT_EQ(messageOf([&] { IsurSuturingSolver{g}; }),
            "I-SUR left arm: joint 2 limits [1, 0.5] rad: min must be <= max");
  g = IsurSuturingGeometry{};
  g.left.a2 = 0.0;
  EXPECT_EQ(messageOf([&] { IsurSuturingSolver{g}; }),
            "I-SUR left arm: parameter a2 is 0 m: the closed-form solution needs it non-zero");
  g = IsurSuturingGeometry{};
  g.left_mount.p = KDL::Vector(std::nan(""), 0.0, 0.0);
  EXPECT_EQ(messageOf([&] { IsurSuturingSolver{g}; }),
            "I-SUR: left_mount is not a pose: its translation must be finite and its rotation orthonormal");
}

TEST(IsurSuturing, UnreachableGripperLeavesTheOutputUntouched) {
  IsurSuturingSolver isur;
  KDL::JntArray q(14);
  q(0) = q(1) = q(2) = 0.1;
  KDL::Frame stitch;
  KDL::Frame gripper;
  ASSERT_EQ(isur.forward(q, stitch, gripper), IkStatus::Ok);
  KDL::JntArray out = test::filled(14, 42.0);
  EXPECT_EQ(isur.inverse(stitch, KDL::Frame(gripper.p + KDL::Vector(1.0, 0.0, 0.0)), q, out), IkStatus::Unreachable);
  EXPECT_TRUE(test::isFilled(out, 42.0));
  EXPECT_EQ(allocationsDuring([&] { EXPECT_EQ(isur.inverse(stitch, gripper, q, out), IkStatus::Ok); }), 0);
}



// Every link frame against KDL's FK of the equivalent serial chain, segment by segment, on 500
// seeded random configurations; the last link is forward()'s needle pose.
TEST(IsurPuncturing, LinkFramesMatchKdlSegmentsAndTheToolForwardKinematics) {
  IsurPuncturingSolver isur;
  const IsurMicroArm& m = isur.geometry().micro;
  const KDL::Chain chain = cartesianMacroChain(m);
  KDL::ChainFkSolverPos_recursive kdl(chain);
  std::mt19937 rng(47);
  std::array<KDL::Frame, IsurPuncturingSolver::kLinks> links{};
  for (int i = 0; i < 500; ++i) {
    const KDL::JntArray q = randomJoints(isur.limits(), rng, 0.0);
    ASSERT_EQ(isur.linkFrames(q, links), IkStatus::Ok);
    KDL::Frame tool;
    ASSERT_EQ(isur.forward(q, tool), IkStatus::Ok);
    EXPECT_LT(norm(links[5].p - tool.p), 1e-12);
    EXPECT_LT(orientationError(links[5].M, tool.M), 1e-12);
    KDL::Vector p_delta;
    ASSERT_EQ(isur.macro().forwardPosition(std::span<const double, 3>(q.data.data(), 3), p_delta), IkStatus::Ok);
    KDL::JntArray chain_q(8);
    chain_q(0) = q(3);
    chain_q(1) = p_delta.x();
    chain_q(2) = p_delta.y();
    chain_q(3) = p_delta.z();
    for (unsigned j = 4; j < 8; ++j) chain_q(j) = q(j);
    // KDL segment k's frame = joint_k(q)·tip_k: the link frame times the segment's fixed offset.
    const std::array<std::pair<int, KDL::Frame>, 6> expected = {
        std::pair{1, links[0]},
        std::pair{4, links[1] * KDL::Frame(m.mount)},
        std::pair{5, links[2] * KDL::Frame(m.shoulder)},
        std::pair{6, links[3] * KDL::Frame(KDL::Vector(m.upper_arm, 0, 0))},
        std::pair{7, links[4] * KDL::Frame(KDL::Vector(m.forearm, 0, 0))},
        std::pair{8, links[5]}};
    for (const auto& [segment, frame] : expected) {
      KDL::Frame by_kdl;
      ASSERT_GE(kdl.JntToCart(chain_q, by_kdl, segment), 0);
      EXPECT_LT(norm(frame.p - by_kdl.p), 1e-12) << "segment " << segment;
      EXPECT_LT(orientationError(frame.M, by_kdl.M), 1e-12) << "segment " << segment;
    }
  }
}

TEST(IsurPuncturing, LinkFramesRejectWrongSizesAndAllocateNothing) {
  IsurPuncturingSolver isur;
  KDL::JntArray q(8);
  q(0) = q(1) = q(2) = 0.1;
  std::array<KDL::Frame, IsurPuncturingSolver::kLinks> links{};
  std::array<KDL::Frame, 3> too_few{};
  EXPECT_EQ(isur.linkFrames(q, too_few), IkStatus::BadInput);
  EXPECT_EQ(isur.linkFrames(KDL::JntArray(7), links), IkStatus::BadInput);
  EXPECT_EQ(allocationsDuring([&] { EXPECT_EQ(isur.linkFrames(q, links), IkStatus::Ok); }), 0);
}

// The suturing robot's link frames: the first six are the puncturing structure's, the left arm's
// frames are KDL's FK of its DH chain mounted on the platform, the last is the gripper.
TEST(IsurSuturing, LinkFramesMatchBothArmsAndTheToolForwardKinematics) {
  IsurSuturingSolver isur;
  IsurPuncturingSolver right;
  const IsurSuturingGeometry geometry;
  const Puma260Solver left(geometry.left, geometry.left_limits);
  KDL::ChainFkSolverPos_recursive kdl(left.model().chain());
  std::mt19937 rng(53);
  std::array<KDL::Frame, IsurSuturingSolver::kLinks> links{};
  std::array<KDL::Frame, IsurPuncturingSolver::kLinks> right_links{};
  for (int i = 0; i < 300; ++i) {
    const KDL::JntArray q = randomJoints(isur.limits(), rng, 0.0);
    ASSERT_EQ(isur.linkFrames(q, links), IkStatus::Ok);
    KDL::Frame stitch, gripper;
    ASSERT_EQ(isur.forward(q, stitch, gripper), IkStatus::Ok);
    EXPECT_LT(norm(links[5].p - stitch.p), 1e-12);
    EXPECT_LT(norm(links[11].p - gripper.p), 1e-12);
    EXPECT_LT(orientationError(links[11].M, gripper.M), 1e-12);
    KDL::JntArray q_right(8), q_left(6);
    for (unsigned j = 0; j < 8; ++j) q_right(j) = q(j);
    for (unsigned j = 0; j < 6; ++j) q_left(j) = q(8 + j);
    ASSERT_EQ(right.linkFrames(q_right, right_links), IkStatus::Ok);
    for (std::size_t k = 0; k < right_links.size(); ++k) EXPECT_LT(norm(links[k].p - right_links[k].p), 1e-12);
    // KDL chain segments: 0 base (fixed), 1..6 the DH links, 7 the tool.
    for (int joint = 1; joint <= 5; ++joint) {
      KDL::Frame by_kdl;
      ASSERT_GE(kdl.JntToCart(q_left, by_kdl, joint + 1), 0);
      const KDL::Frame expected = links[1] * geometry.left_mount * by_kdl;
      EXPECT_LT(norm(links[5 + static_cast<std::size_t>(joint)].p - expected.p), 1e-12) << "left joint " << joint;
      EXPECT_LT(orientationError(links[5 + static_cast<std::size_t>(joint)].M, expected.M), 1e-12);
    }
  }
  KDL::JntArray q(14);
  EXPECT_EQ(allocationsDuring([&] { EXPECT_EQ(isur.linkFrames(q, links), IkStatus::Ok); }), 0);
}

}  // namespace
}  // namespace cobra::kinematics
