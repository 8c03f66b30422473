// Unit tests of serial_chain.hpp: the DH transform against an explicit product of elementary
// transforms, FK of the model against KDL's recursive solver, the Jacobian against finite
// differences, NR_JL and LMA inverse kinematics on seeded random poses, unreachable targets,
// joint limits, construction errors, and what allocates on the real-time path.

#include <gtest/gtest.h>

#include "cobra/test_support/counting_new.hpp"
#include "cobra/test_support/test_support.hpp"

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include <kdl/chainfksolverpos_recursive.hpp>

#include "cobra/kinematics/geometry.hpp"
#include "cobra/kinematics/serial_chain.hpp"

#include "kinematics_test_support.hpp"

namespace cobra::kinematics {
namespace {

using cobra::test_support::allocationsDuring;
using cobra::test_support::messageOf;
constexpr double kPi = std::numbers::pi;

/// A 6R arm with UR5-like proportions but every DH parameter non-zero somewhere, so that a
/// transposed or mis-signed parameter shows; plus base and tool frames.
SerialChainModel sixAxisModel() {
  return SerialChainModel("test arm",
                          {{.a = 0.0, .alpha = kPi / 2, .d = 0.09, .theta = 0.1},
                           {.a = -0.42, .alpha = 0.0, .d = 0.0, .theta = -0.2},
                           {.a = -0.39, .alpha = 0.0, .d = 0.0},
                           {.a = 0.0, .alpha = kPi / 2, .d = 0.11},
                           {.a = 0.0, .alpha = -kPi / 2, .d = 0.095},
                           {.a = 0.0, .alpha = 0.0, .d = 0.082}},
                          KDL::Frame(KDL::Rotation::RotZ(0.3), KDL::Vector(0.1, -0.2, 0.5)),
                          KDL::Frame(KDL::Rotation::RotX(0.2), KDL::Vector(0.0, 0.0, 0.05)));
}

/// RRPR (SCARA-like) chain: exercises a prismatic joint and its limits (m).
SerialChainModel scaraModel() {
  return SerialChainModel("scara", {{.a = 0.3, .alpha = 0.0, .d = 0.4},
                                    {.a = 0.25, .alpha = kPi, .d = 0.0},
                                    {.type = JointType::Prismatic, .lower = 0.0, .upper = 0.2},
                                    {.a = 0.0, .alpha = 0.0, .d = 0.05}});
}

KDL::JntArray randomJoints(const JointLimits& limits, std::mt19937& rng, double margin = 0.0) {
  KDL::JntArray q(static_cast<unsigned>(limits.size()));
  for (unsigned i = 0; i < q.rows(); ++i) {
    std::uniform_real_distribution<double> value(limits.lower[i] + margin, limits.upper[i] - margin);
    q(i) = value(rng);
  }
  return q;
}

TEST(DhTransform, IsRzTzTxRxForRevoluteAndPrismaticJoints) {
  const DhRow revolute{.a = 0.3, .alpha = 0.7, .d = -0.2, .theta = 0.4};
  const double q = 1.1;
  const KDL::Frame expected = KDL::Frame(KDL::Rotation::RotZ(0.4 + q)) * KDL::Frame(KDL::Vector(0, 0, -0.2)) *
                              KDL::Frame(KDL::Vector(0.3, 0, 0)) * KDL::Frame(KDL::Rotation::RotX(0.7));
  EXPECT_TRUE(KDL::Equal(dhTransform(revolute, q), expected, 1e-14));

  const DhRow prismatic{.a = 0.1, .alpha = -0.5, .d = 0.2, .theta = 0.3, .type = JointType::Prismatic};
  const KDL::Frame expected_prismatic = KDL::Frame(KDL::Rotation::RotZ(0.3)) * KDL::Frame(KDL::Vector(0, 0, 0.2 + q)) *
                                        KDL::Frame(KDL::Vector(0.1, 0, 0)) * KDL::Frame(KDL::Rotation::RotX(-0.5));
  EXPECT_TRUE(KDL::Equal(dhTransform(prismatic, q), expected_prismatic, 1e-14));
}

// 500 seeded random configurations per model: the DH product equals KDL's recursive FK on the
// chain built from the same table, and the solver's forward.
TEST(SerialChain, ForwardMatchesKdlRecursiveSolver) {
  std::mt19937 rng(1);
  for (const SerialChainModel& model : {sixAxisModel(), scaraModel()}) {
    SerialChainSolver solver(model);
    KDL::ChainFkSolverPos_recursive kdl_fk(model.chain());
    for (int i = 0; i < 500; ++i) {
      const KDL::JntArray q = randomJoints(model.limits(), rng);
      KDL::Frame by_kdl;
      KDL::Frame by_solver;
      ASSERT_GE(kdl_fk.JntToCart(q, by_kdl), 0);
      ASSERT_EQ(solver.forward(q, by_solver), IkStatus::Ok);
      const KDL::Frame by_dh = model.forward(std::span<const double>(q.data.data(), q.rows()));
      EXPECT_TRUE(KDL::Equal(by_dh, by_kdl, 1e-12)) << model.name();
      EXPECT_TRUE(KDL::Equal(by_solver, by_kdl, 1e-12)) << model.name();
    }
  }
}

// 500 seeded random configurations per model: forward and linkFrames (written-out products with
// each row's cos α, sin α computed once) give exactly KDL's own base · Π Frame::DH · tool, bit
// for bit, so the control path's poses did not change by a rounding when they were sped up.
TEST(SerialChain, ForwardIsKdlsFrameProductBitForBit) {
  std::mt19937 rng(2);
  for (const SerialChainModel& model : {sixAxisModel(), scaraModel()}) {
    std::vector<KDL::Frame> links(model.linkCount());
    for (int i = 0; i < 500; ++i) {
      const KDL::JntArray q = randomJoints(model.limits(), rng);
      const std::span<const double> values(q.data.data(), q.rows());
      KDL::Frame expected = model.base();
      for (unsigned j = 0; j < q.rows(); ++j) expected = expected * dhTransform(model.rows()[j], q(j));
      const KDL::Frame last = expected;
      expected = expected * model.tool();
      const KDL::Frame by_model = model.forward(values);
      ASSERT_TRUE(model.linkFrames(values, links));
      for (int k = 0; k < 9; ++k) {
        EXPECT_EQ(by_model.M.data[k], expected.M.data[k]) << model.name();
        EXPECT_EQ(links.back().M.data[k], expected.M.data[k]) << model.name();
        EXPECT_EQ(links[links.size() - 2].M.data[k], last.M.data[k]) << model.name();
      }
      for (int k = 0; k < 3; ++k) {
        EXPECT_EQ(by_model.p(k), expected.p(k)) << model.name();
        EXPECT_EQ(links.back().p(k), expected.p(k)) << model.name();
      }
    }
  }
}

// 100 seeded random configurations: each Jacobian column equals the central difference of the
// tool pose (linear part: d p / d q_j; angular part: the rotation vector of R(q+h) R(q-h)ᵀ / 2h).
TEST(SerialChain, JacobianMatchesFiniteDifferences) {
  std::mt19937 rng(2);
  for (const SerialChainModel& model : {sixAxisModel(), scaraModel()}) {
    SerialChainSolver solver(model);
    KDL::Jacobian jacobian(model.jointCount());
    for (int i = 0; i < 100; ++i) {
      const KDL::JntArray q = randomJoints(model.limits(), rng, 1e-3);
      ASSERT_EQ(solver.jacobian(q, jacobian), IkStatus::Ok);
      constexpr double h = 1e-6;
      for (unsigned j = 0; j < model.jointCount(); ++j) {
        KDL::JntArray plus = q;
        KDL::JntArray minus = q;
        plus(j) += h;
        minus(j) -= h;
        KDL::Frame f_plus;
        KDL::Frame f_minus;
        solver.forward(plus, f_plus);
        solver.forward(minus, f_minus);
        const KDL::Vector linear = (f_plus.p - f_minus.p) / (2 * h);
        const KDL::Vector angular = (f_plus.M * f_minus.M.Inverse()).GetRot() / (2 * h);
        for (int r = 0; r < 3; ++r) {
          EXPECT_NEAR(jacobian(static_cast<unsigned>(r), j), linear(r), 1e-7) << model.name() << " column " << j;
          EXPECT_NEAR(jacobian(static_cast<unsigned>(r + 3), j), angular(r), 1e-7) << model.name() << " column " << j;
        }
      }
    }
  }
}

// 200 seeded random configurations in limits per method: FK, then IK from a seed 0.2 rad away,
// then FK again reaches the pose within 1e-9 m / 1e-9 rad.
class SerialChainIk : public ::testing::TestWithParam<IterativeIk> {};

TEST_P(SerialChainIk, RandomPosesRoundTrip) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> noise(-0.2, 0.2);
  SerialChainSolver solver(sixAxisModel(), {.method = GetParam()});
  int solved = 0;
  constexpr int kCount = 200;
  for (int i = 0; i < kCount; ++i) {
    const KDL::JntArray q = randomJoints(solver.limits(), rng, 0.3);
    KDL::Frame target;
    ASSERT_EQ(solver.forward(q, target), IkStatus::Ok);
    KDL::JntArray seed = q;
    for (unsigned j = 0; j < seed.rows(); ++j) seed(j) += noise(rng);
    KDL::JntArray out(solver.jointCount());
    const IkStatus status = solver.inverse(target, seed, out);
    if (status != IkStatus::Ok) {
      EXPECT_EQ(status, IkStatus::NoConvergence);  // near-singular seeds may stall; never garbage
      continue;
    }
    ++solved;
    KDL::Frame reached;
    ASSERT_EQ(solver.forward(out, reached), IkStatus::Ok);
    EXPECT_LT(norm(reached.p - target.p), 1e-9);
    EXPECT_LT(orientationError(reached.M, target.M), 1e-9);
    EXPECT_TRUE(solver.limits().contains(out));
  }
  EXPECT_GE(solved, kCount * 95 / 100);
}

INSTANTIATE_TEST_SUITE_P(Methods, SerialChainIk,
                         ::testing::Values(IterativeIk::NewtonRaphsonJL, IterativeIk::LevenbergMarquardt));

TEST(SerialChain, UnreachableTargetLeavesTheOutputUntouched) {
  for (const IterativeIk method : {IterativeIk::NewtonRaphsonJL, IterativeIk::LevenbergMarquardt}) {
    SerialChainSolver solver(sixAxisModel(), {.method = method});
    KDL::JntArray seed(6);
    KDL::JntArray out = test::filled(6, 42.0);
    const KDL::Frame far_away(KDL::Vector(5.0, 0.0, 0.0));
    EXPECT_EQ(solver.inverse(far_away, seed, out), IkStatus::Unreachable);
    EXPECT_TRUE(test::isFilled(out, 42.0));
  }
}

TEST(SerialChain, BadInputIsRefused) {
  SerialChainSolver solver(sixAxisModel());
  KDL::JntArray wrong(5);
  KDL::JntArray q(6);
  KDL::Frame pose;
  EXPECT_EQ(solver.forward(wrong, pose), IkStatus::BadInput);
  q(2) = std::nan("");
  EXPECT_EQ(solver.forward(q, pose), IkStatus::BadInput);
  KDL::JntArray seed(6);
  EXPECT_EQ(solver.inverse(KDL::Frame::Identity(), seed, wrong), IkStatus::BadInput);
  KDL::Frame not_a_pose;
  not_a_pose.M = KDL::Rotation(2, 0, 0, 0, 1, 0, 0, 0, 1);
  EXPECT_EQ(solver.inverse(not_a_pose, seed, q), IkStatus::BadInput);
  KDL::Jacobian jacobian(4);
  EXPECT_EQ(solver.jacobian(seed, jacobian), IkStatus::BadInput);
}

// A pose reached with joint 1 at 2.0 rad, limits on joint 1 of [-0.5, 0.5] rad: LMA finds the
// pose (it ignores limits) and the solver refuses it; NR_JL clamps and cannot get there.
TEST(SerialChain, JointLimitsAreEnforced) {
  std::vector<DhRow> rows = sixAxisModel().rows();
  rows[0].lower = -0.5;
  rows[0].upper = 0.5;
  const SerialChainModel narrow("narrow", rows);
  const KDL::JntArray q = test::joints({2.0, -1.0, 1.2, 0.4, 0.9, 0.3});
  const KDL::Frame target = narrow.forward(std::span<const double>(q.data.data(), 6));
  KDL::JntArray out = test::filled(6, 42.0);
  KDL::JntArray seed = q;
  seed(0) = 1.9;
  SerialChainSolver lma(narrow, {.method = IterativeIk::LevenbergMarquardt});
  EXPECT_EQ(lma.inverse(target, seed, out), IkStatus::JointLimits);
  SerialChainSolver nr(narrow, {.method = IterativeIk::NewtonRaphsonJL});
  seed(0) = 0.4;
  const IkStatus status = nr.inverse(target, seed, out);
  if (status == IkStatus::Ok) {
    EXPECT_TRUE(narrow.limits().contains(out));  // another branch inside the limits is fine
  } else {
    EXPECT_EQ(status, IkStatus::NoConvergence);
    EXPECT_TRUE(test::isFilled(out, 42.0));
  }
}

TEST(SerialChainModel, ConstructionErrorsNameTheRobotJointAndParameter) {
  std::vector<DhRow> rows = sixAxisModel().rows();
  rows[2].lower = 2.0;
  rows[2].upper = 1.0;
  EXPECT_EQ(messageOf([&] { SerialChainModel("UR5", rows); }), "UR5: joint 3 limits [2, 1] rad: min must be <= max");

  rows = sixAxisModel().rows();
  rows[1].a = std::nan("");
  EXPECT_EQ(messageOf([&] { SerialChainModel("UR5", rows); }),
            "UR5: joint 2 DH parameter a is nan: give a finite value in m");

  rows = sixAxisModel().rows();
  rows[4].upper = std::numeric_limits<double>::infinity();
  EXPECT_CONTAINS(messageOf([&] { SerialChainModel("arm", rows); }), "arm: joint 5 limits [-3.14");
  EXPECT_CONTAINS(messageOf([&] { SerialChainModel("arm", rows); }), "both bounds must be finite numbers");

  EXPECT_EQ(messageOf([] { SerialChainModel("arm", {}); }), "arm: the DH table is empty: give one row per joint");

  KDL::Frame skewed;
  skewed.M = KDL::Rotation(1, 0.5, 0, 0, 1, 0, 0, 0, 1);
  EXPECT_CONTAINS(messageOf([&] { SerialChainModel("arm", sixAxisModel().rows(), skewed); }),
                  "arm: the base frame is not a pose");

  EXPECT_EQ(messageOf([] { SerialChainSolver(sixAxisModel(), {.position_tolerance = 0.0}); }),
            "test arm: IK tolerances must be > 0 (position 0 m, orientation 1e-09 rad)");
}

// The real-time path of a constructed solver: forward, jacobian and inverse (KDL's CartToJnt plus
// the polishing steps) allocate nothing.
TEST(SerialChain, AllocationsOnTheRealTimePath) {
  for (const IterativeIk method : {IterativeIk::NewtonRaphsonJL, IterativeIk::LevenbergMarquardt}) {
    SerialChainSolver solver(sixAxisModel(), {.method = method});
    KDL::JntArray q(6);
    for (unsigned j = 0; j < 6; ++j) q(j) = 0.3 + 0.1 * j;
    KDL::JntArray seed = q;
    seed(0) += 0.1;
    KDL::JntArray out(6);
    KDL::Frame pose;
    KDL::Jacobian jacobian(6);
    solver.forward(q, pose);
    solver.inverse(pose, seed, out);  // first call: any lazy set-up happens here
    EXPECT_EQ(allocationsDuring([&] { solver.forward(q, pose); }), 0);
    EXPECT_EQ(allocationsDuring([&] { solver.jacobian(q, jacobian); }), 0);
    // KDL 1.5's NR_JL and LMA preallocate in their constructors: CartToJnt allocates nothing.
    const long ik_allocations = allocationsDuring([&] { EXPECT_EQ(solver.inverse(pose, seed, out), IkStatus::Ok); });
    EXPECT_EQ(ik_allocations, 0) << (method == IterativeIk::NewtonRaphsonJL ? "NR_JL" : "LMA");
  }
}

}  // namespace
}  // namespace cobra::kinematics
