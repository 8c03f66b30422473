// Unit tests of puma260.hpp: the DH table, FK against KDL's recursive solver, all inverse
// solutions on seeded random poses (Puma 260 and, for the elbow offset a3, Puma 560), KDL's LMA
// landing on an analytic solution, the interchangeable solver kinds (§6.2.4), the wrist
// singularity, unreachable poses, joint limits, construction errors and no allocation.

#include <gtest/gtest.h>

#include "cobra/test_support/counting_new.hpp"
#include "cobra/test_support/test_support.hpp"

#include <cmath>
#include <numbers>
#include <random>

#include "cobra/kinematics/geometry.hpp"
#include "cobra/kinematics/puma260.hpp"

#include "kinematics_test_support.hpp"

namespace cobra::kinematics {
namespace {

using cobra::test_support::allocationsDuring;
using cobra::test_support::messageOf;
using test::joints;
using test::toJnt;
constexpr double kPi = std::numbers::pi;

TEST(Puma260, DhTableIsTheDocumentedOne) {
  const Puma260Solver puma;
  const auto& rows = puma.model().rows();
  EXPECT_DOUBLE_EQ(rows[0].d, 0.3302);
  EXPECT_DOUBLE_EQ(rows[1].a, 0.2032);
  EXPECT_DOUBLE_EQ(rows[2].a, 0.0);
  EXPECT_DOUBLE_EQ(rows[2].d, 0.12623);
  EXPECT_DOUBLE_EQ(rows[2].alpha, -kPi / 2);
  EXPECT_DOUBLE_EQ(rows[3].d, 0.2032);
  EXPECT_DOUBLE_EQ(rows[5].d, 0.05537);
  EXPECT_NEAR(puma.limits().upper[1], 225 * kPi / 180, 1e-15);
}

// At q = 0 the upper arm lies along x (a2), the shoulder offset d3 along z1 = (0, -1, 0) and the
// forearm and flange point up: flange at (a2, -d3, d1 + d4 + d6).
TEST(Puma260, ZeroConfigurationMatchesTheTableByHand) {
  Puma260Solver puma;
  KDL::Frame pose;
  ASSERT_EQ(puma.forward(KDL::JntArray(6), pose), IkStatus::Ok);
  EXPECT_NEAR(pose.p.x(), 0.2032, 1e-15);
  EXPECT_NEAR(pose.p.y(), -0.12623, 1e-15);
  EXPECT_NEAR(pose.p.z(), 0.3302 + 0.2032 + 0.05537, 1e-15);
}

// 10,000 seeded random configurations each for the Puma 260 and the Puma 560 (a3 != 0): every
// solution reproduces the pose within 1e-9 m / 1e-9 rad through KDL's FK of the same DH chain,
// the original is among them, nearest-to-seed works; most poses have 8 solutions.
TEST(Puma260, AllSolutionsReproduceRandomPoses) {
  const JointLimits wide = revoluteLimits(6, -kPi, kPi);
  for (const Puma260Parameters& parameters : {Puma260Parameters{}, Puma260Parameters::puma560()}) {
    Puma260Solver puma(parameters, wide, KDL::Frame(KDL::Rotation::RotZ(0.4), KDL::Vector(0.1, 0.0, 0.2)),
                       KDL::Frame(KDL::Vector(0.0, 0.0, 0.1)));
    constexpr int kCount = 10000;
    const test::RoundTripCounts counts = test::checkAnalyticRoundTrips(puma, puma.model().chain(), kCount, 21, kPi);
    EXPECT_EQ(counts.poses, kCount);
    EXPECT_GE(counts.with_eight, kCount / 2);
  }
}

// 200 seeded random poses: KDL's LMA from a nearby seed converges to one of the analytic solutions.
TEST(Puma260, KdlLmaLandsOnAnAnalyticSolution) {
  Puma260Solver puma;
  EXPECT_GE(test::checkLmaLandsOnAnalyticSolution(puma, 200, 22, 0.2), 150);
}

// The three solver kinds behind KinematicsSolver give the same FK and reach the same pose.
TEST(Puma260, SolverKindsAreInterchangeable) {
  const KDL::JntArray q = joints({0.3, 0.8, -1.2, 0.4, 0.9, -0.5});
  KDL::JntArray seed = q;
  for (unsigned j = 0; j < 6; ++j) seed(j) += 0.05;
  KDL::Frame target;
  Puma260Solver().forward(q, target);
  for (const char* name : {"closed_form", "kdl_nr", "kdl_lma"}) {
    const std::unique_ptr<KinematicsSolver> solver = makePuma260Solver(parseSolverKind(name));
    EXPECT_EQ(solver->name(), "Puma 260");
    KDL::Frame pose;
    ASSERT_EQ(solver->forward(q, pose), IkStatus::Ok);
    EXPECT_LT(norm(pose.p - target.p), 1e-12) << name;
    KDL::JntArray out(6);
    ASSERT_EQ(solver->inverse(target, seed, out), IkStatus::Ok) << name;
    for (unsigned j = 0; j < 6; ++j) EXPECT_NEAR(out(j), q(j), 1e-8) << name << " joint " << j + 1;
  }
  EXPECT_EQ(messageOf([] { parseSolverKind("kdl"); }),
            "unknown kinematics solver \"kdl\": expected closed_form, kdl_nr or kdl_lma");
}

TEST(Puma260, WristSingularityTakesJoint4FromTheSeed) {
  Puma260Solver puma;
  const KDL::JntArray q = joints({0.3, 0.8, -1.2, 0.4, 0.0, -0.5});
  KDL::Frame target;
  puma.forward(q, target);
  KDL::JntArray seed = q;
  seed(3) = 1.0;
  KDL::JntArray out(6);
  ASSERT_EQ(puma.inverse(target, seed, out), IkStatus::Ok);
  EXPECT_DOUBLE_EQ(out(3), 1.0);
  EXPECT_NEAR(out(4), 0.0, 1e-9);
  EXPECT_NEAR(out(3) + out(5), 0.4 - 0.5, 1e-9);  // only θ4 + θ6 is defined there
  KDL::Frame reached;
  puma.forward(out, reached);
  EXPECT_LT(norm(reached.p - target.p), 1e-9);
  EXPECT_LT(orientationError(reached.M, target.M), 1e-9);
}

TEST(Puma260, UnreachablePosesLeaveTheOutputUntouched) {
  Puma260Solver puma;
  KDL::JntArray seed(6);
  KDL::JntArray out = test::filled(6, 42.0);
  EXPECT_EQ(puma.inverse(KDL::Frame(KDL::Vector(0.6, 0.0, 0.3)), seed, out), IkStatus::Unreachable);
  // Wrist centre on the base axis: closer to it than the shoulder offset d3.
  EXPECT_EQ(puma.inverse(KDL::Frame(KDL::Vector(0.0, 0.0, 0.5)), seed, out), IkStatus::Unreachable);
  EXPECT_TRUE(test::isFilled(out, 42.0));
}

TEST(Puma260, JointLimitsExcludeSolutions) {
  Puma260Solver puma;
  // Joint 5 at 120° is outside the ±100° range; the flipped wrist (θ4 + π, -θ5, θ6 + π) has
  // θ4 + π = 200°, outside [-110°, 170°]: no solution of this pose fits.
  const KDL::JntArray q = joints({0.3, 0.8, -1.2, 0.0, 120 * kPi / 180, 0.2});
  const KDL::Frame target = puma.model().forward(std::span<const double>(q.data.data(), 6));
  KDL::JntArray out = test::filled(6, 42.0);
  const IkStatus status = puma.inverse(target, q, out);
  if (status == IkStatus::Ok) {
    EXPECT_TRUE(puma.limits().contains(out));  // another shoulder/elbow branch may reach it in limits
  } else {
    EXPECT_EQ(status, IkStatus::JointLimits);
    EXPECT_TRUE(test::isFilled(out, 42.0));
  }
  JointLimits narrow = Puma260Solver::defaultLimits();
  narrow.lower[1] = 2.9;
  narrow.upper[1] = 3.0;
  Puma260Solver pinned(Puma260Parameters{}, narrow);
  EXPECT_EQ(pinned.inverse(target, q, out), IkStatus::JointLimits);
  EXPECT_TRUE(test::isFilled(out, 42.0));
}

TEST(Puma260, ConstructionErrorsNameTheParameterOrJoint) {
  JointLimits limits = Puma260Solver::defaultLimits();
  limits.lower[1] = 1.0;
  limits.upper[1] = 0.5;
  EXPECT_EQ(messageOf([&] { Puma260Solver(Puma260Parameters{}, limits); }),
            "Puma 260: joint 2 limits [1, 0.5] rad: min must be <= max");
  EXPECT_EQ(messageOf([] { Puma260Solver(Puma260Parameters{.a2 = 0.0}); }),
            "Puma 260: parameter a2 is 0 m: the closed-form solution needs it non-zero");
  EXPECT_EQ(messageOf([] { Puma260Solver(Puma260Parameters{.d3 = INFINITY}); }),
            "Puma 260: parameter d3 is inf: give a finite value in m");
  EXPECT_EQ(messageOf([] { Puma260Solver(Puma260Parameters{.a3 = 0.0, .d4 = 0.0}); }),
            "Puma 260: parameters a3 and d4 are both 0 m: the forearm has no length");
}

TEST(Puma260, RealTimeCallsAllocateNothing) {
  Puma260Solver puma;
  const KDL::JntArray q = joints({0.3, 0.8, -1.2, 0.4, 0.9, -0.5});
  KDL::JntArray out(6);
  KDL::Frame pose;
  IkSolutionSet solutions;
  EXPECT_EQ(allocationsDuring([&] { puma.forward(q, pose); }), 0);
  EXPECT_EQ(allocationsDuring([&] { puma.allInverse(pose, q, solutions); }), 0);
  EXPECT_EQ(allocationsDuring([&] { EXPECT_EQ(puma.inverse(pose, q, out), IkStatus::Ok); }), 0);
}

}  // namespace
}  // namespace cobra::kinematics
