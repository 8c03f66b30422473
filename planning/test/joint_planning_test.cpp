// The joint-space planner (MotionPlanner::planPath from joints) and the joint-space parts of the
// real robot models on the puncturing scene: goal IK nearest the start, the gimbal lock of the
// I-SUR's wrist, paths whose Cartesian interpolation the continuity-keeping IK follows within the
// joint velocity limits, goals refused with their reason before any search, and the distances of
// the declared allowed contacts reported apart.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <numbers>
#include <random>
#include <vector>

#include "cobra/planning/motion_planner.hpp"
#include "cobra/planning/robot_adapters.hpp"
#include "cobra/test_support/counting_new.hpp"
#include "cobra/test_support/test_support.hpp"
#include "joint_path_checks.hpp"
#include "planning_fixture.hpp"

namespace cobra::planning {
namespace {

using cobra::test_support::allocationsDuring;
constexpr double kPi = std::numbers::pi;

/// The joints apps/puncturing/deployment/world.lua starts the robots at: the needle 10° from
/// vertical at (-0.05, 0.05, 0.26) m, the probe pointing down at (0.2, -0.25, 0.3) m.
const JointState kStart{0.00202, 0.00249, 0.204398, 0, 0, 0.85, 0.55, 0, 0.798, -1.4495, -1.714, 1.5925, -1.571, -2.344};

/// The puncturing scene with the application's needle frames (z along the needle).
StateValidator puncturingValidator() {
  SceneDescription scene = loadScene(std::filesystem::path(COBRA_SOURCE_DIR) / "planning/test/scenes/puncturing.scene");
  for (RobotPlacement& robot : scene.robots)
    if (robot.name == "isur") robot.setToolFrame(0, KDL::Frame(KDL::Rotation::RPY(0.0, kPi / 2, 0.0)));
  RobotModels models = makeRobotModels(scene);
  return StateValidator(std::move(scene), std::move(models));
}

PlannerOptions options() {
  PlannerOptions o;
  o.first_bounds = {{-0.3, -0.3, 0.0}, {0.3, 0.3, 0.5}};
  o.second_bounds = {{-0.4, -0.5, 0.0}, {0.4, 0.4, 0.6}};
  o.max_validity_checks = 200000;
  o.max_linear_velocity = 0.04;
  o.max_angular_velocity = 0.15;
  o.tool_names = {"needle", "probe"};
  return o;
}

/// Needle frame (z along the needle) with its tip at p, the needle tilted `tilt` rad from the
/// vertical toward azimuth `azimuth`.
KDL::Frame needle(const KDL::Vector& p, double tilt, double azimuth) {
  return KDL::Frame(KDL::Rotation::RotZ(azimuth) * KDL::Rotation::RotY(kPi - tilt), p);
}

TEST(JointSpace, ForwardKinematicsOfTheStartGivesTheSimulatedRobotsPoses) {
  StateValidator validator = puncturingValidator();
  DualPose tools;
  ASSERT_TRUE(validator.toolPoses(kStart, tools));
  EXPECT_LT((tools.first.p - KDL::Vector(-0.0503, 0.0497, 0.2606)).Norm(), 1e-3);
  EXPECT_LT((tools.second.p - KDL::Vector(0.2000, -0.2501, 0.3002)).Norm(), 1e-3);
  EXPECT_TRUE(validator.checkJoints(kStart).valid()) << describe(validator.checkJoints(kStart, true));
  // The same tool poses solved back from the start's joints are the start's joints (same branch).
  JointState back(kStart.size());
  std::size_t robot = 0;
  ASSERT_EQ(validator.inverseNear(tools, kStart, back, robot), Reachability::Reachable);
  for (std::size_t j = 0; j < kStart.size(); ++j) EXPECT_NEAR(back[j], kStart[j], 1e-6) << j;
}

TEST(JointSpace, AtTheGimbalLockTheIsurKeepsTheSeedsYaw) {
  IsurPuncturingModel model;
  std::mt19937 rng(5);  // 20 seeded cases
  std::uniform_real_distribution<double> yaw(-1.2, 1.2), roll(-2.5, 2.5), spin(-kPi, kPi);
  for (int i = 0; i < 20; ++i) {
    const std::array<double, 8> seed{0.01, 0.01, 0.2, 0.0, yaw(rng), 0.8, 0.6, roll(rng)};
    // The needle (tool x) exactly vertical, turned about the vertical by an arbitrary angle.
    const KDL::Frame target(KDL::Rotation::RotZ(spin(rng)) * KDL::Rotation::RotY(kPi / 2), KDL::Vector(0.0, 0.0, -0.8));
    std::array<double, 8> q{};
    ASSERT_EQ(model.inverseNear(std::span(&target, 1), seed, q), Reachability::Reachable);
    EXPECT_NEAR(q[3] + q[4], seed[3] + seed[4], 1e-9) << "case " << i;  // the yaw stays
    std::array<KDL::Frame, 6> links{};
    ASSERT_TRUE(model.linkFramesAt(q, links));
    EXPECT_TRUE(KDL::Equal(links[5], target, 1e-6)) << "case " << i;  // the roll took the rest
  }
}

TEST(JointSpace, APlannedPathIsFollowedByTheContinuityKeepingIkWithinTheVelocityLimits) {
  StateValidator validator = puncturingValidator();
  const PlannerOptions o = options();
  MotionPlanner planner(validator, o);
  DualPose start;
  ASSERT_TRUE(validator.toolPoses(kStart, start));
  // The needle swung about the world y axis from leaning 10° toward +x to 13° toward -x, 12 cm
  // lower, the probe holding: the I-SUR's wrist passes its gimbal lock (needle vertical).
  const DualPose goal{KDL::Frame(KDL::Rotation::RotY(0.4) * start.first.M, start.first.p - KDL::Vector(0, 0, 0.12)),
                      start.second};
  const PlanResult result = planner.planPath(kStart, goal);
  expectFollowable(validator, o, result, kStart);
  // The probe held still: its joints never moved.
  for (const JointState& q : result.joint_waypoints)
    for (std::size_t j = 8; j < 14; ++j) EXPECT_NEAR(q[j], kStart[j], 1e-6);
}

TEST(JointSpace, AVerticalNeedleGoalIsReachedWithoutTurningTheArmAboutTheVertical) {
  StateValidator validator = puncturingValidator();
  const PlannerOptions o = options();
  MotionPlanner planner(validator, o);
  DualPose start;
  ASSERT_TRUE(validator.toolPoses(kStart, start));
  const DualPose goal{needle(KDL::Vector(-0.004, -0.004, 0.12), 0.0, 0.0), start.second};
  const PlanResult result = planner.planPath(kStart, goal);
  expectFollowable(validator, o, result, kStart);
  const JointState& end = result.joint_waypoints.back();
  EXPECT_NEAR(end[3] + end[4], kStart[3] + kStart[4], 1e-6);  // the yaw of the start
  // And back from the vertical (the start at the lock) to the tilted change pose.
  const PlanResult back = planner.planPath(end, start);
  expectFollowable(validator, o, back, end);
}

/// The registration sweep's two_needles seed 1 before the second needle's approach: the robots'
/// joints (m, rad), the needle's approach 8.6 cm above its entry and its insertion (the probe
/// holding on the skin).
const JointState kSecondNeedleStart{0.0022418675641719399, 0.0032706053407631774, 0.20446081533657973, 0,
                                    -2.0032456918514996e-09, 0.85000016339744844, 0.55000016339744839,
                                    -2.3783362966895218e-09, 0.42626579944586696, -1.9979455840184659,
                                    -1.724076869225712, 2.9040335284704675, -2.0320886793127442, -1.8303906801875494};
KDL::Frame secondNeedleAt(const KDL::Vector& tip) {
  return KDL::Frame(KDL::Rotation::Quaternion(0.99527511183648287, -0.064069847081349829, -0.018496705081426978,
                                              0.070571795747166349),
                    tip);
}
KDL::Frame secondNeedleProbe() {
  return KDL::Frame(KDL::Rotation::Quaternion(0.85415667357355229, -0.31171128522376651, -0.41051596139694141,
                                              -0.068768430927690694),
                    KDL::Vector(0.086320042510758269, 0.016749001959914484, 0.063956214885181342));
}
DualPose secondNeedleApproach() {
  return {secondNeedleAt(KDL::Vector(0.042378306990500422, 0.055502346440470023, 0.099897490135253536)),
          secondNeedleProbe()};
}
DualPose secondNeedleInserted() {
  return {secondNeedleAt(KDL::Vector(0.038512699729566113, 0.043861565267038174, 0.016506328734012983)),
          secondNeedleProbe()};
}

TEST(JointSpace, TheIsursTwoGoalChoicesReachTheSameToolsOneOnTheStartsWristBranch) {
  // The rule's goal lies on the other pitch branch than the start's: inverseGoal weighs it against
  // the solver's answer on the start's branch and offers the one it did not take as the second.
  StateValidator validator = puncturingValidator();
  const DualPose goal = secondNeedleApproach();
  JointState first(kSecondNeedleStart.size()), second(kSecondNeedleStart.size());
  std::size_t robot = 0;
  ASSERT_EQ(validator.inverseGoal(goal, kSecondNeedleStart, first, robot), Reachability::Reachable);
  EXPECT_EQ(allocationsDuring([&] {
              EXPECT_EQ(validator.inverseGoalAlternative(goal, kSecondNeedleStart, second, robot),
                        Reachability::Reachable);
            }),
            0);
  double difference = 0.0;
  for (std::size_t j = 0; j < 8; ++j) difference = std::max(difference, std::abs(first[j] - second[j]));
  EXPECT_GT(difference, 0.1);  // two configurations, not one solved twice
  for (const JointState* q : {&first, &second}) {
    DualPose tools;
    ASSERT_TRUE(validator.toolPoses(*q, tools));
    EXPECT_TRUE(KDL::Equal(tools.first, goal.first, 1e-9));
    EXPECT_TRUE(KDL::Equal(tools.second, goal.second, 1e-9));
  }
  // Exactly one keeps the pitch q6 + q7 on the start's side of the vertical (±90°).
  const auto side = [](const JointState& q) { return std::abs(q[5] + q[6]) < kPi / 2; };
  EXPECT_NE(side(first), side(second));
  EXPECT_TRUE(side(first) == side(kSecondNeedleStart) || side(second) == side(kSecondNeedleStart));
  // A robot without a second goal (the UR5) keeps inverseGoal's; a goal on the start's branch
  // by the rule has no second.
  for (std::size_t j = 8; j < 14; ++j) EXPECT_NEAR(first[j], second[j], 1e-9);
  DualPose start;
  ASSERT_TRUE(validator.toolPoses(kStart, start));
  EXPECT_EQ(validator.inverseGoalAlternative(start, kStart, second, robot), Reachability::Unreachable);
}

TEST(JointSpace, TheGoalIsChosenSoThatTheStraightMotionAfterItCanBeMade) {
  // A second needle's approach 8.6 cm above its entry, then its insertion (the registration
  // sweep's two_needles seed 1): the I-SUR's preferred goal keeps its wrist on the start's pitch
  // branch with the elbow off its redundancy rule; the path into it ends with the roll where the
  // insertion that follows would turn it half a turn. The rule's goal, on the other pitch branch,
  // is the alternative that makes the insertion possible.
  // The kinematic question only: the phantom, registered elsewhere in that setup, is left out
  // (the probe rests where the test scene's phantom is).
  SceneDescription scene = loadScene(std::filesystem::path(COBRA_SOURCE_DIR) / "planning/test/scenes/puncturing.scene");
  for (RobotPlacement& robot : scene.robots)
    if (robot.name == "isur") robot.setToolFrame(0, KDL::Frame(KDL::Rotation::RPY(0.0, kPi / 2, 0.0)));
  std::erase_if(scene.objects, [](const ObjectDescription& object) { return object.name == "phantom"; });
  for (auto* pairs : {&scene.allowed_contacts, &scene.primitive_contacts})
    std::erase_if(*pairs, [](const auto& pair) { return pair.first == "phantom" || pair.second == "phantom"; });
  RobotModels models = makeRobotModels(scene);
  StateValidator validator(std::move(scene), std::move(models));
  PlannerOptions o = options();
  o.max_validity_checks = 600000;
  MotionPlanner planner(validator, o);
  const JointState& start = kSecondNeedleStart;
  const DualPose approach = secondNeedleApproach(), inserted = secondNeedleInserted();
  // Without the motion after it the planner takes its preferred goal, from which the insertion
  // cannot be made (the test would pass without the alternative otherwise).
  const PlanResult alone = planner.planPath(start, approach);
  ASSERT_TRUE(alone.solved()) << toString(alone.status) << ": " << alone.message;
  const PlanResult refused = planner.checkFollowOn(alone.joint_waypoints.back(), alone.waypoints.back(), inserted);
  EXPECT_EQ(refused.status, PlanStatus::InvalidGoal);
  EXPECT_CONTAINS(refused.message, "the straight motion after the goal, to (0.0385, 0.0439, 0.0165) m");
  EXPECT_CONTAINS(refused.message, "IK discontinuity");
  // With the motion after it named, the goal from which it can be made.
  const PlanResult planned = planner.planPath(start, approach, inserted);
  ASSERT_TRUE(planned.solved()) << planned.message;
  expectFollowable(validator, o, planned, start);
  const PlanResult insertion = planner.checkFollowOn(planned.joint_waypoints.back(), planned.waypoints.back(), inserted);
  EXPECT_TRUE(insertion.solved()) << insertion.message;
  // The same goal checked before a search gives the same verdict.
  EXPECT_TRUE(planner.checkGoal(start, approach, inserted).solved());
}

TEST(JointSpace, ASameSeedGivesTheSamePathUnderAWorkLimit) {
  StateValidator validator = puncturingValidator();
  MotionPlanner planner(validator, options());
  DualPose start;
  ASSERT_TRUE(validator.toolPoses(kStart, start));
  const DualPose goal{start.first, KDL::Frame(KDL::Rotation::RotX(kPi), KDL::Vector(0.15, -0.1, 0.25))};
  const PlanResult a = planner.planPath(kStart, goal);
  const PlanResult b = planner.planPath(kStart, goal);
  ASSERT_TRUE(a.solved()) << a.message;
  ASSERT_EQ(a.joint_waypoints.size(), b.joint_waypoints.size());
  for (std::size_t k = 0; k < a.joint_waypoints.size(); ++k) EXPECT_EQ(a.joint_waypoints[k], b.joint_waypoints[k]);
  EXPECT_EQ(a.validity_checks, b.validity_checks);
}

TEST(JointSpace, BadGoalsAreRefusedNamingTheToolAndWhyBeforeAnySearch) {
  StateValidator validator = puncturingValidator();
  MotionPlanner planner(validator, options());
  DualPose start;
  ASSERT_TRUE(validator.toolPoses(kStart, start));
  // The needle 0.25 m to the side at table height: beyond the delta's reach.
  PlanResult result = planner.planPath(kStart, {needle(KDL::Vector(0.25, -0.25, 0.01), 0.1, 0.0), start.second});
  EXPECT_EQ(result.status, PlanStatus::InvalidGoal);
  EXPECT_EQ(result.validity_checks, 0u);
  EXPECT_CONTAINS(result.message, "needle goal (0.2500, -0.2500, 0.0100) m is unreachable: robot 'isur' has no inverse "
                                  "kinematics solution for it within its joint limits");
  // The probe inside the phantom: reachable, but not a valid state.
  result = planner.planPath(kStart, {start.first, KDL::Frame(KDL::Rotation::RotX(kPi), KDL::Vector(0.0, 0.0, 0.05))});
  EXPECT_EQ(result.status, PlanStatus::InvalidGoal);
  EXPECT_CONTAINS(result.message, "goal state is not valid: too close:");
  // Start joints of the wrong count, and outside the limits.
  result = planner.planPath(JointState(13, 0.0), start);
  EXPECT_EQ(result.status, PlanStatus::InvalidInput);
  EXPECT_CONTAINS(result.message, "start joints: 14 values expected (isur 8, ur5 6), got 13");
  JointState outside = kStart;
  outside[4] = 2.0;  // the micro yaw's limit is 1.571 rad
  result = planner.planPath(outside, start);
  EXPECT_EQ(result.status, PlanStatus::InvalidStart);
  EXPECT_CONTAINS(result.message, "start joints of robot 'isur' are outside its joint limits");
}

// A moving robot off its IK's redundancy rule, as the continuity-keeping controller leaves the
// I-SUR after a straight motion near its wrist lock (~0.04 rad in the elbow): the path is planned
// from where the joints are, and its verification walks it from there with the same IK.
TEST(JointSpace, AStartOffTheRedundancyRuleIsPlannedFromWhereTheJointsAre) {
  StateValidator validator = puncturingValidator();
  MotionPlanner planner(validator, options());
  DualPose start;
  JointState elbow = kStart;  // the elbow q6 - q7 at 0.38 rad, the rule's is 0.3: the same pitch
  elbow[5] += 0.04;
  elbow[6] -= 0.04;
  ASSERT_TRUE(validator.toolPoses(elbow, start));
  const PlanResult result = planner.planPath(elbow, {needle(KDL::Vector(-0.06, 0.05, 0.25), 0.17, 0.0), start.second});
  ASSERT_TRUE(result.solved()) << result.message;
  ASSERT_FALSE(result.joint_waypoints.empty());
  for (std::size_t j = 0; j < elbow.size(); ++j) EXPECT_DOUBLE_EQ(result.joint_waypoints.front()[j], elbow[j]) << j;
  // Half a radian off: not where Cartesian control leaves the robot; refused before any search.
  JointState far = kStart;
  far[5] += 0.5;
  far[6] -= 0.5;
  DualPose far_poses;
  ASSERT_TRUE(validator.toolPoses(far, far_poses));
  const PlanResult refused = planner.planPath(far, {needle(KDL::Vector(-0.06, 0.05, 0.25), 0.17, 0.0), far_poses.second});
  EXPECT_EQ(refused.status, PlanStatus::InvalidStart);
  EXPECT_EQ(refused.validity_checks, 0u);
  EXPECT_CONTAINS(refused.message, "start joints of robot 'isur' (joint 6) are further from where its inverse "
                                   "kinematics resolves its redundancy for the start pose than the joint moves in "
                                   "0.25 s: the first Cartesian command of any path would jump them");
}

TEST(JointSpace, CheckGoalGivesThePlannersOwnVerdictWithoutSearching) {
  StateValidator validator = puncturingValidator();
  MotionPlanner planner(validator, options());
  DualPose start;
  ASSERT_TRUE(validator.toolPoses(kStart, start));
  const std::vector<DualPose> goals{
      {start.first, KDL::Frame(KDL::Rotation::RotX(kPi), KDL::Vector(0.15, -0.1, 0.25))},   // accepted
      {needle(KDL::Vector(0.25, -0.25, 0.01), 0.1, 0.0), start.second},                       // unreachable
      {start.first, KDL::Frame(KDL::Rotation::RotX(kPi), KDL::Vector(0.0, 0.0, 0.05))},      // probe in the phantom
      {needle(KDL::Vector(0.0, 0.0, 0.9), 0.0, 0.0), start.second}};                          // outside the bounds
  for (std::size_t k = 0; k < goals.size(); ++k) {
    const PlanResult verdict = planner.checkGoal(kStart, goals[k]);
    EXPECT_EQ(verdict.validity_checks, 0u) << k;  // no search
    const PlanResult planned = planner.planPath(kStart, goals[k]);
    if (k == 0) {
      EXPECT_EQ(verdict.status, PlanStatus::Solved) << verdict.message;
      EXPECT_EQ(verdict.message, "accepted: the planner would search for a path");
      EXPECT_TRUE(planned.solved()) << planned.message;
    } else {
      EXPECT_NE(verdict.status, PlanStatus::Solved) << k;
      EXPECT_EQ(verdict.status, planned.status) << k;
      EXPECT_EQ(verdict.message, planned.message) << k;
    }
  }
  // Refused start joints too, with planPath's message.
  EXPECT_CONTAINS(planner.checkGoal(JointState(13, 0.0), start).message, "start joints: 14 values expected");
}

TEST(JointSpace, AllowedContactsAreMeasuredApartFromTheClearance) {
  StateValidator validator = puncturingValidator();
  DualPose start;
  ASSERT_TRUE(validator.toolPoses(kStart, start));
  // The probe pressed 2 mm into the phantom's top (z = 0.1 m): an allowed contact.
  const DualPose pressed{start.first, KDL::Frame(KDL::Rotation::RotX(kPi), KDL::Vector(0.1, -0.05, 0.098))};
  JointState q(kStart.size());
  std::size_t robot = 0;
  ASSERT_EQ(validator.inverseNear(pressed, kStart, q, robot), Reachability::Reachable);
  const StateValidator::Distances d = validator.distancesAt(q);
  EXPECT_EQ(d.allowed_contact, 0.0);
  EXPECT_GT(d.clearance, validator.scene().min_collision_distance);
  EXPECT_TRUE(validator.checkJoints(q).valid());
  // Lifted 3 cm: the allowed contact's distance is the gap.
  const DualPose lifted{start.first, KDL::Frame(KDL::Rotation::RotX(kPi), KDL::Vector(0.1, -0.05, 0.13))};
  JointState up(kStart.size());
  ASSERT_EQ(validator.inverseNear(lifted, q, up, robot), Reachability::Reachable);
  EXPECT_NEAR(validator.distancesAt(up).allowed_contact, 0.03, 1e-6);
  // The needle's own contact (a primitive contact of the scene) is measured apart as well.
  EXPECT_NEAR(validator.distancesAt(up).primitive_contact, start.first.p.z() - 0.1, 2e-3);
}

TEST(JointSpace, APrimitiveContactIsMeasuredApartButPlannedStatesKeepTheirClearanceFromIt) {
  StateValidator validator = puncturingValidator();
  ASSERT_EQ(validator.scene().primitive_contacts.size(), 1u);  // puncturing.scene: needle/phantom
  DualPose start;
  ASSERT_TRUE(validator.toolPoses(kStart, start));
  // The needle's tip 1 cm into the phantom's top (z = 0.1 m), as after the skin's puncture.
  DualPose inserted = start;
  inserted.first.p.z(0.09);
  JointState q(kStart.size());
  std::size_t robot = 0;
  ASSERT_EQ(validator.inverseNear(inserted, kStart, q, robot), Reachability::Reachable);
  const StateValidator::Distances d = validator.distancesAt(q);
  EXPECT_EQ(d.primitive_contact, 0.0);
  EXPECT_GT(d.clearance, validator.scene().min_collision_distance);  // nothing else is near
  EXPECT_EQ(d.clearance, validator.distancesAt(inserted).clearance);  // the same from the tool poses
  // For the planner the needle in the phantom is still too close: plans never take it there.
  const ValidityResult verdict = validator.checkJoints(q, true);
  EXPECT_EQ(verdict.validity, Validity::TooClose);
  EXPECT_EQ(verdict.first_object, "needle");
  EXPECT_EQ(verdict.second_object, "phantom");
}

}  // namespace
}  // namespace cobra::planning
