// The run following a verified procedure (cobra/task/verified_paths.hpp) on the puncturing scene
// with the real robot models: the probe's planned step walked once (PlannerStepVerifier), then
// the run's queries against it: the walk's path from the walk's start, another goal alternative
// refused, the tolerance boundaries of the start and the goal, the other robot in the way, and
// leaving the verified procedure, which fails every later query until it is verified again.
#include "cobra/task/verified_paths.hpp"

#include <gtest/gtest.h>

#include <array>
#include <string>
#include <vector>

#include "cobra/test_support/test_support.hpp"
#include "walk_scene.hpp"

namespace cobra::task {
namespace {

using planning::DualPose;
using planning::JointState;
using planning::PlanResult;
using planning::PlanStatus;

constexpr std::size_t kProbe = 1;  // arm and scene robot of the UR5

/// The probe's approach walked from kStart: two goal alternatives, the first (inside the phantom)
/// refused, the second taken.
struct Walked {
  planning::StateValidator validator = test::walkValidator();
  planning::PlannerOptions options = test::walkOptions();
  planning::MotionPlanner needle{validator, options}, probe{validator, options};
  DualPose start;
  DualPose goal;
  std::vector<CheckedPath> paths;

  Walked() {
    if (!validator.toolPoses(test::kStart, start)) throw std::runtime_error("kStart has no tool poses");
    goal = {start.first, test::probeAt({0.15, -0.1, 0.25})};
    PlannerStepVerifier verifier({&needle, &probe}, validator, test::kStart);
    std::vector<GoalCandidate> candidates(2);
    candidates[0].goal = {start.first, test::probeAt({0.0, 0.0, 0.05})};  // in the phantom
    candidates[1].goal = {goal.first, goal.second};
    for (GoalCandidate& c : candidates) c.then = c.goal;
    const StepOutcome outcome = verifier.planned({"root.MoveToSkin.Approach", kProbe, true, 0}, candidates);
    if (!outcome.ok || outcome.chosen != 1) throw std::runtime_error("the walk did not take the second: " + outcome.why);
    paths = verifier.paths();
  }

  /// A follower of the probe's walked path.
  std::unique_ptr<VerifiedPaths> follower() {
    auto f = std::make_unique<VerifiedPaths>(validator, options, kProbe, kProbe);
    f->assign(paths, {"task state 'root.MoveToSkin.Approach', needle n1 (1 of 2)"});
    return f;
  }

  /// The tool poses of `q`.
  DualPose poses(const JointState& q) {
    DualPose p;
    if (!validator.toolPoses(q, p)) throw std::runtime_error("joints without tool poses");
    return p;
  }
};

TEST(VerifiedPaths, TheWalksPathIsFollowedFromWhereTheWalkStartedItThenPlansSearch) {
  Walked w;
  ASSERT_EQ(w.paths.size(), 1u);
  EXPECT_EQ(w.paths[0].alternative, 1u);
  auto f = w.follower();
  PlanResult r;
  ASSERT_TRUE(f->follow(test::kStart, w.start, w.goal, 1, r));
  ASSERT_TRUE(r.solved()) << r.message;
  EXPECT_CONTAINS(r.message, "the path verified with the procedure (");
  ASSERT_EQ(r.joint_waypoints.size(), w.paths[0].result.joint_waypoints.size());
  for (std::size_t k = 0; k < r.joint_waypoints.size(); ++k)
    for (std::size_t j = 0; j < test::kStart.size(); ++j)
      EXPECT_NEAR(r.joint_waypoints[k][j], w.paths[0].result.joint_waypoints[k][j], 1e-9) << k << ", " << j;
  EXPECT_EQ(f->remaining(), 0u);
  // Every verified path followed: the next query is the planner's own search.
  EXPECT_FALSE(f->follow(w.paths[0].result.joint_waypoints.back(), w.goal, w.start, 0, r));
}

TEST(VerifiedPaths, TheStepJustFollowedAskedAgainFromElsewhereIsSearchedToItsVerifiedGoal) {
  Walked w;
  auto f = w.follower();
  PlanResult r;
  ASSERT_TRUE(f->follow(test::kStart, w.start, w.goal, 1, r));
  ASSERT_TRUE(r.solved()) << r.message;
  // A retry after a reaction: the probe held 3 cm aside of its start, far from any verified start.
  JointState held(test::kStart.size());
  std::size_t robot = 0;
  ASSERT_EQ(w.validator.inverseNear({w.start.first, KDL::Frame(w.start.second.M, w.start.second.p + KDL::Vector(0.03, 0, 0))},
                                    test::kStart, held, robot),
            planning::Reachability::Reachable);
  ASSERT_TRUE(f->follow(held, w.poses(held), w.goal, 1, r));
  ASSERT_TRUE(r.solved()) << r.message;
  EXPECT_CONTAINS(r.message, "the verified goal of task state 'root.MoveToSkin.Approach', needle n1 (1 of 2) again "
                             "from where the robot is: ");
  EXPECT_EQ(r.joint_waypoints.front(), held);
  EXPECT_TRUE(f->left().empty());
}

TEST(VerifiedPaths, AnotherGoalAlternativeIsRefusedAndTheWalksOneIsThenFollowed) {
  Walked w;
  auto f = w.follower();
  PlanResult r;
  ASSERT_TRUE(f->follow(test::kStart, w.start, {w.start.first, test::probeAt({0.0, 0.0, 0.05})}, 0, r));
  EXPECT_EQ(r.status, PlanStatus::NoSolution);
  EXPECT_EQ(r.message, "not the goal alternative the procedure's verification took from here (it took alternative 2)");
  EXPECT_EQ(f->remaining(), 1u);
  EXPECT_TRUE(f->left().empty());
  ASSERT_TRUE(f->follow(test::kStart, w.start, w.goal, 1, r));
  EXPECT_TRUE(r.solved()) << r.message;
}

TEST(VerifiedPaths, AGoalBeyondItsToleranceLeavesTheProcedureNamingTheStep) {
  Walked w;
  const FollowTolerances bound;
  PlanResult r;
  DualPose near = w.goal;
  near.second.p.x(near.second.p.x() + 0.9 * bound.goal_position);
  ASSERT_TRUE(w.follower()->follow(test::kStart, w.start, near, 1, r));
  EXPECT_TRUE(r.solved()) << r.message;
  // The end of the followed path is the goal asked.
  EXPECT_TRUE(KDL::Equal(r.waypoints.back().second, near.second, 1e-12));

  DualPose moved = w.goal;
  moved.second.p.x(moved.second.p.x() + 2.0 * bound.goal_position);
  auto f = w.follower();
  ASSERT_TRUE(f->follow(test::kStart, w.start, moved, 1, r));
  EXPECT_EQ(r.status, PlanStatus::NoSolution);
  EXPECT_EQ(r.message, "left the verified procedure at planned step 1 of 1 (task state 'root.MoveToSkin.Approach', "
                       "needle n1 (1 of 2)): the goal moved since the verification (registration changed?) by 0.004 m "
                       "and 0 rad; verify the procedure again");
  DualPose turned = w.goal;
  turned.second.M = turned.second.M * KDL::Rotation::RotZ(2.0 * bound.goal_angle);
  ASSERT_TRUE(w.follower()->follow(test::kStart, w.start, turned, 1, r));
  EXPECT_CONTAINS(r.message, "the goal moved since the verification (registration changed?) by 0 m and 0.02 rad");
}

TEST(VerifiedPaths, LeavingTheProcedureFailsEveryLaterPlanUntilItIsVerifiedAgain) {
  Walked w;
  auto f = w.follower();
  // The probe 3 cm to the side of where the walk started the step (beyond 0.02 m).
  JointState away(test::kStart.size());
  std::size_t robot = 0;
  ASSERT_EQ(w.validator.inverseNear({w.start.first, KDL::Frame(w.start.second.M, w.start.second.p + KDL::Vector(0.03, 0, 0))},
                                    test::kStart, away, robot),
            planning::Reachability::Reachable);
  PlanResult r;
  ASSERT_TRUE(f->follow(away, w.poses(away), w.goal, 1, r));
  EXPECT_EQ(r.status, PlanStatus::NoSolution);
  const std::string left = "left the verified procedure at planned step 1 of 1 (task state 'root.MoveToSkin.Approach', "
                           "needle n1 (1 of 2)): the tool is 0.03 m and 0 rad from where the verification started "
                           "this step (at most 0.02 m and 0.02 rad); verify the procedure again";
  EXPECT_EQ(r.message, left);
  EXPECT_EQ(f->left(), left);
  // The walk's own query now fails too, and so does any other: no search once left.
  ASSERT_TRUE(f->follow(test::kStart, w.start, w.goal, 1, r));
  EXPECT_EQ(r.message, left);
  ASSERT_TRUE(f->follow(test::kStart, w.start, w.start, 0, r));
  EXPECT_EQ(r.message, left);
  // Verified again: followed.
  f->assign(w.paths, {"again"});
  ASSERT_TRUE(f->follow(test::kStart, w.start, w.goal, 1, r));
  EXPECT_TRUE(r.solved()) << r.message;
  // Turned beyond 0.02 rad about its axis: left too.
  JointState turned = test::kStart;
  turned[13] += 0.03;  // the UR5's last joint: the probe's spin about its axis
  ASSERT_TRUE(w.follower()->follow(turned, w.poses(turned), w.goal, 1, r));
  EXPECT_CONTAINS(r.message, "the tool is 0 m and 0.03 rad from where the verification started this step");
}

TEST(VerifiedPaths, AStartWithinTheToleranceJoinsTheVerifiedPathFromWhereTheRobotIs) {
  Walked w;
  JointState near = test::kStart;
  near[13] += 0.5 * FollowTolerances{}.start_angle;  // the probe's spin about its axis
  PlanResult r;
  ASSERT_TRUE(w.follower()->follow(near, w.poses(near), w.goal, 1, r));
  ASSERT_TRUE(r.solved()) << r.message;
  EXPECT_EQ(r.joint_waypoints.front(), near);
  EXPECT_TRUE(KDL::Equal(r.waypoints.front().second, w.poses(near).second, 1e-12));
  EXPECT_CONTAINS(r.message, "the path verified with the procedure (");
}

TEST(VerifiedPaths, TheOtherRobotInTheWayLeavesTheProcedureWithWhyNotEvenASearchHelps) {
  Walked w;
  // The needle's walked step: 5 cm along -x, 10 cm along -y, 6 cm lower.
  const DualPose needle_goal{KDL::Frame(w.start.first.M, w.start.first.p + KDL::Vector(-0.05, -0.1, -0.06)), w.start.second};
  PlannerStepVerifier verifier({&w.needle, &w.probe}, w.validator, test::kStart);
  GoalCandidate c;
  c.goal = {needle_goal.first, needle_goal.second};
  c.then = c.goal;
  const StepOutcome outcome = verifier.planned({"root.InsertingNeedles.MoveToSkin.Approach", 0, true, 0}, std::vector{c});
  ASSERT_TRUE(outcome.ok) << outcome.why;
  VerifiedPaths f(w.validator, w.options, 0, 0);
  f.assign(verifier.paths(), {"task state 'root.InsertingNeedles.MoveToSkin.Approach', needle n1 (1 of 2)"});
  // The probe pressed where the needle's goal is: the verified path's last waypoint is too close
  // to it, and a search to that goal has no valid goal state.
  JointState blocking = test::kStart;
  std::size_t robot = 0;
  ASSERT_EQ(w.validator.inverseNear({w.start.first, test::probeAt(needle_goal.first.p - KDL::Vector(0, 0, 0.02))},
                                    test::kStart, blocking, robot),
            planning::Reachability::Reachable);
  const DualPose at = w.poses(blocking);
  ASSERT_TRUE(w.validator.checkJoints(blocking).valid()) << planning::describe(w.validator.checkJoints(blocking));
  PlanResult r;
  ASSERT_TRUE(f.follow(blocking, at, {needle_goal.first, at.second}, 0, r));
  EXPECT_EQ(r.status, PlanStatus::NoSolution);
  EXPECT_CONTAINS(r.message, "left the verified procedure at planned step 1 of 1 (task state "
                             "'root.InsertingNeedles.MoveToSkin.Approach', needle n1 (1 of 2)): waypoint ");
  EXPECT_CONTAINS(r.message, " of its verified path is not valid with the other robot where it is: too close");
  EXPECT_CONTAINS(r.message, "; a search from where it is: invalid goal: ");
}

}  // namespace
}  // namespace cobra::task
