// Unit tests of linear_delta.hpp: FK∘IK and IK∘FK round trips on seeded random samples, every rod
// at its length (an independent check of FK), symmetry, assembly mode, unreachable and
// out-of-stroke targets, the singular FK, construction errors and no allocation.

#include <gtest/gtest.h>

#include "cobra/test_support/counting_new.hpp"
#include "cobra/test_support/test_support.hpp"

#include <cmath>
#include <random>

#include "cobra/kinematics/geometry.hpp"
#include "cobra/kinematics/linear_delta.hpp"

#include "kinematics_test_support.hpp"

namespace cobra::kinematics {
namespace {

using cobra::test_support::allocationsDuring;
using cobra::test_support::messageOf;

double rodLengthError(const LinearDeltaGeometry& g, const std::array<double, 3>& q, const KDL::Vector& p) {
  double worst = 0.0;
  for (std::size_t i = 0; i < 3; ++i) {
    const LinearDeltaActuator& a = g.actuators[i];
    const KDL::Vector rod = p + a.platform_joint - (a.rail_origin + q[i] * a.rail_direction);
    worst = std::max(worst, std::abs(norm(rod) - a.rod_length));
  }
  return worst;
}

// 5000 seeded random slider travels within the stroke: FK succeeds, every rod has its length,
// the platform is below its sliders, and IK gives the travels back within 1e-9 m.
TEST(LinearDelta, ForwardThenInverseGivesTheJointsBack) {
  LinearDeltaSolver delta;
  std::mt19937 rng(31);
  std::uniform_real_distribution<double> travel(0.0, 0.25);
  for (int n = 0; n < 5000; ++n) {
    const std::array<double, 3> q = {travel(rng), travel(rng), travel(rng)};
    KDL::Vector p;
    ASSERT_EQ(delta.forwardPosition(q, p), IkStatus::Ok) << "sample " << n;
    EXPECT_LT(rodLengthError(delta.geometry(), q, p), 1e-12);
    for (std::size_t i = 0; i < 3; ++i) {
      const LinearDeltaActuator& a = delta.geometry().actuators[i];
      EXPECT_LT(p.z(), (a.rail_origin + q[i] * a.rail_direction).z());
    }
    std::array<double, 3> back{};
    ASSERT_EQ(delta.inversePosition(p, back), IkStatus::Ok) << "sample " << n;
    for (std::size_t i = 0; i < 3; ++i) EXPECT_NEAR(back[i], q[i], 1e-9) << "sample " << n << " actuator " << i + 1;
  }
}

// 5000 seeded random platform positions in a box around the workspace: where IK succeeds, FK
// gives the position back within 1e-9 m; the box also contains unreachable and out-of-stroke
// points, and both statuses occur.
TEST(LinearDelta, InverseThenForwardGivesThePositionBack) {
  LinearDeltaSolver delta;
  std::mt19937 rng(32);
  std::uniform_real_distribution<double> horizontal(-0.25, 0.25);
  std::uniform_real_distribution<double> vertical(-0.7, -0.15);
  int ok = 0;
  int out_of_stroke = 0;
  int unreachable = 0;
  for (int n = 0; n < 5000; ++n) {
    const KDL::Vector p(horizontal(rng), horizontal(rng), vertical(rng));
    std::array<double, 3> q = {7.0, 7.0, 7.0};
    const IkStatus status = delta.inversePosition(p, q);
    if (status != IkStatus::Ok) {
      EXPECT_EQ(q[0], 7.0);  // untouched
      out_of_stroke += status == IkStatus::JointLimits ? 1 : 0;
      unreachable += status == IkStatus::Unreachable ? 1 : 0;
      continue;
    }
    ++ok;
    EXPECT_TRUE(delta.limits().contains(q));
    KDL::Vector back;
    ASSERT_EQ(delta.forwardPosition(q, back), IkStatus::Ok);
    EXPECT_LT(norm(back - p), 1e-9) << "sample " << n;
  }
  EXPECT_GT(ok, 500);  // 735 with this seed: the workspace is a fraction of the box
  EXPECT_GT(out_of_stroke, 100);
  EXPECT_GT(unreachable, 100);
}

// 500 seeded random travels: the Jacobian's columns equal central differences of forwardPosition.
TEST(LinearDelta, JacobianMatchesFiniteDifferences) {
  LinearDeltaSolver delta;
  std::mt19937 rng(33);
  std::uniform_real_distribution<double> travel(0.01, 0.24);
  for (int n = 0; n < 500; ++n) {
    const std::array<double, 3> q = {travel(rng), travel(rng), travel(rng)};
    Eigen::Matrix3d jacobian;
    ASSERT_EQ(delta.jacobian(q, jacobian), IkStatus::Ok);
    constexpr double h = 1e-6;
    for (std::size_t i = 0; i < 3; ++i) {
      std::array<double, 3> plus = q;
      std::array<double, 3> minus = q;
      plus[i] += h;
      minus[i] -= h;
      KDL::Vector p_plus;
      KDL::Vector p_minus;
      delta.forwardPosition(plus, p_plus);
      delta.forwardPosition(minus, p_minus);
      const Eigen::Vector3d column = toEigen((p_plus - p_minus) / (2 * h));
      EXPECT_LT((jacobian.col(static_cast<Eigen::Index>(i)) - column).norm(), 1e-7) << "sample " << n;
    }
  }
}

TEST(LinearDelta, EqualTravelsKeepThePlatformOnTheAxis) {
  LinearDeltaSolver delta;
  KDL::Vector p;
  ASSERT_EQ(delta.forwardPosition(std::array<double, 3>{0.1, 0.1, 0.1}, p), IkStatus::Ok);
  EXPECT_NEAR(p.x(), 0.0, 1e-15);
  EXPECT_NEAR(p.y(), 0.0, 1e-15);
  // By hand: slider radius 0.30 - 0.1·sin30° = 0.25 m, height -0.1·cos30°; the rod spans
  // 0.25 - 0.06 = 0.19 m horizontally, so it drops sqrt(0.35² - 0.19²) m below the slider.
  EXPECT_NEAR(p.z(), -0.1 * std::cos(std::numbers::pi / 6) - std::sqrt(0.35 * 0.35 - 0.19 * 0.19), 1e-12);
}

TEST(LinearDelta, KinematicsSolverInterfaceUsesThePlatformFrame) {
  LinearDeltaSolver delta;
  const KDL::JntArray q = test::joints({0.05, 0.12, 0.2});
  KDL::Frame pose;
  ASSERT_EQ(delta.forward(q, pose), IkStatus::Ok);
  EXPECT_EQ(orientationError(pose.M, KDL::Rotation::Identity()), 0.0);
  KDL::JntArray seed(3);
  KDL::JntArray out(3);
  ASSERT_EQ(delta.inverse(pose, seed, out), IkStatus::Ok);
  for (unsigned i = 0; i < 3; ++i) EXPECT_NEAR(out(i), q(i), 1e-9);
  // The platform cannot rotate.
  out(0) = 42.0;
  EXPECT_EQ(delta.inverse(KDL::Frame(KDL::Rotation::RotZ(0.01), pose.p), seed, out), IkStatus::Unreachable);
  EXPECT_EQ(out(0), 42.0);
  EXPECT_EQ(delta.inverse(pose, KDL::JntArray(2), out), IkStatus::BadInput);
}

TEST(LinearDelta, UnreachableAndOutOfStrokeTargetsLeaveTheOutputUntouched) {
  LinearDeltaSolver delta;
  std::array<double, 3> q = {7.0, 7.0, 7.0};
  EXPECT_EQ(delta.inversePosition(KDL::Vector(0.0, 0.0, -2.0), q), IkStatus::Unreachable);
  // Directly on the axis but above the lowest slider height reachable: travel below 0.
  EXPECT_EQ(delta.inversePosition(KDL::Vector(0.0, 0.0, -0.2), q), IkStatus::JointLimits);
  EXPECT_EQ(q[0], 7.0);
  // Rods too short for sliders this far apart: the spheres do not meet.
  KDL::Vector p;
  LinearDeltaGeometry short_rods = LinearDeltaGeometry::isurMacro();
  for (auto& a : short_rods.actuators) a.rod_length = 0.1;
  EXPECT_EQ(LinearDeltaSolver(short_rods).forwardPosition(std::array<double, 3>{0.0, 0.0, 0.0}, p),
            IkStatus::Unreachable);
}

TEST(LinearDelta, CollinearSphereCentresAreSingular) {
  // Three parallel vertical rails in one plane: the sphere centres are collinear for equal travels.
  LinearDeltaGeometry g;
  for (std::size_t i = 0; i < 3; ++i) {
    g.actuators[i] = LinearDeltaActuator{.rail_origin = KDL::Vector(0.1 * static_cast<double>(i), 0.0, 0.0),
                                         .rail_direction = KDL::Vector(0.0, 0.0, -1.0),
                                         .platform_joint = KDL::Vector::Zero(),
                                         .rod_length = 0.3,
                                         .lower = 0.0,
                                         .upper = 0.2};
  }
  KDL::Vector p;
  EXPECT_EQ(LinearDeltaSolver(g).forwardPosition(std::array<double, 3>{0.1, 0.1, 0.1}, p), IkStatus::Singular);
  Eigen::Matrix3d jacobian;
  EXPECT_EQ(LinearDeltaSolver(g).jacobian(std::array<double, 3>{0.1, 0.1, 0.1}, jacobian), IkStatus::Singular);
}

// Vertical rails, rods exactly spanning the gap: with equal travels the rods lie flat, perpendicular
// to their rails — the platform is reachable, its velocity along z is not controllable.
TEST(LinearDelta, FlatRodsAreAJacobianSingularity) {
  LinearDeltaGeometry g = LinearDeltaGeometry::isurMacro();
  for (LinearDeltaActuator& a : g.actuators) {
    a.rail_direction = KDL::Vector(0.0, 0.0, -1.0);
    a.rod_length = 0.30 - 0.06;
  }
  LinearDeltaSolver delta(g);
  KDL::Vector p;
  ASSERT_EQ(delta.forwardPosition(std::array<double, 3>{0.1, 0.1, 0.1}, p), IkStatus::Ok);
  EXPECT_NEAR(p.z(), -0.1, 1e-12);
  Eigen::Matrix3d jacobian;
  EXPECT_EQ(delta.jacobian(std::array<double, 3>{0.1, 0.1, 0.1}, jacobian), IkStatus::Singular);
}

TEST(LinearDelta, ConstructionErrorsNameTheActuator) {
  LinearDeltaGeometry g = LinearDeltaGeometry::isurMacro();
  g.actuators[1].rod_length = -0.1;
  EXPECT_EQ(messageOf([&] { LinearDeltaSolver{g}; }), "linear delta: actuator 2 rod length -0.1 m: must be > 0");
  g = LinearDeltaGeometry::isurMacro();
  g.actuators[0].rail_direction = KDL::Vector::Zero();
  EXPECT_EQ(messageOf([&] { LinearDeltaSolver{g}; }),
            "linear delta: actuator 1 rail direction is zero: give the direction of travel");
  g = LinearDeltaGeometry::isurMacro();
  g.actuators[2].lower = 0.3;
  EXPECT_EQ(messageOf([&] { LinearDeltaSolver(g, "I-SUR macro"); }),
            "I-SUR macro: joint 3 limits [0.3, 0.25] m: min must be <= max");
  g = LinearDeltaGeometry::isurMacro();
  g.actuators[0].rail_direction = KDL::Vector(1.0, 0.0, 0.0);
  EXPECT_EQ(messageOf([&] { LinearDeltaSolver{g}; }),
            "linear delta: actuator 1 rail is perpendicular to platform_side: the assembly mode is undefined");
  g = LinearDeltaGeometry::isurMacro();
  g.platform_side = KDL::Vector::Zero();
  EXPECT_EQ(messageOf([&] { LinearDeltaSolver{g}; }), "linear delta: platform_side must be a finite non-zero vector");
}

TEST(LinearDelta, RealTimeCallsAllocateNothing) {
  LinearDeltaSolver delta;
  const KDL::JntArray q = test::joints({0.1, 0.15, 0.05});
  KDL::JntArray out(3);
  KDL::Frame pose;
  EXPECT_EQ(allocationsDuring([&] { delta.forward(q, pose); }), 0);
  EXPECT_EQ(allocationsDuring([&] { EXPECT_EQ(delta.inverse(pose, q, out), IkStatus::Ok); }), 0);
}

}  // namespace
}  // namespace cobra::kinematics
