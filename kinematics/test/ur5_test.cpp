// Unit tests of ur5.hpp: FK against KDL's recursive solver on the same DH chain, all 8 inverse
// solutions on seeded random poses (each reproduces the pose; one is the original joints),
// nearest-to-seed choice with the ±2π joint ranges, KDL's LMA landing on one of the analytic
// solutions, the wrist singularity, unreachable poses, joint limits, construction errors and
// the absence of allocation.

#include "cobra/kinematics/ur5.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <kdl/chainfksolverpos_recursive.hpp>
#include <numbers>
#include <random>

#include "cobra/kinematics/geometry.hpp"
#include "cobra/test_support/counting_new.hpp"
#include "cobra/test_support/test_support.hpp"
#include "kinematics_test_support.hpp"

namespace cobra::kinematics {
namespace {

using cobra::test_support::allocationsDuring;
using cobra::test_support::messageOf;
constexpr double kPi = std::numbers::pi;
constexpr double kPoseTolerance = 1e-9;  // m and rad

using test::jointDistanceModulo2Pi;
using test::toJnt;

KDL::JntArray randomJoints(std::mt19937& rng, double range = kPi) {
  return test::randomJoints(Ur5Solver::defaultLimits(), rng, range);
}

TEST(Ur5, DhTableIsUniversalRobotsPublishedOne) {
  const Ur5Solver ur5;
  const auto& rows = ur5.model().rows();
  ASSERT_EQ(rows.size(), 6u);
  EXPECT_DOUBLE_EQ(rows[0].d, 0.089159);
  EXPECT_DOUBLE_EQ(rows[1].a, -0.425);
  EXPECT_DOUBLE_EQ(rows[2].a, -0.39225);
  EXPECT_DOUBLE_EQ(rows[3].d, 0.10915);
  EXPECT_DOUBLE_EQ(rows[4].d, 0.09465);
  EXPECT_DOUBLE_EQ(rows[5].d, 0.0823);
  EXPECT_DOUBLE_EQ(rows[0].alpha, kPi / 2);
  EXPECT_DOUBLE_EQ(rows[3].alpha, kPi / 2);
  EXPECT_DOUBLE_EQ(rows[4].alpha, -kPi / 2);
  EXPECT_DOUBLE_EQ(ur5.limits().lower[2], -2 * kPi);
  EXPECT_DOUBLE_EQ(ur5.limits().upper[5], 2 * kPi);
}

TEST(Ur5, ZeroConfigurationIsTheKnownStretchedPose) {
  // At q = 0 the UR5 lies stretched along -x: flange at (a2 + a3, -(d4 + d6), d1 - d5).
  Ur5Solver ur5;
  KDL::Frame pose;
  ASSERT_EQ(ur5.forward(KDL::JntArray(6), pose), IkStatus::Ok);
  EXPECT_NEAR(pose.p.x(), -0.425 - 0.39225, 1e-15);
  EXPECT_NEAR(pose.p.y(), -(0.10915 + 0.0823), 1e-15);
  EXPECT_NEAR(pose.p.z(), 0.089159 - 0.09465, 1e-15);
}

// 1000 seeded random configurations each with and without base and tool frames: the closed-form
// FK equals KDL's ChainFkSolverPos_recursive on the DH chain, and cobra's own chain product.
TEST(Ur5, ForwardMatchesKdl) {
  std::mt19937 rng(11);
  const KDL::Frame base(KDL::Rotation::RPY(0.1, 0.2, 0.3), KDL::Vector(0.4, -0.1, 0.8));
  const KDL::Frame tool(KDL::Rotation::RotY(0.3), KDL::Vector(0.0, 0.02, 0.15));
  Ur5Solver placed(Ur5Parameters{}, Ur5Solver::defaultLimits(), base, tool);
  Ur5Solver bare;
  for (Ur5Solver* ur5 : {&placed, &bare}) {
    KDL::ChainFkSolverPos_recursive kdl(ur5->model().chain());
    for (int i = 0; i < 1000; ++i) {
      const KDL::JntArray q = randomJoints(rng, 2 * kPi);
      KDL::Frame ours;
      KDL::Frame theirs;
      ASSERT_EQ(ur5->forward(q, ours), IkStatus::Ok);
      ASSERT_GE(kdl.JntToCart(q, theirs), 0);
      EXPECT_LT(norm(ours.p - theirs.p), 1e-12);
      EXPECT_LT(orientationError(ours.M, theirs.M), 1e-12);
      const KDL::Frame chain = ur5->model().forward(std::span<const double>(q.data.data(), 6));
      EXPECT_LT(norm(ours.p - chain.p), 1e-12);
      EXPECT_LT(orientationError(ours.M, chain.M), 1e-12);
    }
  }
}

// 10,000 seeded random configurations (with base and tool frames): every solution reproduces the
// pose within 1e-9 m / 1e-9 rad through KDL's FK, one of them is the original configuration, the
// nearest-to-seed choice works (see checkAnalyticRoundTrips); most poses have all 8 solutions
// (others lose a shoulder/wrist branch whose planar elbow problem has no real solution).
TEST(Ur5, AllEightSolutionsReproduceRandomPoses) {
  const KDL::Frame base(KDL::Rotation::RotZ(0.7), KDL::Vector(0.1, 0.2, 0.3));
  const KDL::Frame tool(KDL::Rotation::RotX(-0.4), KDL::Vector(0.01, 0.0, 0.12));
  Ur5Solver ur5(Ur5Parameters{}, Ur5Solver::defaultLimits(), base, tool);
  constexpr int kCount = 10000;
  const test::RoundTripCounts counts = test::checkAnalyticRoundTrips(ur5, ur5.model().chain(), kCount, 12, kPi);
  EXPECT_EQ(counts.poses, kCount);
  EXPECT_GE(counts.with_eight, kCount / 2);
}

// The ±2π ranges: a seed near q + 2π on joint 1 gets q + 2π, not q.
TEST(Ur5, InverseUsesThe2PiRepresentativeNearestTheSeed) {
  Ur5Solver ur5;
  const KDL::JntArray q = test::joints({-0.5, -1.2, 1.4, -0.7, 1.1, 2.0});
  KDL::Frame target;
  ur5.forward(q, target);
  KDL::JntArray seed = q;
  seed(0) = 5.7;   // nearer to -0.5 + 2π = 5.78 than to -0.5
  seed(5) = -4.2;  // nearer to 2 - 2π = -4.28 than to 2
  KDL::JntArray out(6);
  ASSERT_EQ(ur5.inverse(target, seed, out), IkStatus::Ok);
  EXPECT_NEAR(out(0), -0.5 + 2 * kPi, 1e-9);
  EXPECT_NEAR(out(5), 2.0 - 2 * kPi, 1e-9);
  EXPECT_NEAR(out(1), -1.2, 1e-9);
}

// 200 seeded random poses: KDL's LMA on the same DH chain, started near one configuration,
// converges to one of the analytic solutions (an independent check of the closed form).
TEST(Ur5, KdlLmaLandsOnAnAnalyticSolution) {
  Ur5Solver ur5;
  EXPECT_GE(test::checkLmaLandsOnAnalyticSolution(ur5, 200, 13, 0.0), 150);
}

// The three solver kinds behind KinematicsSolver (thesis §6.2.4) agree on FK and reach the pose.
TEST(Ur5, SolverKindsAreInterchangeable) {
  const KDL::JntArray q = test::joints({0.4, -1.1, 1.3, -0.6, 1.0, 0.3});
  KDL::JntArray seed = q;
  for (unsigned j = 0; j < 6; ++j) seed(j) += 0.05;
  const KDL::Frame base(KDL::Vector(0.1, 0.0, 0.5));
  KDL::Frame target;
  Ur5Solver(Ur5Parameters{}, Ur5Solver::defaultLimits(), base).forward(q, target);
  for (const SolverKind kind :
       {SolverKind::ClosedForm, SolverKind::KdlNewtonRaphson, SolverKind::KdlLevenbergMarquardt}) {
    const std::unique_ptr<KinematicsSolver> solver =
        makeUr5Solver(kind, Ur5Parameters{}, Ur5Solver::defaultLimits(), base);
    EXPECT_EQ(solver->name(), "UR5");
    KDL::JntArray out(6);
    ASSERT_EQ(solver->inverse(target, seed, out), IkStatus::Ok);
    for (unsigned j = 0; j < 6; ++j) EXPECT_NEAR(out(j), q(j), 1e-8) << "joint " << j + 1;
  }
}

// Wrist singularity (θ5 = 0: axes 4 and 6 aligned): θ6 is the seed's, the pose is still reached.
TEST(Ur5, WristSingularityTakesTheFreeJointFromTheSeed) {
  Ur5Solver ur5;
  const KDL::JntArray q = test::joints({0.3, -1.0, 1.2, 0.2, 0.0, 0.8});
  KDL::Frame target;
  ur5.forward(q, target);
  KDL::JntArray seed = q;
  seed(5) = 0.5;
  IkSolutionSet solutions;
  ASSERT_EQ(ur5.allInverse(target, seed, solutions), IkStatus::Ok);
  // On the original shoulder branch the two wrist branches coincide (θ5 = 0): 2 solutions with
  // θ6 = seed; the other shoulder branch is not singular there: 4 regular solutions.
  int singular = 0;
  for (std::size_t s = 0; s < solutions.size(); ++s) {
    if (std::abs(solutions[s][4]) < 1e-9) {
      ++singular;
      EXPECT_DOUBLE_EQ(solutions[s][5], 0.5);
    }
    KDL::Frame reached;
    ur5.forward(toJnt(solutions[s]), reached);
    EXPECT_LT(norm(reached.p - target.p), kPoseTolerance);
    EXPECT_LT(orientationError(reached.M, target.M), kPoseTolerance);
  }
  EXPECT_EQ(singular, 2);
  EXPECT_EQ(solutions.size(), 6u);
}

TEST(Ur5, UnreachablePosesLeaveTheOutputUntouched) {
  Ur5Solver ur5;
  KDL::JntArray seed(6);
  KDL::JntArray out = test::filled(6, 42.0);
  IkSolutionSet solutions;
  // Beyond the 0.85 m reach.
  EXPECT_EQ(ur5.inverse(KDL::Frame(KDL::Vector(1.2, 0.0, 0.3)), seed, out), IkStatus::Unreachable);
  EXPECT_EQ(ur5.allInverse(KDL::Frame(KDL::Vector(1.2, 0.0, 0.3)), seed, solutions), IkStatus::Unreachable);
  EXPECT_TRUE(solutions.empty());
  // Wrist point on the base axis, closer to it than the shoulder offset d4.
  const KDL::Frame on_axis(KDL::Rotation::Identity(), KDL::Vector(0.0, 0.0, 0.5 + 0.0823));
  EXPECT_EQ(ur5.inverse(on_axis, seed, out), IkStatus::Unreachable);
  EXPECT_TRUE(test::isFilled(out, 42.0));
}

TEST(Ur5, JointLimitsExcludeSolutions) {
  const KDL::JntArray q = test::joints({0.5, -1.2, 1.4, -0.7, 1.1, -2.0});
  // Elbow limited to [0.1, 2] rad: only the elbow-up solutions remain, the nearest is q.
  JointLimits limits = Ur5Solver::defaultLimits();
  limits.lower[2] = 0.1;
  limits.upper[2] = 2.0;
  Ur5Solver ur5(Ur5Parameters{}, limits);
  KDL::Frame target;
  ur5.forward(q, target);
  KDL::JntArray seed = q;
  seed(2) = -1.4;  // nearer to the elbow-down branch, which the limits exclude
  KDL::JntArray out(6);
  ASSERT_EQ(ur5.inverse(target, seed, out), IkStatus::Ok);
  EXPECT_GE(out(2), 0.1);

  // Elbow limited to [2.5, 3] rad: no solution of this pose fits.
  limits.lower[2] = 2.5;
  limits.upper[2] = 3.0;
  Ur5Solver narrow(Ur5Parameters{}, limits);
  for (unsigned j = 0; j < 6; ++j) out(j) = 42.0;
  EXPECT_EQ(narrow.inverse(target, seed, out), IkStatus::JointLimits);
  EXPECT_TRUE(test::isFilled(out, 42.0));
}

// inverseOnBranch solves the branch's own solutions first: 5,000 seeded random poses, seeds near
// them and branches (every one of the eight, and IkBranch::any()), some with the elbow limited so
// that only another branch fits: the answer and the status are exactly those of the generic
// selection among all eight solutions (AnalyticSolver::inverseOnBranch).
TEST(Ur5, InverseOnBranchIsTheSelectionAmongAllEight) {
  std::mt19937 rng(11);
  JointLimits narrow = Ur5Solver::defaultLimits();
  narrow.lower[2] = 0.1;
  narrow.upper[2] = 2.5;
  Ur5Solver full;
  Ur5Solver limited(Ur5Parameters{}, narrow);
  std::uniform_real_distribution<double> nudge(-0.05, 0.05);
  std::uniform_int_distribution<int> bits(0, 8);
  int refused = 0;
  for (int i = 0; i < 5000; ++i) {
    Ur5Solver& ur5 = i % 2 == 0 ? full : limited;
    const KDL::JntArray q = randomJoints(rng);
    KDL::Frame target;
    ASSERT_EQ(ur5.forward(q, target), IkStatus::Ok);
    KDL::JntArray seed = q;
    for (unsigned j = 0; j < 6; ++j) seed(j) += nudge(rng);
    const int b = bits(rng);
    const IkBranch branch = b == 8 ? IkBranch::any() : IkBranch{static_cast<std::uint8_t>(b), 0};
    KDL::JntArray fast(6), generic(6);
    for (unsigned j = 0; j < 6; ++j) fast(j) = generic(j) = 42.0;
    const IkStatus by_branch = ur5.inverseOnBranch(target, seed, branch, fast);
    const IkStatus by_all = ur5.AnalyticSolver::inverseOnBranch(target, seed, branch, generic);
    ASSERT_EQ(by_branch, by_all) << "pose " << i;
    for (unsigned j = 0; j < 6; ++j) EXPECT_EQ(fast(j), generic(j)) << "pose " << i << " joint " << j;
    refused += by_branch != IkStatus::Ok ? 1 : 0;
  }
  EXPECT_GT(refused, 100) << "some branches must have no solution in the limits";
}

TEST(Ur5, BadInputIsRefused) {
  Ur5Solver ur5;
  KDL::JntArray seed(6);
  KDL::JntArray out(5);
  IkSolutionSet solutions;
  EXPECT_EQ(ur5.inverse(KDL::Frame(KDL::Vector(0.4, 0.1, 0.3)), seed, out), IkStatus::BadInput);
  KDL::Frame nan_target(KDL::Vector(std::nan(""), 0, 0));
  EXPECT_EQ(ur5.allInverse(nan_target, seed, solutions), IkStatus::BadInput);
  KDL::Frame pose;
  EXPECT_EQ(ur5.forward(out, pose), IkStatus::BadInput);
}

TEST(Ur5, ConstructionErrorsNameTheParameterOrJoint) {
  JointLimits limits = Ur5Solver::defaultLimits();
  limits.lower[2] = 2.0;
  limits.upper[2] = 1.0;
  EXPECT_EQ(messageOf([&] { Ur5Solver(Ur5Parameters{}, limits); }),
            "UR5: joint 3 limits [2, 1] rad: min must be <= max");
  EXPECT_EQ(messageOf([] { Ur5Solver(Ur5Parameters{.a2 = std::nan("")}); }),
            "UR5: parameter a2 is nan: give a finite value in m");
  EXPECT_EQ(messageOf([] { Ur5Solver(Ur5Parameters{.d6 = 0.0}); }),
            "UR5: parameter d6 is 0 m: the closed-form solution needs it non-zero");
  EXPECT_CONTAINS(messageOf([] { Ur5Solver(Ur5Parameters{}, revoluteLimits(5, -1, 1)); }), "the robot has 6 joints");
  JointLimits prismatic = Ur5Solver::defaultLimits();
  prismatic.types[1] = JointType::Prismatic;
  EXPECT_EQ(messageOf([&] { Ur5Solver(Ur5Parameters{}, prismatic); }),
            "UR5: every joint is revolute: give JointType::Revolute limits");
}

TEST(Ur5, RealTimeCallsAllocateNothing) {
  Ur5Solver ur5;
  KDL::JntArray q(6);
  for (unsigned j = 0; j < 6; ++j) q(j) = 0.2 * (j + 1);
  KDL::JntArray out(6);
  KDL::Frame pose;
  IkSolutionSet solutions;
  EXPECT_EQ(allocationsDuring([&] { ur5.forward(q, pose); }), 0);
  EXPECT_EQ(allocationsDuring([&] { ur5.allInverse(pose, q, solutions); }), 0);
  EXPECT_EQ(allocationsDuring([&] { EXPECT_EQ(ur5.inverse(pose, q, out), IkStatus::Ok); }), 0);
  const KDL::Frame far(KDL::Vector(3.0, 0.0, 0.0));
  EXPECT_EQ(allocationsDuring([&] { EXPECT_EQ(ur5.inverse(far, q, out), IkStatus::Unreachable); }), 0);
}


// Link frames against KDL's FK of the same DH chain, segment by segment (segment 0 = base, i = DH
// frame i, 7 = tool), on 500 seeded random configurations; the last link is the tool pose.
TEST(Ur5, LinkFramesMatchKdlSegmentsAndTheToolForwardKinematics) {
  const KDL::Frame base(KDL::Rotation::RotZ(0.3), KDL::Vector(0.55, 0.0, 0.0));
  const KDL::Frame tool(KDL::Vector(0.0, 0.0, 0.12));
  Ur5Solver ur5(Ur5Parameters{}, Ur5Solver::defaultLimits(), base, tool);
  const SerialChainModel& model = ur5.model();
  ASSERT_EQ(model.linkCount(), 8u);
  KDL::ChainFkSolverPos_recursive kdl(model.chain());
  std::mt19937 rng(59);
  std::array<KDL::Frame, 8> links{};
  for (int i = 0; i < 500; ++i) {
    const KDL::JntArray q = randomJoints(rng);
    ASSERT_TRUE(model.linkFrames(std::span<const double>(q.data.data(), 6), links));
    KDL::Frame pose;
    ASSERT_EQ(ur5.forward(q, pose), IkStatus::Ok);
    EXPECT_LT(norm(links[7].p - pose.p), 1e-12);
    EXPECT_LT(orientationError(links[7].M, pose.M), 1e-12);
    for (int segment = 0; segment < 8; ++segment) {
      KDL::Frame by_kdl;
      ASSERT_GE(kdl.JntToCart(q, by_kdl, segment + 1), 0);
      EXPECT_LT(norm(links[static_cast<std::size_t>(segment)].p - by_kdl.p), 1e-12) << "link " << segment;
      EXPECT_LT(orientationError(links[static_cast<std::size_t>(segment)].M, by_kdl.M), 1e-12) << "link " << segment;
    }
  }
  std::array<KDL::Frame, 7> too_few{};
  const std::array<double, 6> q{};
  EXPECT_FALSE(model.linkFrames(q, too_few));
  EXPECT_EQ(allocationsDuring([&] { EXPECT_TRUE(model.linkFrames(q, links)); }), 0);
}

}  // namespace
}  // namespace cobra::kinematics
