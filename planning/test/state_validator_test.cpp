// isStateValid (Algorithms 4.2 and 5.1) on the two-robot test scene with stand-in robots: each
// failure comes back with the right reason, groups, objects and distance.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "cobra/planning/robot_adapters.hpp"
#include "cobra/planning/state_validator.hpp"
#include "cobra/test_support/counting_new.hpp"
#include "cobra/test_support/test_support.hpp"
#include "planning_fixture.hpp"
#include "puncturing_tools.hpp"

namespace cobra::planning {
namespace {

using cobra::test_support::messageOf;
using test::toolsAt;

class StateValidatorTest : public ::testing::Test {
 protected:
  StateValidator validator{test::twoRobotScene(), test::twoRobotModels()};
};

TEST_F(StateValidatorTest, FreeQueryIsValid) {
  const ValidityResult result = validator.check(toolsAt({-0.3, 0, 0.3}, {0, 0.3, 0.3}));
  EXPECT_TRUE(result.valid()) << describe(result);
  EXPECT_TRUE(validator.isStateValid(toolsAt({-0.3, 0, 0.3}, {0, 0.3, 0.3})));
}

TEST_F(StateValidatorTest, NeedleInsidePhantomIsTooCloseToTheEnvironment) {
  const ValidityResult result = validator.check(toolsAt({0.3, 0, 0.16}, {0, 0.3, 0.3}), true);
  EXPECT_EQ(result.validity, Validity::TooClose);
  EXPECT_EQ(result.first_group, "micro");
  EXPECT_EQ(result.second_group, "environment");
  EXPECT_EQ(result.first_object, "needle");
  EXPECT_EQ(result.second_object, "phantom");
  EXPECT_EQ(result.distance, 0.0);
  EXPECT_CONTAINS(describe(result), "too close: micro/environment at 0 m (needle/phantom)");
}

TEST_F(StateValidatorTest, ProbeThroughTheGantryColumnIsTooCloseToTheMacroGroup) {
  // The gantry's tool at (-0.3, 0, 0.3) is free; its column spans z 0.3..0.7 m at x = -0.3 m.
  const ValidityResult result = validator.check(toolsAt({-0.3, 0, 0.3}, {-0.3, 0, 0.55}), true);
  EXPECT_EQ(result.validity, Validity::TooClose);
  EXPECT_EQ(result.first_group, "macro");
  EXPECT_EQ(result.second_group, "ur5");
  EXPECT_EQ(result.first_object, "column");
  EXPECT_EQ(result.second_object, "probe");
}

TEST_F(StateValidatorTest, ThresholdIsTheSceneMinimumCollisionDistance) {
  // Tool sphere (r 0.02) and vertical probe capsule (r 0.02): gap = separation - 0.04 m.
  EXPECT_TRUE(validator.isStateValid(toolsAt({0, 0, 0.3}, {0.0451, 0, 0.3})));
  const ValidityResult result = validator.check(toolsAt({0, 0, 0.3}, {0.0449, 0, 0.3}), true);
  EXPECT_EQ(result.validity, Validity::TooClose);
  EXPECT_EQ(result.first_group, "micro");
  EXPECT_EQ(result.second_group, "ur5");
  EXPECT_NEAR(result.distance, 0.0049, 1e-6);
}

TEST_F(StateValidatorTest, MinimumDistanceIsTheClosestCheckedPair) {
  // Closest pair: tool sphere/probe capsule 0.1 - 0.04 = 0.06 m; others are farther (see scene).
  EXPECT_NEAR(validator.minimumDistance(toolsAt({0, 0, 0.3}, {0.1, 0, 0.3})), 0.06, 1e-6);
  EXPECT_TRUE(std::isnan(validator.minimumDistance(toolsAt({0.9, 0, 0.3}, {0, 0.3, 0.3}))));
}

TEST_F(StateValidatorTest, UnreachablePoseNamesTheRobot) {
  ValidityResult result = validator.check(toolsAt({0.9, 0, 0.3}, {0, 0.3, 0.3}));
  EXPECT_EQ(result.validity, Validity::Unreachable);
  EXPECT_EQ(result.robot, "isur");
  result = validator.check(toolsAt({-0.3, 0, 0.3}, {0, 0, 1.2}));
  EXPECT_EQ(result.validity, Validity::Unreachable);
  EXPECT_EQ(result.robot, "ur5");
  EXPECT_CONTAINS(describe(result), "robot 'ur5' has no IK solution");
}

TEST_F(StateValidatorTest, NanOrNonRotationIsInvalidInput) {
  DualPose q = toolsAt({-0.3, 0, 0.3}, {0, 0.3, 0.3});
  q.second.p.z(std::numeric_limits<double>::quiet_NaN());
  EXPECT_EQ(validator.check(q).validity, Validity::InvalidInput);
  q = toolsAt({-0.3, 0, 0.3}, {0, 0.3, 0.3});
  q.first.M = KDL::Rotation(2, 0, 0, 0, 1, 0, 0, 0, 1);
  EXPECT_EQ(validator.check(q).validity, Validity::InvalidInput);
  q.first.M = KDL::Rotation(-1, 0, 0, 0, 1, 0, 0, 0, 1);  // a reflection, not a rotation
  EXPECT_EQ(validator.check(q).validity, Validity::InvalidInput);
}

TEST_F(StateValidatorTest, RotatedToolSwingsTheNeedle) {
  // Tool beside the phantom (x 0.25..0.35 m, z 0..0.1 m): with the needle (0.1 m along the tool's
  // -z) pointing down it is free; tilted 45 degrees towards +x the needle tip enters the phantom.
  DualPose q = toolsAt({0.17, 0, 0.06 + 0.1 + 0.01}, {0, 0.3, 0.3});
  EXPECT_TRUE(validator.isStateValid(q)) << describe(validator.check(q));
  q.first.M = KDL::Rotation::RotY(-M_PI / 2);
  q.first.p = KDL::Vector(0.17, 0, 0.05);
  EXPECT_EQ(validator.check(q).validity, Validity::Unreachable);  // below the gantry's z range
  q.first.p = KDL::Vector(0.19, 0, 0.16);
  q.first.M = KDL::Rotation::RotY(-M_PI / 4);
  const ValidityResult result = validator.check(q, true);
  EXPECT_EQ(result.validity, Validity::TooClose) << describe(result);
  EXPECT_EQ(result.second_group, "environment");
}

TEST(StateValidator, RobotBasePlacementMovesTheLinks) {
  // Same query, ur5 base moved 0.2 m along x: the probe reaches the same world pose (its IK is
  // in the base frame) and its reach sphere moves with the base.
  SceneDescription scene = test::twoRobotScene();
  scene.robots[1].base_in_world = KDL::Frame(KDL::Vector(0.2, 0, 0));
  StateValidator validator(scene, test::twoRobotModels());
  EXPECT_EQ(validator.check(toolsAt({-0.3, 0, 0.3}, {-0.45, 0.3, 0.5})).validity, Validity::Unreachable);
  EXPECT_TRUE(validator.isStateValid(toolsAt({-0.3, 0, 0.3}, {0.6, 0.3, 0.3})));
}

TEST(StateValidator, TheSceneToolFrameIsWhatThePosesName) {
  // The poses of q name a frame 0.1 m above the gantry's tool (identity rotations here). Low
  // enough that the needle's tip is the closest object to the table (0.07 m; the column is 0.08 m
  // from the tool): the shifted scene at q moved up 0.1 m sees exactly the plain scene at q, and
  // not the plain scene at the moved q.
  SceneDescription scene = test::twoRobotScene();
  scene.robots[0].setToolFrame(0, KDL::Frame(KDL::Vector(0, 0, 0.1)));
  StateValidator shifted(scene, test::twoRobotModels());
  StateValidator plain(test::twoRobotScene(), test::twoRobotModels());
  const DualPose q = toolsAt({-0.3, 0, 0.17}, {0.6, 0.3, 0.3});
  const DualPose moved{KDL::Frame(KDL::Vector(0, 0, 0.1)) * q.first, q.second};
  const double expected = plain.minimumDistance(q);
  ASSERT_TRUE(std::isfinite(expected));
  EXPECT_NEAR(shifted.minimumDistance(moved), expected, 1e-9);
  EXPECT_GT(std::abs(plain.minimumDistance(moved) - expected), 1e-3) << "the offset must matter in this query";
}

TEST(StateValidator, OneSolverForBothTools) {
  // Algorithm 5.1: one robot takes both poses; its links go to two groups.
  const SceneDescription scene = parseScene(
      "min_collision_distance 0.01\nrobot isur tools 0 1 base 0 0 0 0 0 0\ngroup right\ngroup left\n"
      "object right_tool right isur.0 sphere 0.02 at 0 0 0 0 0 0\n"
      "object left_tool left isur.1 sphere 0.02 at 0 0 0 0 0 0\ncheck right left\n",
      "suturing.scene", test::dataDir());
  StateValidator validator(scene, {{"isur", std::make_shared<test::StandInTwoArmed>(0.3)}});
  EXPECT_TRUE(validator.isStateValid(toolsAt({0, 0, 0}, {0.1, 0, 0})));
  EXPECT_EQ(validator.check(toolsAt({0, 0, 0}, {0.045, 0, 0})).validity, Validity::TooClose);
  EXPECT_EQ(validator.check(toolsAt({0, 0, 0}, {0.4, 0, 0})).validity, Validity::Unreachable);
}

TEST(StateValidator, ConfigurationErrorsExplainTheFix) {
  RobotModels models = test::twoRobotModels();
  models.erase("ur5");
  EXPECT_CONTAINS(messageOf([&] { StateValidator v(test::twoRobotScene(), models); }),
                  "the scene's robot 'ur5' has no robot model");
  models = test::twoRobotModels();
  models["ur5"] = std::make_shared<test::StandInTwoArmed>(1.0);
  EXPECT_CONTAINS(messageOf([&] { StateValidator v(test::twoRobotScene(), models); }),
                  "robot 'ur5' takes 2 tool(s) but the scene gives it 1");
  const SceneDescription scene = test::twoRobotScene("object extra ur5 ur5.3 sphere 0.01 at 0 0 0 0 0 0\n");
  EXPECT_CONTAINS(messageOf([&] { StateValidator v(scene, test::twoRobotModels()); }),
                  "attaches objects to link 3 of robot 'ur5' but its model has 1 links");
}

// The clearance per pair of groups on the puncturing scene with the real robot models: every
// checked pair whose distance the joints change, each the minimum over its object pairs that move,
// the declared contacts and the pairs no joint moves (the UR5 base's fixed 20 mm gap to the table)
// left out; a pair of two fixed groups is left out whole.
TEST(StateValidator, GivesTheClearanceOfEachPairOfGroupsThatMoves) {
  const std::string text = test::readText(test::scenes() / "puncturing.scene") +
                           "group stand\nobject stand stand world box 0.1 0.1 0.1 at 0.6 0.4 0.1 0 0 0\n"
                           "check stand environment\n";
  StateValidator validator(parseScene(text, "puncturing.scene", test::scenes()),
                           {{"isur", std::make_shared<IsurPuncturingModel>()}, {"ur5", std::make_shared<Ur5Model>()}});
  EXPECT_EQ(validator.clearancePairs(), (std::vector<std::string>{"macro/micro", "macro/ur5", "micro/ur5",
                                                                  "micro/environment", "ur5/environment"}));
  const SceneDescription& scene = validator.scene();
  std::vector<double> q(validator.jointCount());
  std::size_t failed = 0;
  ASSERT_EQ(validator.inverseNear({test::needleDown(0.0, 0.0, 0.2), test::probeDown(-0.1, 0.0, 0.12)}, {}, q, failed),
            Reachability::Reachable);
  std::vector<double> pairs(5);
  ASSERT_TRUE(validator.pairDistancesAt(q, pairs));
  const StateValidator::Distances all = validator.distancesAt(q);
  auto between = [&](const char* a, const char* b) {
    return validator.world().objectDistance(scene.objectIndex(a), scene.objectIndex(b));
  };
  EXPECT_NEAR(between("ur5_base", "table"), 0.02, 1e-9) << "the fixed gap the minimum over all pairs shows";
  EXPECT_NEAR(all.clearance, 0.02, 1e-9);
  // ur5/environment: the UR5's moving links and the probe to the table and the phantom, neither
  // the base (fixed) nor the probe on the phantom (an allowed contact).
  double expected = INFINITY;
  for (const char* link : {"ur5_shoulder", "ur5_upper_arm", "ur5_forearm", "ur5_wrist_1", "ur5_wrist_2", "ur5_wrist_3"})
    for (const char* world : {"table", "phantom"}) expected = std::min(expected, between(link, world));
  expected = std::min(expected, between("us_probe", "table"));
  EXPECT_DOUBLE_EQ(pairs[4], expected);
  EXPECT_GT(pairs[4], 0.02);
  for (double d : pairs) EXPECT_GE(d, all.clearance);
  // Moving the UR5 only changes the pairs it is in.
  std::vector<double> moved = q, after(5);
  moved[validator.jointOffset(1) + 1] += 0.05;
  ASSERT_TRUE(validator.pairDistancesAt(moved, after));
  EXPECT_EQ(after[0], pairs[0]);
  EXPECT_EQ(after[3], pairs[3]);
  EXPECT_NE(after[2], pairs[2]);
  // The measured state's query runs in the planner component's step: it allocates nothing.
  EXPECT_EQ(cobra::test_support::allocationsDuring([&] { validator.pairDistancesAt(q, pairs); }), 0);
  moved[validator.jointOffset(1)] = 100.0;  // outside the UR5's limits: no forward kinematics
  EXPECT_FALSE(validator.pairDistancesAt(moved, after));
  EXPECT_TRUE(std::isnan(after[2]));
}

}  // namespace
}  // namespace cobra::planning
