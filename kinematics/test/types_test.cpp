// Unit tests of types.hpp: status names, limit validation messages, 2π wrapping into limits and
// the nearest-to-seed choice among analytic solutions (also restricted to a branch), branch
// compatibility.

#include <gtest/gtest.h>

#include "cobra/test_support/test_support.hpp"

#include <array>
#include <numbers>

#include "cobra/kinematics/types.hpp"

#include "kinematics_test_support.hpp"

namespace cobra::kinematics {
namespace {

using cobra::test_support::messageOf;
constexpr double kPi = std::numbers::pi;

TEST(IkStatus, HasStableNames) {
  EXPECT_STREQ(toString(IkStatus::Ok), "ok");
  EXPECT_STREQ(toString(IkStatus::Unreachable), "unreachable");
  EXPECT_STREQ(toString(IkStatus::JointLimits), "joint limits");
  EXPECT_STREQ(toString(IkStatus::Singular), "singular");
  EXPECT_STREQ(toString(IkStatus::NoConvergence), "no convergence");
  EXPECT_STREQ(toString(IkStatus::BadInput), "bad input");
  EXPECT_STREQ(toString(IkStatus::Discontinuous), "discontinuous");
}

TEST(ValidateLimits, MessagesNameTheRobotJointAndUnit) {
  JointLimits limits = revoluteLimits(3, -1.0, 1.0);
  EXPECT_NO_THROW(validateLimits("arm", limits, 3));
  limits.types[1] = JointType::Prismatic;
  limits.lower[1] = 0.3;
  limits.upper[1] = 0.1;
  EXPECT_EQ(messageOf([&] { validateLimits("delta", limits, 3); }),
            "delta: joint 2 limits [0.3, 0.1] m: min must be <= max");
  EXPECT_CONTAINS(messageOf([&] { validateLimits("arm", revoluteLimits(3, -1, 1), 4); }),
                  "arm: joint limits have 3 lower, 3 upper bounds and 3 joint types; the robot has 4 joints");
}

TEST(WrapIntoLimits, PicksThe2PiRepresentativeNearestTheSeedInsideTheLimits) {
  const JointLimits limits = revoluteLimits(1, -2 * kPi, 2 * kPi);
  double q = -0.5;
  double seed = 5.0;
  ASSERT_TRUE(wrapIntoLimits(std::span<double>(&q, 1), limits, std::span<const double>(&seed, 1)));
  EXPECT_NEAR(q, -0.5 + 2 * kPi, 1e-12);  // 5.78 is inside ±2π and nearer to 5.0 than -0.5
  q = 0.5;                                // 0.5 + 2π is outside ±2π: stays
  ASSERT_TRUE(wrapIntoLimits(std::span<double>(&q, 1), limits, std::span<const double>(&seed, 1)));
  EXPECT_NEAR(q, 0.5, 1e-12);

  const JointLimits narrow = revoluteLimits(1, 3.0, 4.0);
  q = -2.9;  // ≡ 3.383 rad
  seed = 0.0;
  ASSERT_TRUE(wrapIntoLimits(std::span<double>(&q, 1), narrow, std::span<const double>(&seed, 1)));
  EXPECT_NEAR(q, -2.9 + 2 * kPi, 1e-12);
  q = 1.0;  // no representative in [3, 4]
  EXPECT_FALSE(wrapIntoLimits(std::span<double>(&q, 1), narrow, std::span<const double>(&seed, 1)));
}

TEST(SelectNearest, ChoosesTheClosestSolutionInLimitsAndReportsWhyOtherwise) {
  IkSolutionSet set;
  set.reset(2);
  const double a[] = {0.1, 0.2};
  const double b[] = {1.5, -1.0};
  ASSERT_TRUE(set.push(a));
  ASSERT_TRUE(set.push(b));
  const KDL::JntArray seed = test::joints({1.4, -0.8});
  KDL::JntArray out(2);
  ASSERT_EQ(selectNearest(set, revoluteLimits(2, -kPi, kPi), seed, out), IkStatus::Ok);
  EXPECT_DOUBLE_EQ(out(0), 1.5);
  EXPECT_DOUBLE_EQ(out(1), -1.0);

  // Joint 1 limited to [-0.5, 0.5]: only solution a fits.
  JointLimits limits = revoluteLimits(2, -kPi, kPi);
  limits.lower[0] = -0.5;
  limits.upper[0] = 0.5;
  ASSERT_EQ(selectNearest(set, limits, seed, out), IkStatus::Ok);
  EXPECT_DOUBLE_EQ(out(0), 0.1);

  limits.upper[0] = -0.4;
  out(0) = 42.0;
  EXPECT_EQ(selectNearest(set, limits, seed, out), IkStatus::JointLimits);
  EXPECT_EQ(out(0), 42.0);

  set.reset(2);
  EXPECT_EQ(selectNearest(set, limits, seed, out), IkStatus::Unreachable);
  KDL::JntArray wrong(3);
  EXPECT_EQ(selectNearest(set, limits, wrong, out), IkStatus::BadInput);
}

TEST(SelectNearest, KeepsToTheGivenBranch) {
  IkSolutionSet set;
  set.reset(2);
  const std::array<double, 2> near_one{0.1, 0.0};
  const std::array<double, 2> far_one{1.5, 0.0};
  set.push(near_one, IkBranch{.bits = 1, .ambiguous = 0});
  set.push(far_one, IkBranch{.bits = 0, .ambiguous = 0});
  const KDL::JntArray seed = test::joints({0.0, 0.0});
  KDL::JntArray out = test::filled(2, 7.0);
  const JointLimits limits = revoluteLimits(2, -kPi, kPi);
  ASSERT_EQ(selectNearest(set, limits, seed, out), IkStatus::Ok);  // any branch: the nearest
  EXPECT_DOUBLE_EQ(out(0), 0.1);
  ASSERT_EQ(selectNearest(set, limits, seed, out, IkBranch{.bits = 0, .ambiguous = 0}), IkStatus::Ok);
  EXPECT_DOUBLE_EQ(out(0), 1.5);
  ASSERT_EQ(selectNearest(set, limits, seed, out, IkBranch{.bits = 0, .ambiguous = 1}), IkStatus::Ok);  // bit 0 free
  EXPECT_DOUBLE_EQ(out(0), 0.1);
  out = test::filled(2, 7.0);
  set.reset(2);
  set.push(near_one, IkBranch{.bits = 1, .ambiguous = 0});
  EXPECT_EQ(selectNearest(set, limits, seed, out, IkBranch{.bits = 0, .ambiguous = 0}), IkStatus::Discontinuous);
  EXPECT_TRUE(test::isFilled(out, 7.0));
  EXPECT_EQ(selectNearest(set, revoluteLimits(2, 0.5, 1.0), seed, out, IkBranch{}), IkStatus::JointLimits);
}

TEST(IkBranch, ChoicesOnASingularBoundaryAreCompatibleWithBothSides) {
  EXPECT_TRUE((IkBranch{.bits = 5, .ambiguous = 0}).compatibleWith(IkBranch{.bits = 5, .ambiguous = 0}));
  EXPECT_FALSE((IkBranch{.bits = 5, .ambiguous = 0}).compatibleWith(IkBranch{.bits = 1, .ambiguous = 0}));
  EXPECT_TRUE((IkBranch{.bits = 5, .ambiguous = 4}).compatibleWith(IkBranch{.bits = 1, .ambiguous = 0}));
  EXPECT_TRUE((IkBranch{.bits = 1, .ambiguous = 0}).compatibleWith(IkBranch{.bits = 5, .ambiguous = 4}));
  EXPECT_TRUE(IkBranch::any().compatibleWith(IkBranch{.bits = 7, .ambiguous = 0}));
  EXPECT_TRUE(IkBranch{}.compatibleWith(IkBranch{}));  // a solver without branches
}

TEST(IkSolutionSet, HoldsAtMostEightSolutions) {
  IkSolutionSet set;
  set.reset(1);
  const double q[] = {0.0};
  for (std::size_t i = 0; i < IkSolutionSet::kMaxSolutions; ++i) EXPECT_TRUE(set.push(q));
  EXPECT_FALSE(set.push(q));
  EXPECT_EQ(set.size(), IkSolutionSet::kMaxSolutions);
  const double two[] = {0.0, 1.0};
  set.reset(1);
  EXPECT_FALSE(set.push(two));
}

TEST(WrapToPi, MapsIntoTheHalfOpenInterval) {
  EXPECT_NEAR(wrapToPi(3 * kPi), kPi, 1e-12);
  EXPECT_NEAR(wrapToPi(-kPi), kPi, 1e-12);
  EXPECT_NEAR(wrapToPi(0.5 - 4 * kPi), 0.5, 1e-12);
}

}  // namespace
}  // namespace cobra::kinematics
