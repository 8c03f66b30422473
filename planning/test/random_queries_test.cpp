// Seeded random feasible queries (planning/test/random_queries.hpp's walkedQueries: the first of
// the queries bench/planning_bench.cpp's RandomQueries* draw, goals the robots' controllers reach
// from the start, with the deployments' planner settings) on the puncturing and the suturing
// scene: the planner's goal check accepts every goal the controllers reached, the success rate,
// and every returned path followed as the
// robots' controllers follow it, checked independently of the planner's own verifier: the
// Cartesian interpolation stepped at the trajectory generator's speed through
// kinematics::ContinuousIk / ContinuousIsurSuturingIk (the solvers and the continuity rule the
// simulated robots use, built here from cobra::kinematics, not the planner's robot models), every
// step accepted (no branch change, every joint within its velocity limit over the step), and every
// tracked state collision-free (StateValidator::checkJoints: forward kinematics and FCL).

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "controllers.hpp"
#include "joint_path_checks.hpp"
#include "random_queries.hpp"

namespace cobra::planning {
namespace {

using test::Query;
using test::RandomScene;

using test::Controllers;
using test::kControlPeriod;

/// The controllers follow the solved path from the query's start at the generator's speeds: every
/// step accepted, and every tracked state collision-free with at least half the scene's clearance
/// (the planner keeps the whole clearance at its verification's points, verify_points_per_segment
/// per segment; between them a state may come a little closer).
void expectControllersFollow(StateValidator& validator, const PlannerOptions& o, const PlanResult& result,
                             const JointState& start, std::size_t query) {
  Controllers controllers(validator);
  const double clearance = 0.5 * validator.scene().min_collision_distance;
  JointState q = start;
  std::string why;
  for (std::size_t k = 0; k + 1 < result.waypoints.size(); ++k) {
    const DualPose& a = result.waypoints[k];
    const DualPose& b = result.waypoints[k + 1];
    const auto steps = static_cast<std::size_t>(std::ceil(
        test::generatorDuration(o.max_linear_velocity, o.max_angular_velocity, o.blend_time, a, b) / kControlPeriod));
    for (std::size_t i = 1; i <= steps; ++i) {
      const double s = static_cast<double>(i) / static_cast<double>(steps);
      ASSERT_TRUE(controllers.step({interpolate(a.first, b.first, s), interpolate(a.second, b.second, s)}, q, why))
          << "query " << query << ", segment " << k << " at " << s << ": " << why;
      const ValidityResult state = validator.checkJoints(q, true);
      ASSERT_TRUE(state.valid() || (state.validity == Validity::TooClose && state.distance >= clearance))
          << "query " << query << ", segment " << k << " at " << s << ": " << describe(state);
    }
  }
}

/// How many of the first `count` walked queries of `setup` the planner's goal check
/// (MotionPlanner::checkGoal) accepts; each refusal is printed.
std::size_t acceptedGoals(const RandomScene& setup, std::size_t count) {
  SceneDescription scene = setup.scene();
  RobotModels models = makeRobotModels(scene);
  StateValidator validator(std::move(scene), std::move(models));
  std::map<std::string, int> dropped;
  const std::vector<Query> queries = test::walkedQueries(validator, setup, count, dropped);
  MotionPlanner planner(validator, setup.options);
  std::size_t accepted = 0;
  for (std::size_t i = 0; i < queries.size(); ++i) {
    const PlanResult result = planner.checkGoal(queries[i].start, queries[i].goal);
    if (result.solved()) ++accepted;
    else std::printf("query %zu refused: %s\n", i, result.message.c_str());
  }
  return accepted;
}

/// Plans the first `count` queries of `setup` (the bench's, its work limit and speeds); every
/// solved path is cross-checked. Returns the number solved.
std::size_t planAndCrossCheck(const RandomScene& setup, std::size_t count) {
  SceneDescription scene = setup.scene();
  RobotModels models = makeRobotModels(scene);
  StateValidator validator(std::move(scene), std::move(models));
  std::map<std::string, int> dropped;
  const std::vector<Query> queries = test::walkedQueries(validator, setup, count, dropped);
  std::size_t solved = 0;
  for (std::size_t i = 0; i < queries.size(); ++i) {
    PlannerOptions o = setup.options;
    o.seed = static_cast<std::uint32_t>(i + 1);
    o.max_linear_velocity = queries[i].max_linear_velocity;
    o.max_angular_velocity = queries[i].max_angular_velocity;
    MotionPlanner planner(validator, o);
    const PlanResult result = planner.planPath(queries[i].start, queries[i].goal);
    if (!result.solved()) {
      std::printf("query %zu: %s\n", i, result.message.c_str());
      continue;
    }
    ++solved;
    EXPECT_TRUE(KDL::Equal(result.waypoints.back().first, queries[i].goal.first, 1e-9)) << "query " << i;
    EXPECT_TRUE(KDL::Equal(result.waypoints.back().second, queries[i].goal.second, 1e-9)) << "query " << i;
    expectControllersFollow(validator, o, result, queries[i].start, i);
  }
  return solved;
}

// The goal check agrees with the controllers: the goals they reached from the start (walked
// along valid, branch-keeping states, and settled there) are accepted; the check used to refuse
// goals whose I-SUR elbow the delta's stroke or a pitch joint's limit moved off the redundancy
// rule, and (suturing query 29) one where the rule is reached only on the other wrist
// representation, the base turntable turned 2.3 rad and the arms in contact, while the
// controllers reach the goal on the start's representation with the elbow moved. Measured: all
// 100 puncturing goals, all 40 suturing goals.
TEST(RandomQueries, ThePlannerAcceptsEveryGoalTheControllersReach) {
  EXPECT_EQ(acceptedGoals(test::puncturingRandom("RRTConnect"), 100), 100u);
  EXPECT_EQ(acceptedGoals(test::suturingRandom("RRTConnect"), 40), 40u);
}

// The target is 99 % (the bench's 1,000): here the bench's first 120 walked queries, every one
// solved (measured). They hold goals where the delta's stroke moves the I-SUR's elbow off its
// rule and the goal's projection on the rule lies outside the planner's tool bounds (queries 71
// and 116), which failed before the search headed for a valid configuration on the rule next to
// the goal (MotionPlanner::searchGoal).
TEST(RandomQueries, PuncturingQueriesAreSolvedAndTheControllersFollowEveryPath) {
  EXPECT_EQ(planAndCrossCheck(test::puncturingRandom("RRTConnect"), 120), 120u);
}

// The suturing scene's first 70 walked queries: measured, all 70 solved, every path followed by
// the two-armed robot's controller. Queries 11, 29, 54, 62 and 63 failed before (their goals off
// the Endo Stitch arm's rule: the goal IK flipped the wrist, or the search's goal was not valid).
TEST(RandomQueries, SuturingQueriesAreSolvedAndTheTwoArmedRobotsControllerFollowsEveryPath) {
  EXPECT_EQ(planAndCrossCheck(test::suturingRandom("RRTConnect"), 70), 70u);
}

}  // namespace
}  // namespace cobra::planning
