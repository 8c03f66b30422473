// Acceptance tests of isStateValid and planPath with the REAL robot models (planning::Ur5Model,
// IsurPuncturingModel, IsurSuturingModel over cobra::kinematics) on the shipped scenes. Every pose
// is what the test says it is: positions inside obstacles and links through structures are
// verified from the kinematics' link frames, not assumed.

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <limits>
#include <numbers>
#include <random>
#include <vector>

#include "cobra/planning/motion_planner.hpp"
#include "cobra/planning/robot_adapters.hpp"
#include "cobra/test_support/counting_new.hpp"
#include "cobra/test_support/test_support.hpp"
#include "joint_path_checks.hpp"
#include "planning_fixture.hpp"
#include "puncturing_tools.hpp"

namespace cobra::planning {
namespace {

using cobra::test_support::allocationsDuring;
using cobra::test_support::messageOf;
constexpr double kPi = std::numbers::pi;

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
constexpr double kSanitizerSlowdown = 10.0;
#else
constexpr double kSanitizerSlowdown = 1.0;
#endif

using test::needleDown;
using test::probeDown;
using test::scenes;

/// Distance from point p to the segment a-b [m].
double segmentDistance(const KDL::Vector& p, const KDL::Vector& a, const KDL::Vector& b) {
  const KDL::Vector ab = b - a;
  const double t = std::clamp(KDL::dot(p - a, ab) / KDL::dot(ab, ab), 0.0, 1.0);
  return (p - (a + t * ab)).Norm();
}

class PuncturingScene : public ::testing::Test {
 protected:
  PuncturingScene() {
    scene = loadScene(scenes() / "puncturing.scene");
    isur = std::make_shared<IsurPuncturingModel>();
    ur5 = std::make_shared<Ur5Model>();
  }
  StateValidator makeValidator(const std::string& extra = "") {
    SceneDescription s = extra.empty() ? scene : parseScene(test::readText(scenes() / "puncturing.scene") + extra,
                                                             "puncturing.scene", scenes());
    return StateValidator(s, {{"isur", isur}, {"ur5", ur5}});
  }
  /// World frame of a scene robot's base.
  KDL::Frame base(const char* robot) const { return scene.robots[scene.robotIndex(robot)].base_in_world; }

  SceneDescription scene;
  std::shared_ptr<IsurPuncturingModel> isur;
  std::shared_ptr<Ur5Model> ur5;
};

const DualPose kFree{needleDown(0.0, 0.0, 0.2), probeDown(-0.1, 0.0, 0.12)};

TEST_F(PuncturingScene, FreeQueryIsValidAndTheToolsAreWhereAsked) {
  StateValidator validator = makeValidator();
  const ValidityResult result = validator.check(kFree, true);
  ASSERT_TRUE(result.valid()) << describe(result);
  // The solved configurations put the tools at the asked poses (FK of the IK solution).
  KDL::Frame needle, probe;
  ASSERT_EQ(isur->solver().forward(isur->joints(), needle), kinematics::IkStatus::Ok);
  ASSERT_EQ(ur5->solver().forward(ur5->joints(), probe), kinematics::IkStatus::Ok);
  EXPECT_LT(((base("isur") * needle).p - kFree.first.p).Norm(), 1e-9);
  EXPECT_LT(((base("ur5") * probe).p - kFree.second.p).Norm(), 1e-9);
  EXPECT_GT(validator.minimumDistance(kFree), scene.min_collision_distance);
}

TEST_F(PuncturingScene, NeedleInsideThePhantomIsTooCloseToTheEnvironment) {
  StateValidator validator = makeValidator();
  // Phantom: box 0.3 x 0.22 x 0.1 m centred at (0, 0, 0.05): the tip at (0.05, 0, 0.05) is inside.
  const DualPose q{needleDown(0.05, 0.0, 0.05), kFree.second};
  const ValidityResult result = validator.check(q, true);
  EXPECT_EQ(result.validity, Validity::TooClose) << describe(result);
  EXPECT_EQ(result.first_group, "micro");
  EXPECT_EQ(result.second_group, "environment");
  EXPECT_EQ(result.first_object, "needle");
  EXPECT_EQ(result.second_object, "phantom");
  EXPECT_EQ(result.distance, 0.0);
}

TEST_F(PuncturingScene, Ur5WristThroughAnIsurRailIsTooCloseToTheMacroStructure) {
  StateValidator validator = makeValidator();
  // Rail 3 of the delta (azimuth 330 deg; turns with q4, which stays 0 with yaw_share 0): its axis
  // from 0.30 m off the vertical at the sliders' level, 30 deg inwards, in the I-SUR base frame.
  const double azimuth = 330.0 * kPi / 180.0;
  const KDL::Vector radial(std::cos(azimuth), std::sin(azimuth), 0.0);
  const KDL::Vector direction = -0.5 * radial + KDL::Vector(0, 0, -std::cos(kPi / 6));
  const KDL::Vector rail_top = base("isur") * (0.30 * radial);
  const KDL::Vector rail_bottom = base("isur") * (0.30 * radial + 0.30 * direction);
  const KDL::Vector on_rail = base("isur") * (0.30 * radial + 0.28 * direction);
  // The probe pointing along world +y (away from the UR5 base) with the flange (link 6) on the rail's axis.
  const KDL::Frame probe(KDL::Rotation::RotX(-kPi / 2), on_rail + KDL::Vector(0, 0.12, 0));
  const DualPose q{kFree.first, probe};
  const ValidityResult result = validator.check(q, true);
  EXPECT_EQ(result.validity, Validity::TooClose) << describe(result);
  EXPECT_EQ(result.first_group, "macro");
  EXPECT_EQ(result.second_group, "ur5");
  EXPECT_EQ(result.distance, 0.0);
  // The UR5's solved links: the flange frame (link 6) is on the rail axis, inside the rail.
  std::array<KDL::Frame, 8> links{};
  ASSERT_TRUE(ur5->solver().model().linkFrames(std::span<const double>(ur5->joints().data.data(), 6), links));
  EXPECT_LT(segmentDistance(base("ur5") * links[6].p, rail_top, rail_bottom), 1e-9);
}

TEST_F(PuncturingScene, UnreachablePosesNameTheRobot) {
  StateValidator validator = makeValidator();
  // The delta's platform cannot go below z = 1.0 - 0.55 m: the needle tip 0.75 m under it is out.
  ValidityResult result = validator.check({needleDown(0.0, 0.0, -0.3), kFree.second});
  EXPECT_EQ(result.validity, Validity::Unreachable);
  EXPECT_EQ(result.robot, "isur");
  EXPECT_CONTAINS(describe(result), "unreachable: robot 'isur' has no IK solution");
  // 1.5 m from the UR5's shoulder (its reach is under 0.95 m).
  result = validator.check({kFree.first, probeDown(-0.95, 0.0, 0.3)});
  EXPECT_EQ(result.validity, Validity::Unreachable);
  EXPECT_EQ(result.robot, "ur5");
}

// The warm start only follows small steps: for unrelated states the answer does not depend on the
// states checked before (the planner samples far-apart states in an arbitrary order).
TEST_F(PuncturingScene, ValidityOfUnrelatedStatesDoesNotDependOnTheOrderOfChecks) {
  StateValidator validator = makeValidator();
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> tilt(-0.5, 0.5), x(-0.15, 0.15), z(0.15, 0.3), px(-0.3, 0.35), py(-0.3, 0.3),
      pz(0.03, 0.35), yaw(-kPi, kPi);
  std::vector<DualPose> states;
  for (int i = 0; i < 400; ++i)
    states.push_back({KDL::Frame(KDL::Rotation::RPY(tilt(rng), tilt(rng), 0.0) * KDL::Rotation::RotY(kPi / 2),
                                 KDL::Vector(x(rng), x(rng), z(rng))),
                      KDL::Frame(KDL::Rotation::RotZ(yaw(rng)) * KDL::Rotation::RotX(kPi),
                                 KDL::Vector(px(rng), py(rng), pz(rng)))});
  std::vector<Validity> forward, backward(states.size());
  for (const DualPose& q : states) forward.push_back(validator.check(q).validity);
  for (std::size_t i = states.size(); i-- > 0;) backward[i] = validator.check(states[i]).validity;
  int valid = 0;
  for (std::size_t i = 0; i < states.size(); ++i) {
    EXPECT_EQ(forward[i], backward[i]) << "state " << i;
    valid += forward[i] == Validity::Valid ? 1 : 0;
  }
  EXPECT_GT(valid, 40);  // the sample mixes valid and invalid states
  EXPECT_LT(valid, 360);
}

TEST_F(PuncturingScene, NanPoseIsInvalidInput) {
  StateValidator validator = makeValidator();
  DualPose q = kFree;
  q.second.p.z(std::numeric_limits<double>::quiet_NaN());
  EXPECT_EQ(validator.check(q).validity, Validity::InvalidInput);
}

TEST_F(PuncturingScene, RobotSolveAllocatesNothing) {
  std::array<KDL::Frame, 1> tool{needleDown(0, 0, 0.22)};
  std::array<KDL::Frame, 6> isur_links{};
  EXPECT_EQ(allocationsDuring([&] { isur->solve(tool, isur_links); }), 0);
  tool[0] = probeDown(-0.4, 0.05, 0.2);
  std::array<KDL::Frame, 8> ur5_links{};
  EXPECT_EQ(allocationsDuring([&] { EXPECT_EQ(ur5->solve(tool, ur5_links), Reachability::Reachable); }), 0);
  EXPECT_EQ(allocationsDuring([&] { ur5->resetWarmStart(); }), 0);
}

// The puncturing scene is made of primitives only: a whole check (IK, FK, FCL updates and distance
// queries with FCL's own GJK) allocates nothing, for valid, too-close and unreachable states.
TEST_F(PuncturingScene, ChecksOnThePrimitiveSceneAllocateNothing) {
  StateValidator validator = makeValidator();
  const DualPose in_phantom{needleDown(0.05, 0.0, 0.05), kFree.second};
  const DualPose unreachable{needleDown(0.0, 0.0, -0.3), kFree.second};
  validator.check(kFree);
  EXPECT_EQ(allocationsDuring([&] { EXPECT_TRUE(validator.check(kFree).valid()); }), 0);
  EXPECT_EQ(allocationsDuring([&] { EXPECT_TRUE(validator.check(kFree, true).valid()); }), 0);
  EXPECT_EQ(allocationsDuring([&] { EXPECT_EQ(validator.check(in_phantom).validity, Validity::TooClose); }), 0);
  EXPECT_EQ(allocationsDuring([&] { EXPECT_EQ(validator.check(unreachable).validity, Validity::Unreachable); }), 0);
  EXPECT_EQ(allocationsDuring([&] { EXPECT_GT(validator.minimumDistance(kFree), 0.005); }), 0);
}

// distancesAt along a measured motion bounds each pair by its last distance minus how far its
// objects travelled, and measures the last closest pair first: 400 seeded random joint states
// (small steps as a servo makes them, a jump every 50) give the same distances as a validator that
// measures every pair afresh (a new one per state), within the narrow phase's rounding.
TEST_F(PuncturingScene, DistancesAlongAMotionEqualThoseMeasuredAfresh) {
  StateValidator validator = makeValidator();
  std::vector<double> q(validator.jointCount());
  std::size_t failed = 0;
  ASSERT_EQ(validator.inverseNear(kFree, {}, q, failed), Reachability::Reachable);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> small(-0.003, 0.003), jump(-0.15, 0.15);
  int measured = 0;
  std::vector<double> previous = q;  // the state before q
  for (int i = 0; i < 400; ++i) {
    std::vector<double> next = q;
    for (double& value : next) value += i % 50 == 49 ? jump(rng) : small(rng);
    const StateValidator::Distances d = validator.distancesAt(next);
    StateValidator fresh = makeValidator();
    const StateValidator::Distances expected = fresh.distancesAt(next);
    if (std::isnan(expected.clearance)) {  // outside the joint limits: the walk steps elsewhere
      EXPECT_TRUE(std::isnan(d.clearance)) << "state " << i;
      continue;
    }
    previous = q;
    q = next;
    ++measured;
    EXPECT_NEAR(d.clearance, expected.clearance, 1e-9) << "state " << i;
    EXPECT_EQ(d.allowed_contact, expected.allowed_contact) << "state " << i;
  }
  EXPECT_GT(measured, 200) << "the walk must stay mostly inside the joint limits";
  // The monitoring query runs in the planner component's step: on primitives it allocates nothing.
  double clearance = 0.0;
  EXPECT_EQ(allocationsDuring([&] { clearance = validator.distancesAt(previous).clearance; }), 0);
  EXPECT_FALSE(std::isnan(clearance));
}

// A robot whose joints did not change since distancesAt placed it is not placed again: 300 seeded
// states in which only the I-SUR moves, only the UR5 moves, or both, with pose checks (which place
// both robots from tool poses) in between, give the distances of a validator measuring each state
// afresh. A placement kept after a pose check moved the robots would give the pose's distances.
TEST_F(PuncturingScene, DistancesOfARobotHoldingStillAreThoseOfItsJoints) {
  StateValidator validator = makeValidator();
  std::vector<double> q(validator.jointCount());
  std::size_t failed = 0;
  ASSERT_EQ(validator.inverseNear(kFree, {}, q, failed), Reachability::Reachable);
  const std::size_t isur_joints = validator.model(0).jointCount();
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> small(-0.004, 0.004);
  const DualPose elsewhere{needleDown(0.05, 0.05, 0.25), probeDown(-0.15, 0.05, 0.2)};
  int measured = 0;
  for (int i = 0; i < 300; ++i) {
    std::vector<double> next = q;
    const int moving = i % 3;  // 0: the I-SUR, 1: the UR5, 2: both
    for (std::size_t j = 0; j < next.size(); ++j) {
      if (moving == 2 || (moving == 0) == (j < isur_joints)) next[j] += small(rng);
    }
    if (i % 7 == 6) {
      EXPECT_NE(validator.check(elsewhere).validity, Validity::InvalidInput);
    }
    if (i % 11 == 10) (void)validator.distancesAt(elsewhere);
    const StateValidator::Distances d = validator.distancesAt(next);
    StateValidator fresh = makeValidator();
    const StateValidator::Distances expected = fresh.distancesAt(next);
    if (std::isnan(expected.clearance)) {
      EXPECT_TRUE(std::isnan(d.clearance)) << "state " << i;
      continue;
    }
    q = next;
    ++measured;
    EXPECT_NEAR(d.clearance, expected.clearance, 1e-9) << "state " << i;
    EXPECT_EQ(d.allowed_contact, expected.allowed_contact) << "state " << i;
    EXPECT_EQ(d.primitive_contact, expected.primitive_contact) << "state " << i;
    // The same state again: nothing moves, the same distances.
    const StateValidator::Distances again = validator.distancesAt(next);
    EXPECT_EQ(again.allowed_contact, d.allowed_contact) << "state " << i;
    EXPECT_NEAR(again.clearance, d.clearance, 1e-9) << "state " << i;
  }
  EXPECT_GT(measured, 200) << "the walk must stay mostly inside the joint limits";
}

/// The probe moves from one side of the phantom to the other (x -0.2 to 0.25 m), low (tip 0.04 m
/// under the phantom's top): straight across is blocked by the phantom.
const DualPose kStart{needleDown(0.0, 0.0, 0.2), probeDown(-0.2, 0.0, 0.06)};
const DualPose kGoal{needleDown(0.0, 0.0, 0.2), probeDown(0.25, 0.0, 0.06)};

PlannerOptions puncturingOptions(std::uint32_t seed = 1) {
  PlannerOptions o;
  o.seed = seed;
  o.time_limit = 5.0 * kSanitizerSlowdown;
  o.first_bounds = {{-0.15, -0.15, 0.15}, {0.15, 0.15, 0.3}};
  o.second_bounds = {{-0.3, -0.3, 0.03}, {0.35, 0.3, 0.35}};
  return o;
}

TEST_F(PuncturingScene, PlannedPathAroundThePhantomIsValidAtEveryDensePoint) {
  StateValidator validator = makeValidator();
  ASSERT_TRUE(validator.isStateValid(kStart)) << describe(validator.check(kStart, true));
  ASSERT_TRUE(validator.isStateValid(kGoal)) << describe(validator.check(kGoal, true));
  // The probe's own contact with the phantom is allowed (the scene's `allow`), its wrist's is not.
  const DualPose across{kStart.first, probeDown(-0.1, 0.0, 0.015)};
  const ValidityResult blocked = validator.check(across, true);
  ASSERT_EQ(blocked.validity, Validity::TooClose);
  EXPECT_EQ(blocked.second_object, "phantom");

  MotionPlanner planner(validator, puncturingOptions());
  const PlanResult result = planner.planPath(kStart, kGoal);
  ASSERT_TRUE(result.solved()) << result.message;
  ASSERT_GE(result.waypoints.size(), 3u);
  // Independent dense check (KDL interpolation, 100 points per segment), walking from the start as
  // the robots would (the IK warm-starts from the previous point).
  validator.resetWarmStart();
  expectDenselyValid(validator, result);
}

TEST_F(PuncturingScene, SameSeedGivesTheSamePath) {
  StateValidator validator = makeValidator();
  const PlanResult first = MotionPlanner(validator, puncturingOptions(7)).planPath(kStart, kGoal);
  validator.check(kFree);  // moves the IK warm starts: the next query must not depend on it
  const PlanResult again = MotionPlanner(validator, puncturingOptions(7)).planPath(kStart, kGoal);
  ASSERT_TRUE(first.solved() && again.solved()) << first.message << " / " << again.message;
  ASSERT_EQ(first.waypoints.size(), again.waypoints.size());
  for (std::size_t i = 0; i < first.waypoints.size(); ++i) {
    EXPECT_EQ(first.waypoints[i].first, again.waypoints[i].first) << i;
    EXPECT_EQ(first.waypoints[i].second, again.waypoints[i].second) << i;
  }
}

TEST_F(PuncturingScene, GoalBehindAWallAcrossTheProbesBoundsFailsWithinTheTimeLimit) {
  // A wall on the table across the probe's whole bounding box (plane y = 0, x 0..0.3 m, 0.27 m
  // high): the probe (0.12 m long above its tip, tip z <= 0.14 m) can neither pass over nor around
  // it within the bounds. Start and goal are valid: the planner must search and give up.
  StateValidator validator = makeValidator("object wall environment world box 0.3 0.01 0.27 at 0.15 0 0.135 0 0 0\n");
  const DualPose start{needleDown(-0.09, 0.0, 0.18), probeDown(0.15, -0.12, 0.12)};
  const DualPose goal{needleDown(-0.09, 0.0, 0.18), probeDown(0.15, 0.12, 0.12)};
  ASSERT_TRUE(validator.isStateValid(start)) << describe(validator.check(start, true));
  ASSERT_TRUE(validator.isStateValid(goal)) << describe(validator.check(goal, true));
  PlannerOptions o = puncturingOptions();
  o.first_bounds = {{-0.1, -0.05, 0.16}, {-0.08, 0.05, 0.2}};
  o.second_bounds = {{0.05, -0.2, 0.08}, {0.25, 0.2, 0.14}};
  o.time_limit = 0.3;
  const PlanResult result = MotionPlanner(validator, o).planPath(start, goal);
  EXPECT_EQ(result.status, PlanStatus::NoSolution);
  EXPECT_TRUE(result.waypoints.empty());
  EXPECT_CONTAINS(result.message, "no path found by RRTConnect within 0.3");
}

TEST_F(PuncturingScene, BadQueriesNameTheCause) {
  StateValidator validator = makeValidator();
  PlannerOptions o = puncturingOptions();
  o.first_bounds.low[2] = 0.03;
  MotionPlanner planner(validator, o);
  DualPose out = kGoal;
  out.second.p.z(0.5);
  PlanResult result = planner.planPath(kStart, out);
  EXPECT_EQ(result.status, PlanStatus::OutOfBounds);
  EXPECT_CONTAINS(result.message, "goal position of the second tool (0.2500, 0.0000, 0.5000) m is outside the planner's bounds");
  DualPose nan_goal = kGoal;
  nan_goal.first.p.x(std::numeric_limits<double>::quiet_NaN());
  result = planner.planPath(kStart, nan_goal);
  EXPECT_EQ(result.status, PlanStatus::InvalidInput);
  EXPECT_CONTAINS(result.message, "goal pose has a NaN");
  result = planner.planPath(kStart, {needleDown(0.05, 0.0, 0.06), kGoal.second});  // needle in the phantom
  EXPECT_EQ(result.status, PlanStatus::InvalidGoal);
  EXPECT_CONTAINS(result.message, "goal state is not valid: too close: micro/environment");
}

TEST(RealRobotModels, MissingAndMalformedMeshesAndUnknownRobotsAreNamed) {
  const std::string text = test::readText(scenes() / "puncturing.scene");
  const auto build = [&](const std::string& extra, const std::filesystem::path& dir) {
    StateValidator v(parseScene(text + extra, "puncturing.scene", dir),
                     makeRobotModels(loadScene(scenes() / "puncturing.scene")));
  };
  EXPECT_CONTAINS(messageOf([&] { build("object cad environment world mesh absent.stl at 0 0 0 0 0 0\n", scenes()); }),
                  "absent.stl");
  EXPECT_CONTAINS(
      messageOf([&] { build("object cad environment world mesh malformed.stl at 0 0 0 0 0 0\n", test::dataDir()); }),
      "malformed.stl");
  SceneDescription other = loadScene(scenes() / "puncturing.scene");
  other.robots[1].name = "puma";
  EXPECT_EQ(messageOf([&] { makeRobotModels(other); }),
            "robot models: no kinematics for robot 'puma' with 1 tool(s): use 'ur5' (1 tool) or 'isur' (1 tool: "
            "puncturing, 2: suturing)");
}

// Algorithm 5.1: one solver for both arms of the suturing I-SUR. Tool poses from the FK of a
// configuration are valid; the gripper pushed into the phantom is too close to the environment.
TEST(SuturingScene, OneSolverForBothToolsChecksBothArms) {
  const SceneDescription scene = loadScene(scenes() / "suturing.scene");
  auto isur = std::make_shared<IsurSuturingModel>();
  StateValidator validator(scene, {{"isur", isur}});
  KDL::JntArray q = IsurSuturingModel::defaultSeed();
  q(5) = 0.8;  // the Endo Stitch arm pitched down
  q(6) = 0.6;
  KDL::Frame stitch, gripper;
  ASSERT_EQ(isur->solver().forward(q, stitch, gripper), kinematics::IkStatus::Ok);
  const KDL::Frame base = scene.robots[0].base_in_world;
  const DualPose free{base * stitch, base * gripper};
  const ValidityResult result = validator.check(free, true);
  EXPECT_TRUE(result.valid()) << describe(result);
  DualPose low = free;
  low.second.p.z(0.02);  // gripper tip inside the phantom (0.25 x 0.2 x 0.06 m at the origin)
  low.second.p.x(0.0);
  low.second.p.y(0.0);
  const ValidityResult too_low = validator.check(low, true);
  if (too_low.validity == Validity::Unreachable) {
    EXPECT_EQ(too_low.robot, "isur");
  } else {
    EXPECT_EQ(too_low.validity, Validity::TooClose) << describe(too_low);
  }
}

}  // namespace
}  // namespace cobra::planning

namespace cobra::planning {
namespace {

// The UR5's continuity-keeping IK is the controller's (kinematics::ContinuousIk: Ur5Solver's
// branch, where the elbow is the sign of sin q3): from any configuration, its own tool pose solves
// back to itself, also for |q3| > π (the sign of q3 itself, the rule before, flipped the elbow of
// those); and keepsBranch tells the start's branch apart from the others.
TEST(Ur5Joints, TheToolPoseOfAConfigurationSolvesBackToItselfOnTheControllersBranch) {
  Ur5Model ur5;
  std::mt19937 rng(5);  // 200 seeded configurations within the ±2π limits
  std::uniform_real_distribution<double> joint(-2.0 * std::numbers::pi, 2.0 * std::numbers::pi);
  std::array<KDL::Frame, 8> links{};
  std::vector<double> q(6), solved(6);
  int beyond_pi = 0;
  for (int i = 0; i < 200; ++i) {
    for (double& v : q) v = joint(rng);
    // Away from the singular sets, where the branch is well defined.
    if (!ur5.keepsBranch(q, q, q)) continue;
    beyond_pi += std::abs(q[2]) > std::numbers::pi ? 1 : 0;
    ASSERT_TRUE(ur5.linkFramesAt(q, links));
    const std::array<KDL::Frame, 1> tool{links[ur5.toolLink(0)]};
    ASSERT_EQ(ur5.inverseNear(tool, q, solved), Reachability::Reachable) << "configuration " << i;
    for (std::size_t j = 0; j < 6; ++j) EXPECT_NEAR(solved[j], q[j], 1e-7) << "configuration " << i << " joint " << j;
  }
  EXPECT_GT(beyond_pi, 20);
}

TEST(Ur5Joints, KeepsBranchRefusesTheOtherElbowWristAndShoulderAndTheMarginsNearThem) {
  Ur5Model ur5;
  const std::vector<double> start{0.5, -1.9, -1.7, 2.0, -1.5708, 0.0};  // elbow sin q3 < 0, wrist sin q5 < 0
  EXPECT_TRUE(ur5.keepsBranch(start, start, start));
  std::vector<double> q = start;
  q[2] = 1.7;  // the other elbow
  EXPECT_FALSE(ur5.keepsBranch(q, start, start));
  q = start;
  q[2] = -1.7 + 2.0 * std::numbers::pi;  // sin q3 < 0 again: the start's elbow, one turn on
  EXPECT_TRUE(ur5.keepsBranch(q, start, start));
  q = start;
  q[4] = -0.05;  // the start's wrist side, but within kWristMargin (0.1) of the aligned wrist
  EXPECT_FALSE(ur5.keepsBranch(q, start, start));
  q[4] = 1.0;  // the other wrist
  EXPECT_FALSE(ur5.keepsBranch(q, start, start));
  q = start;
  q[1] = -1.9 + std::numbers::pi;  // the upper arm turned over: the wrist point behind the base axis
  EXPECT_FALSE(ur5.keepsBranch(q, start, start));
  // A goal closer to the singular set than the margin lowers it to half the goal's distance.
  std::vector<double> goal = start;
  goal[4] = -0.04;
  q = start;
  q[4] = -0.03;
  EXPECT_TRUE(ur5.keepsBranch(q, start, goal));
  q[4] = -0.01;
  EXPECT_FALSE(ur5.keepsBranch(q, start, goal));
}

}  // namespace
}  // namespace cobra::planning
