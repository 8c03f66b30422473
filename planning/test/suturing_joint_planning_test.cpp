// The joint space of the two-armed I-SUR (IsurSuturingModel) and the joint-space planner on the
// suturing scene: coordinates and joints agree, the split IK keeps the seed's branch, the 6-DOF
// arm's coordinate bounds keep its elbow and wrist branch, a goal only the other wrist reaches is
// refused before any search; seeded random queries are solved and every path is re-walked
// densely with the continuity-keeping IK (no branch change, joint steps within the velocity
// limits, collision-free).

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <filesystem>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "cobra/kinematics/isur.hpp"
#include "cobra/planning/motion_planner.hpp"
#include "cobra/planning/robot_adapters.hpp"
#include "cobra/test_support/test_support.hpp"
#include "joint_path_checks.hpp"

namespace cobra::planning {
namespace {

/// SimulatedISURSuturingRobot's default initial joints (m, rad): the Endo Stitch pitched 1.2 rad
/// down, the 6-DOF arm's elbow bent and its wrist away from alignment.
const JointState kStart{0.1, 0.1, 0.1, 0.0, 0.0, 0.75, 0.45, 0.0, 0.0, 0.5, -0.5, 0.0, 0.5, 0.0};

StateValidator suturingValidator() {
  SceneDescription scene = loadScene(std::filesystem::path(COBRA_SOURCE_DIR) / "planning/test/scenes/suturing.scene");
  RobotModels models = makeRobotModels(scene);
  return StateValidator(std::move(scene), std::move(models));
}

PlannerOptions options() {
  PlannerOptions o;
  o.first_bounds = {{-0.8, -0.8, 0.0}, {0.8, 0.8, 1.2}};
  o.second_bounds = {{-0.8, -0.8, 0.0}, {0.8, 0.8, 1.2}};
  o.max_validity_checks = 100000;
  o.max_linear_velocity = 0.04;
  o.max_angular_velocity = 0.15;
  o.tool_names = {"Endo Stitch", "gripper"};
  return o;
}

IsurSuturingModel& isurOf(StateValidator& validator) { return dynamic_cast<IsurSuturingModel&>(validator.model(0)); }

kinematics::IkBranch branchOf(IsurSuturingModel& model, std::span<const double> q) { return model.solver().branch(q); }

/// The branch along a solved path's joint waypoints: the gripper arm's shoulder, elbow and wrist
/// never change; the Endo Stitch's wrist representation (bit 0) changes only between the two
/// waypoints RobotModel::singularCrossing puts around the vertical (pitch within kCrossingMargin
/// of ±90° on both), where the Cartesian path passes through the singular pose itself and the
/// control path's rule allows either side (the re-walk of expectFollowable proves it with the
/// branch-keeping IK).
void expectBranchKept(IsurSuturingModel& model, const PlanResult& result, kinematics::IkBranch start, int query) {
  constexpr std::uint8_t kGripperArm = 0x0E;
  for (std::size_t k = 0; k < result.joint_waypoints.size(); ++k) {
    const JointState& q = result.joint_waypoints[k];
    EXPECT_EQ(branchOf(model, q).bits & kGripperArm, start.bits & kGripperArm)
        << "query " << query << " waypoint " << k;
    if (k == 0) continue;
    const JointState& previous = result.joint_waypoints[k - 1];
    if ((branchOf(model, q).bits & 1u) == (branchOf(model, previous).bits & 1u)) continue;
    for (const JointState* end : {&previous, &q})
      EXPECT_LE(std::abs(std::abs((*end)[5] + (*end)[6]) - std::numbers::pi / 2),
                IsurPuncturingModel::kCrossingMargin + 1e-9)
          << "query " << query << ": the Endo Stitch changes its branch between waypoints " << k - 1 << " and " << k;
  }
}

/// The goal joints the planner derives from the tool poses of `q` (IsurSuturingModel::inverseGoal
/// from the start) are `q` itself: the query's goal is that configuration.
bool goalIsTheConfiguration(IsurSuturingModel& model, const JointState& q) {
  std::vector<KDL::Frame> links(model.linkCount());
  if (!model.linkFramesAt(q, links)) return false;
  const std::array<KDL::Frame, 2> tools{links[model.toolLink(0)], links[model.toolLink(1)]};
  JointState goal(q.size());
  if (model.inverseGoal(tools, kStart, goal) != Reachability::Reachable) return false;
  for (std::size_t j = 0; j < q.size(); ++j)
    if (std::abs(goal[j] - q[j]) > 1e-6) return false;
  return true;
}

TEST(SuturingJointSpace, CoordinatesAndJointsAgreeAndTheToolsAreLinks5And11) {
  IsurSuturingModel model;
  ASSERT_EQ(model.jointCount(), 14u);
  ASSERT_EQ(model.coordinateCount(), 13u);
  std::vector<double> c(13), q(14);
  model.coordinatesOf(kStart, c);
  model.jointsOf(c, kStart, q);
  for (std::size_t j = 0; j < 14; ++j) EXPECT_NEAR(q[j], kStart[j], 1e-12) << j;
  std::vector<KDL::Frame> links(model.linkCount());
  ASSERT_TRUE(model.linkFramesAt(kStart, links));
  KDL::Frame stitch, gripper;
  KDL::JntArray joints(14);
  for (unsigned j = 0; j < 14; ++j) joints(j) = kStart[j];
  ASSERT_EQ(model.solver().forward(joints, stitch, gripper), kinematics::IkStatus::Ok);
  EXPECT_TRUE(KDL::Equal(links[model.toolLink(0)], stitch, 1e-12));
  EXPECT_TRUE(KDL::Equal(links[model.toolLink(1)], gripper, 1e-12));
  // The same tools solved back from the start's joints are the start's joints.
  const std::array<KDL::Frame, 2> tools{stitch, gripper};
  ASSERT_EQ(model.inverseNear(tools, kStart, q), Reachability::Reachable);
  for (std::size_t j = 0; j < 14; ++j) EXPECT_NEAR(q[j], kStart[j], 1e-9) << j;
}

TEST(SuturingJointSpace, TheGripperArmsBoundsKeepItsElbowAndWristBranch) {
  IsurSuturingModel model;
  std::vector<double> lower(13), upper(13);
  model.coordinateBounds(kStart, kStart, lower, upper);
  // Elbow q11 = -0.5 (cos > 0: within ±π/2), wrist q13 = 0.5 (sin > 0: within (0, π)).
  EXPECT_NEAR(lower[7 + 2], -std::numbers::pi / 2 + IsurSuturingModel::kBranchBoundMargin, 1e-12);
  EXPECT_NEAR(upper[7 + 2], std::numbers::pi / 2 - IsurSuturingModel::kBranchBoundMargin, 1e-12);
  EXPECT_NEAR(lower[7 + 4], IsurSuturingModel::kBranchBoundMargin, 1e-12);
  EXPECT_NEAR(upper[7 + 4], 2.967, 1e-12);  // the joint limit before π
  // Every configuration inside the bounds is on the start's elbow and wrist branch.
  std::mt19937 rng(31);  // 500 seeded samples
  std::vector<double> c(13), q(14);
  const kinematics::IkBranch start = branchOf(model, kStart);
  for (int i = 0; i < 500; ++i) {
    for (std::size_t k = 0; k < 13; ++k) c[k] = std::uniform_real_distribution<double>(lower[k], upper[k])(rng);
    model.jointsOf(c, kStart, q);
    const kinematics::IkBranch sampled = branchOf(model, q);
    EXPECT_EQ((sampled.bits >> 2) & 3u, (start.bits >> 2) & 3u) << "sample " << i;  // elbow and wrist bits
  }
}

TEST(SuturingJointSpace, AGoalOnlyTheOtherWristReachesIsRefusedBeforeAnySearch) {
  StateValidator validator = suturingValidator();
  MotionPlanner planner(validator, options());
  // The wrist on the other side (q13 < 0) with q14 = 0.1 rad: on the start's wrist branch the
  // same pose needs q14 = 0.1 + π, outside its ±2.967 rad limits.
  JointState flipped = kStart;
  flipped[12] = -0.5;
  flipped[13] = 0.1;
  DualPose goal;
  ASSERT_TRUE(validator.toolPoses(flipped, goal));
  const PlanResult result = planner.planPath(kStart, goal);
  EXPECT_EQ(result.status, PlanStatus::InvalidGoal) << result.message;
  EXPECT_CONTAINS(result.message, "reachable only on another IK branch than the start's: robot 'isur'");
}

/// A series of queries from kStart: each solved path is re-walked (expectFollowable) and its
/// branch checked (expectBranchKept); counts the solved ones and the worst joint step share.
struct QuerySeries {
  StateValidator& validator;
  const PlannerOptions& options;
  MotionPlanner& planner;
  IsurSuturingModel& model;
  kinematics::IkBranch start_branch;
  int queries = 0, solved = 0;
  double worst_step = 0.0;

  /// Plans query number ++queries (planner seed = that number); the message when not solved.
  std::string run(const DualPose& goal) {
    ++queries;
    planner.setSeed(static_cast<std::uint32_t>(queries));
    const PlanResult result = planner.planPath(kStart, goal);
    if (!result.solved()) return "query " + std::to_string(queries) + ": " + result.message;
    ++solved;
    expectFollowable(validator, options, result, kStart, &worst_step);
    expectBranchKept(model, result, start_branch, queries);
    return {};
  }
};

// Seeded random queries: goals are the tool poses of random configurations near the start on the
// start's branch and redundancy rule that the scene allows. Every solved path is re-walked at 3x
// the verification's density.
TEST(SuturingJointSpace, RandomQueriesArePlannedAndFollowedWithoutABranchChange) {
  StateValidator validator = suturingValidator();
  PlannerOptions o = options();
  MotionPlanner planner(validator, o);
  IsurSuturingModel& model = isurOf(validator);
  ASSERT_TRUE(validator.checkJoints(kStart).valid()) << describe(validator.checkJoints(kStart, true));
  QuerySeries series{validator, o, planner, model, branchOf(model, kStart)};
  std::mt19937 rng(2024);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  constexpr int kQueries = 50;
  while (series.queries < kQueries) {
    JointState goal_joints = kStart;
    for (std::size_t j = 0; j < 3; ++j) goal_joints[j] += 0.05 * unit(rng);  // m
    goal_joints[4] += 1.0 * unit(rng);   // yaw
    const double pitch = kStart[5] + kStart[6] + 0.5 * unit(rng);
    goal_joints[5] = 0.5 * (pitch + 0.3);
    goal_joints[6] = 0.5 * (pitch - 0.3);
    goal_joints[7] += 1.0 * unit(rng);  // roll
    for (std::size_t j = 8; j < 14; ++j) goal_joints[j] += 0.8 * unit(rng);
    DualPose goal;
    if (!validator.checkJoints(goal_joints).valid() || !validator.toolPoses(goal_joints, goal)) continue;
    if (!branchOf(model, goal_joints).compatibleWith(series.start_branch) ||
        !goalIsTheConfiguration(model, goal_joints))
      continue;
    const std::string failure = series.run(goal);
    if (!failure.empty()) ADD_FAILURE() << failure;
  }
  const int solved = series.solved;
  const double worst_step = series.worst_step;
  EXPECT_EQ(solved, kQueries);
  EXPECT_LE(worst_step, 1.05);
  RecordProperty("solved", solved);
  RecordProperty("worst_joint_step_share", std::to_string(worst_step));
}

/// True when the straight joint-space segment a → b has an invalid state among 50 equally spaced.
bool straightSegmentBlocked(StateValidator& validator, const JointState& a, const JointState& b) {
  JointState q(a.size());
  for (int i = 1; i < 50; ++i) {
    for (std::size_t j = 0; j < q.size(); ++j) q[j] = a[j] + (b[j] - a[j]) * i / 50.0;
    if (!validator.checkJoints(q).valid()) return true;
  }
  return false;
}

// 10 seeded random queries whose straight joint-space path is blocked (an arm through the
// phantom, the table or the other arm, or too close to them), goals anywhere in the start's
// branch: the planner goes around, and every solved path is re-walked at 3x the verification's
// density like the others. Under the 100,000-check work limit 8 of these 10 are solved (33 of the
// first 40 of this sequence: 6 find no path within the limit, one path fails its verification), so
// at least 8 must be.
TEST(SuturingJointSpace, QueriesWhoseStraightPathIsBlockedArePlannedAroundTheObstacle) {
  StateValidator validator = suturingValidator();
  PlannerOptions o = options();
  MotionPlanner planner(validator, o);
  IsurSuturingModel& model = isurOf(validator);
  QuerySeries series{validator, o, planner, model, branchOf(model, kStart)};
  std::vector<double> lower(13), upper(13), c(13);
  model.coordinateBounds(kStart, kStart, lower, upper);
  std::mt19937 rng(4711);
  constexpr int kQueries = 10;
  int draws = 0;
  while (series.queries < kQueries && draws < 200000) {
    ++draws;
    for (std::size_t k = 0; k < 13; ++k) c[k] = std::uniform_real_distribution<double>(lower[k], upper[k])(rng);
    JointState goal_joints(14);
    model.jointsOf(c, kStart, goal_joints);
    DualPose goal;
    if (!validator.checkJoints(goal_joints).valid() || !validator.toolPoses(goal_joints, goal)) continue;
    if (!branchOf(model, goal_joints).compatibleWith(series.start_branch) ||
        !goalIsTheConfiguration(model, goal_joints) || !straightSegmentBlocked(validator, kStart, goal_joints))
      continue;
    const std::string failure = series.run(goal);
    if (!failure.empty()) std::printf("%s\n", failure.c_str());  // allowed: some of the queries
  }
  const int queries = series.queries, solved = series.solved;
  const double worst_step = series.worst_step;
  ASSERT_EQ(queries, kQueries);
  EXPECT_GE(solved, 8);
  EXPECT_LE(worst_step, 1.05);
  RecordProperty("solved", solved);
  RecordProperty("worst_joint_step_share", std::to_string(worst_step));
}

}  // namespace
}  // namespace cobra::planning
