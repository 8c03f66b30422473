// planPath (Algorithm 4.1) on the two-robot test scene with a wall between start and goal: paths
// are valid at 100 points per segment (checked with an independent KDL interpolation), seeded
// planning repeats itself, blocked and bad queries come back with the right status.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "cobra/planning/motion_planner.hpp"
#include "cobra/test_support/test_support.hpp"
#include "joint_path_checks.hpp"
#include "planning_fixture.hpp"

namespace cobra::planning {
namespace {

using cobra::test_support::messageOf;
using test::toolsAt;

/// Planning stops at the first solution; only time limits that a test needs to succeed within are
/// scaled for the ~10x slower sanitizer builds (`./do test --asan`).
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
constexpr double kSanitizerSlowdown = 10.0;
#else
constexpr double kSanitizerSlowdown = 1.0;
#endif

/// A wall (x -0.02..0.02 m, y -0.2..0.2 m, z 0..0.7 m) that the gantry column cannot pass over.
const char* const kWall = "object wall environment world box 0.04 0.4 0.7 at 0 0 0.35 0 0 0\n";
/// A closed cage (inside 0.16 m) around (0, 0.35, 0.3) m.
const char* const kCage =
    "object cage_bottom environment world box 0.2 0.2 0.02 at 0 0.35 0.21 0 0 0\n"
    "object cage_top environment world box 0.2 0.2 0.02 at 0 0.35 0.39 0 0 0\n"
    "object cage_left environment world box 0.02 0.2 0.2 at -0.09 0.35 0.3 0 0 0\n"
    "object cage_right environment world box 0.02 0.2 0.2 at 0.09 0.35 0.3 0 0 0\n"
    "object cage_front environment world box 0.2 0.02 0.2 at 0 0.26 0.3 0 0 0\n"
    "object cage_back environment world box 0.2 0.02 0.2 at 0 0.44 0.3 0 0 0\n";

PlannerOptions options(const std::string& planner = "RRTConnect", std::uint32_t seed = 1) {
  PlannerOptions o;
  o.planner = planner;
  o.seed = seed;
  o.time_limit = 2.0 * kSanitizerSlowdown;
  o.first_bounds = {{-0.45, -0.45, 0.2}, {0.45, 0.45, 0.45}};
  o.second_bounds = {{-0.45, -0.1, 0.2}, {0.45, 0.6, 0.5}};
  return o;
}

const DualPose kStart = toolsAt({-0.25, 0, 0.3}, {0, 0.42, 0.3});
const DualPose kGoal{KDL::Frame(KDL::Rotation::RPY(0.3, 0, 0.5), KDL::Vector(0.25, 0, 0.3)),
                     KDL::Frame(KDL::Rotation::RotZ(1.0), KDL::Vector(0.2, 0.42, 0.3))};

/// Bit-for-bit equality: reproducibility means the same numbers, not close ones.
bool sameFrame(const KDL::Frame& a, const KDL::Frame& b) {
  for (int i = 0; i < 3; ++i)
    if (a.p(i) != b.p(i)) return false;
  for (int i = 0; i < 9; ++i)
    if (a.M.data[i] != b.M.data[i]) return false;
  return true;
}

class MotionPlannerTest : public ::testing::Test {
 protected:
  StateValidator validator{test::twoRobotScene(kWall), test::twoRobotModels()};
};

TEST_F(MotionPlannerTest, StraightLineIsBlockedSoThePathGoesAround) {
  // The straight segment crosses the wall: a path must have intermediate waypoints.
  const DualPose middle = toolsAt({0, 0, 0.3}, {0.1, 0.42, 0.3});
  EXPECT_FALSE(validator.isStateValid(middle));
  MotionPlanner planner(validator, options());
  const PlanResult result = planner.planPath(kStart, kGoal);
  ASSERT_TRUE(result.solved()) << result.message;
  EXPECT_GE(result.waypoints.size(), 3u);
  EXPECT_TRUE(sameFrame(result.waypoints.front().first, kStart.first));
  EXPECT_TRUE(sameFrame(result.waypoints.back().second, kGoal.second));
  expectDenselyValid(validator, result);
}

TEST(MotionPlanner, EveryPlannerFindsAValidPathAroundAPillar) {
  // Plain RRT often needs more than 0.5 s around the wide wall (its nearest node to the goal keeps
  // hitting the wall; see bench/planning_bench.cpp): every planner gets a narrower obstacle here.
  StateValidator validator(test::twoRobotScene("object pillar environment world box 0.06 0.1 0.7 at 0 0 0.35 0 0 0\n"),
                           test::twoRobotModels());
  ASSERT_FALSE(validator.isStateValid(toolsAt({0, 0, 0.3}, {0, 0.42, 0.3})));
  for (const char* name : {"RRT", "PRM", "RRTConnect"}) {
    PlannerOptions o = options(name);
    o.time_limit = 6.0 * kSanitizerSlowdown;  // RRT, seed 1: ~0.2 s of CPU here; room for a loaded machine
    MotionPlanner planner(validator, o);
    const PlanResult result = planner.planPath(kStart, kGoal);
    ASSERT_TRUE(result.solved()) << name << ": " << result.message;
    expectDenselyValid(validator, result);
  }
}

TEST_F(MotionPlannerTest, SameSeedGivesTheSamePath) {
  const PlanResult first = MotionPlanner(validator, options("RRTConnect", 42)).planPath(kStart, kGoal);
  const PlanResult again = MotionPlanner(validator, options("RRTConnect", 42)).planPath(kStart, kGoal);
  ASSERT_TRUE(first.solved() && again.solved());
  ASSERT_EQ(first.waypoints.size(), again.waypoints.size());
  for (std::size_t i = 0; i < first.waypoints.size(); ++i) {
    EXPECT_TRUE(sameFrame(first.waypoints[i].first, again.waypoints[i].first)) << i;
    EXPECT_TRUE(sameFrame(first.waypoints[i].second, again.waypoints[i].second)) << i;
  }
}

TEST_F(MotionPlannerTest, SetSeedMakesTheNextQueryThatOfTheNewSeed) {
  MotionPlanner planner(validator, options("RRTConnect", 42));
  planner.setSeed(7);
  EXPECT_EQ(planner.options().seed, 7u);
  const PlanResult reseeded = planner.planPath(kStart, kGoal);
  const PlanResult fresh = MotionPlanner(validator, options("RRTConnect", 7)).planPath(kStart, kGoal);
  ASSERT_TRUE(reseeded.solved() && fresh.solved());
  ASSERT_EQ(reseeded.waypoints.size(), fresh.waypoints.size());
  for (std::size_t i = 0; i < fresh.waypoints.size(); ++i)
    EXPECT_TRUE(sameFrame(reseeded.waypoints[i].first, fresh.waypoints[i].first)) << i;
  EXPECT_THROW(planner.setSeed(0), std::invalid_argument);
}

TEST(MotionPlanner, GoalInsideAClosedCageFailsWithinTheTimeLimit) {
  StateValidator validator(test::twoRobotScene(kCage), test::twoRobotModels());
  const DualPose start = toolsAt({-0.25, 0, 0.3}, {0.3, 0.35, 0.3});
  const DualPose goal = toolsAt({-0.25, 0, 0.3}, {0, 0.35, 0.3});
  ASSERT_TRUE(validator.isStateValid(goal)) << describe(validator.check(goal));
  PlannerOptions o = options();
  o.time_limit = 0.3;
  const PlanResult result = MotionPlanner(validator, o).planPath(start, goal);
  EXPECT_EQ(result.status, PlanStatus::NoSolution);
  EXPECT_TRUE(result.waypoints.empty());
  EXPECT_CONTAINS(result.message, "no path found by RRTConnect within 0.3");
}

TEST_F(MotionPlannerTest, AWorkLimitMakesSuccessAndFailureTheSameOnAnyMachine) {
  // The query with no limit but time: it needs N validity checks with this seed.
  const PlanResult unlimited = MotionPlanner(validator, options("RRTConnect", 42)).planPath(kStart, kGoal);
  ASSERT_TRUE(unlimited.solved()) << unlimited.message;
  const std::size_t needed = unlimited.validity_checks;
  ASSERT_GT(needed, 10u);
  // A budget of exactly N finds the same path however slow the machine (time_limit is ignored).
  PlannerOptions enough = options("RRTConnect", 42);
  enough.max_validity_checks = needed;
  enough.time_limit = 1e-9;
  const PlanResult budgeted = MotionPlanner(validator, enough).planPath(kStart, kGoal);
  ASSERT_TRUE(budgeted.solved()) << budgeted.message;
  ASSERT_EQ(budgeted.waypoints.size(), unlimited.waypoints.size());
  for (std::size_t i = 0; i < budgeted.waypoints.size(); ++i)
    EXPECT_TRUE(sameFrame(budgeted.waypoints[i].first, unlimited.waypoints[i].first)) << i;
  // Half of it fails, the same way every time, naming the budget.
  PlannerOptions short_of_it = enough;
  short_of_it.max_validity_checks = needed / 2;
  for (int run = 0; run < 2; ++run) {
    const PlanResult result = MotionPlanner(validator, short_of_it).planPath(kStart, kGoal);
    EXPECT_EQ(result.status, PlanStatus::NoSolution);
    EXPECT_CONTAINS(result.message, "no path found by RRTConnect within " + std::to_string(needed / 2) +
                                        " validity checks");
    EXPECT_GE(result.validity_checks, needed / 2);
  }
}

TEST_F(MotionPlannerTest, BadQueriesNameTheCause) {
  MotionPlanner planner(validator, options());
  PlanResult result = planner.planPath(kStart, toolsAt({0.25, 0, 0.9}, {0, 0.42, 0.3}));
  EXPECT_EQ(result.status, PlanStatus::OutOfBounds);
  EXPECT_CONTAINS(result.message, "goal position is outside the planner's bounds");

  DualPose nan_start = kStart;
  nan_start.first.p.x(std::numeric_limits<double>::quiet_NaN());
  result = planner.planPath(nan_start, kGoal);
  EXPECT_EQ(result.status, PlanStatus::InvalidInput);
  EXPECT_CONTAINS(result.message, "start pose has a NaN");

  result = planner.planPath(kStart, toolsAt({0.3, 0, 0.2}, {0, 0.42, 0.3}));  // needle in the phantom
  EXPECT_EQ(result.status, PlanStatus::InvalidGoal);
  EXPECT_EQ(result.rejected.second_object, "phantom");
  EXPECT_CONTAINS(result.message, "goal state is not valid: too close: micro/environment");

  result = planner.planPath(toolsAt({0, 0, 0.3}, {0, 0.42, 0.3}), kGoal);  // tool in the wall
  EXPECT_EQ(result.status, PlanStatus::InvalidStart);
}

TEST(MotionPlanner, ConfigurationErrorsExplainTheFix) {
  StateValidator validator(test::twoRobotScene(), test::twoRobotModels());
  PlannerOptions o = options("BIT*");
  EXPECT_CONTAINS(messageOf([&] { MotionPlanner p(validator, o); }),
                  "unknown planner 'BIT*': use RRTConnect, RRT, PRM, BiTRRT, LazyPRM, LBKPIECE1, BITstar");
  o = options();
  o.time_limit = 0.0;
  EXPECT_CONTAINS(messageOf([&] { MotionPlanner p(validator, o); }), "time_limit must be a positive");
  o = options();
  o.first_bounds.low[2] = 1.0;
  EXPECT_CONTAINS(messageOf([&] { MotionPlanner p(validator, o); }),
                  "first tool bounds must be finite with low < high");
  o = options();
  o.seed = 0;
  EXPECT_CONTAINS(messageOf([&] { MotionPlanner p(validator, o); }), "seed must be > 0");
}

}  // namespace
}  // namespace cobra::planning
