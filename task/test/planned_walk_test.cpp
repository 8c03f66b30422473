// The planned walk's verifier (cobra/task/planned_walk.hpp) on the puncturing scene with the real
// robot models: a failed search moves the planner to the next seed, as the MotionPlanner
// component does; a motion primitive's end joints are those the continuity-keeping IK tracks
// along it in steps fine enough that finer ones do not change them; a primitive that leaves the
// robot's reach is refused.
#include "cobra/task/planned_walk.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "cobra/test_support/test_support.hpp"
#include "walk_scene.hpp"

namespace cobra::task {
namespace {

using planning::DualPose;
using planning::JointState;

TEST(PlannerStepVerifier, AFailedSearchMovesThePlannerToTheNextSeedAsTheComponentDoes) {
  planning::StateValidator validator = test::walkValidator();
  planning::PlannerOptions starved = test::walkOptions();
  starved.max_validity_checks = 1;  // no search can finish
  starved.seed = 7;
  planning::MotionPlanner needle(validator, test::walkOptions()), probe(validator, starved);
  DualPose start;
  ASSERT_TRUE(validator.toolPoses(test::kStart, start));
  PlannerStepVerifier verifier({&needle, &probe}, validator, test::kStart);
  GoalCandidate c;
  c.goal = {start.first, test::probeAt({0.15, -0.1, 0.25})};
  c.then = c.goal;
  const StepOutcome outcome = verifier.planned({"root.MoveToSkin.Approach", 1, true, 0}, std::vector{c});
  EXPECT_FALSE(outcome.ok);
  EXPECT_CONTAINS(outcome.why, "no solution: ");
  EXPECT_EQ(probe.options().seed, 8u);
  EXPECT_EQ(needle.options().seed, test::walkOptions().seed);
  EXPECT_TRUE(verifier.paths().empty());
  EXPECT_EQ(verifier.joints(), test::kStart);  // a refused step does not move the walk
  // A goal refused before the search (in the phantom, among two alternatives) spends no seed.
  GoalCandidate inside = c;
  inside.goal[1] = test::probeAt({0.0, 0.0, 0.05});
  const StepOutcome both = verifier.planned({"root.MoveToSkin.Approach", 1, true, 0}, std::vector{inside, c});
  EXPECT_CONTAINS(both.why, "none of the 2 goal alternatives can be taken: ");
  EXPECT_EQ(probe.options().seed, 9u);  // the second's search only
}

TEST(PlannerStepVerifier, AMotionPrimitiveEndsAtTheJointsTheIkTracksAlongIt) {
  planning::StateValidator validator = test::walkValidator();
  planning::PlannerOptions slow = test::walkOptions();
  slow.max_angular_velocity = 0.02;  // rad/s: a tilt slow enough for the I-SUR's joints
  planning::MotionPlanner needle(validator, slow), probe(validator, slow);
  PlannerStepVerifier verifier({&needle, &probe}, validator, test::kStart);
  DualPose start;
  ASSERT_TRUE(validator.toolPoses(test::kStart, start));
  // The needle tilted 0.3 rad more about the world x axis and 2 cm lower: the I-SUR's redundant
  // wrist ends 0.1 rad elsewhere when the IK follows the motion in 1 mrad steps than in finer ones.
  const PosePair from{start.first, start.second};
  const PosePair to{KDL::Frame(KDL::Rotation::RotX(0.3) * start.first.M, start.first.p - KDL::Vector(0, 0, 0.02)),
                    start.second};
  const StepOutcome outcome = verifier.straight({"root.InsertingNeedles.MoveToSkin.Descend", 0, false, 0}, from, to);
  ASSERT_TRUE(outcome.ok) << outcome.why;
  const JointState& end = verifier.joints();
  DualPose reached;
  ASSERT_TRUE(validator.toolPoses(end, reached));
  EXPECT_TRUE(KDL::Equal(reached.first, to[0], 1e-6));
  // The oracle: the IK followed in 10000 steps (2 um, 30 urad: finer steps no longer change the
  // end), as the robot tracks its command every millisecond.
  JointState tracked = test::kStart, next(tracked.size());
  std::size_t robot = 0;
  KDL::Vector axis;
  const double angle = (from[0].M.Inverse() * to[0].M).GetRotAngle(axis);
  for (int k = 1; k <= 10000; ++k) {
    const double s = k / 10000.0;
    const KDL::Frame pose(from[0].M * KDL::Rotation::Rot2(axis, s * angle), from[0].p + (to[0].p - from[0].p) * s);
    ASSERT_EQ(validator.inverseNear({pose, from[1]}, tracked, next, robot), planning::Reachability::Reachable) << k;
    tracked.swap(next);
  }
  double from_tracked = 0.0;
  for (std::size_t j = 0; j < 8; ++j) from_tracked = std::max(from_tracked, std::abs(end[j] - tracked[j]));
  EXPECT_LT(from_tracked, 1e-3);
  // The probe's joints did not move.
  for (std::size_t j = 8; j < 14; ++j) EXPECT_NEAR(end[j], test::kStart[j], 1e-9) << j;
}

TEST(PlannerStepVerifier, AMotionPrimitiveOutOfReachIsRefusedWithThePlannersReason) {
  planning::StateValidator validator = test::walkValidator();
  planning::MotionPlanner needle(validator, test::walkOptions()), probe(validator, test::walkOptions());
  PlannerStepVerifier verifier({&needle, &probe}, validator, test::kStart);
  DualPose start;
  ASSERT_TRUE(validator.toolPoses(test::kStart, start));
  const PosePair from{start.first, start.second};
  const PosePair far{KDL::Frame(start.first.M, KDL::Vector(0.25, -0.25, 0.01)), start.second};
  const StepOutcome outcome = verifier.straight({"root.InsertingNeedles.PenetratingSkin", 0, false, 0}, from, far);
  EXPECT_FALSE(outcome.ok);
  EXPECT_CONTAINS(outcome.why, "invalid goal: the straight motion after the goal, to (0.2500, -0.2500, 0.0100) m");
  EXPECT_EQ(verifier.joints(), test::kStart);
}

}  // namespace
}  // namespace cobra::task
