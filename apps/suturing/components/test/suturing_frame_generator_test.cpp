// The Suturing Frame Generator on the lockstep clock with the app's state table: each datum
// against the stitch it was given (computed here independently: the stitch frame flipped about
// its x axis, offsets in the stitch frame), a row with a check (then_right), the errors naming
// the state, the table line and the missing port, a bad table refused with its file:line, and
// the answer to a row without checks allocating nothing.
#include "cobra/components/suturing/suturing_frame_generator.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "cobra/core/core.hpp"
#include "cobra/test_support/counting_new.hpp"
#include "cobra/test_support/test_support.hpp"

namespace cobra::components {
namespace {

using namespace std::chrono_literals;

const std::string kApp = std::string(COBRA_SOURCE_DIR) + "/apps/suturing/";
// A stitch 2 mm deep across a cut along a slanted direction: x along the cut, z out of the skin.
const KDL::Rotation kStitchFrame = KDL::Rotation::RotZ(0.4) * KDL::Rotation::RotX(0.1);
const KDL::Frame kRight(kStitchFrame, KDL::Vector(0.40, -0.05, 0.10));
const KDL::Frame kLeft(kStitchFrame, kRight.p + kStitchFrame * KDL::Vector(0.0, 0.006, 0.0));

struct Bench {
  SuturingFrameGenerator generator{"SutureFrames"};
  core::LockstepClock clock;
  core::OutputPort<core::TaskState> state{"taskState", "", ""};
  core::OutputPort<KDL::Frame> right_stitch{"rs", "", "m"}, left_stitch{"ls", "", "m"};
  core::OutputPort<KDL::Frame> right_meas{"rm", "", "m"}, left_meas{"lm", "", "m"};
  core::InputPort<trajectory::MultiAxisPath> desired{"desired", "", "m"}, goal{"goal", "", "m"};
  core::InputPort<core::Event> events{"events", "", ""};

  explicit Bench(const std::string& table = kApp + "state_table.txt") {
    generator.setProperty("state_table_file", table);
    clock.add(generator, 10ms);
    core::connectPorts(generator.port("events"), events, core::ConnPolicy::buffer(16));
    core::connectPorts(state, generator.port("currentTaskState"));
    core::connectPorts(right_stitch, generator.port("rightStitchPose"));
    core::connectPorts(left_stitch, generator.port("leftStitchPose"));
    core::connectPorts(right_meas, generator.port("rightMeasPose"));
    core::connectPorts(left_meas, generator.port("leftMeasPose"));
    core::connectPorts(generator.port("desiredPoses"), desired);
    core::connectPorts(generator.port("goalPoses"), goal);
  }
  void start() {
    ASSERT_TRUE(generator.configure());
    ASSERT_TRUE(generator.start());
  }
  void plan() {
    right_stitch.write(kRight);
    left_stitch.write(kLeft);
  }
  void measure() {
    right_meas.write(KDL::Frame(KDL::Vector(0.3, 0.0, 0.2)));
    left_meas.write(KDL::Frame(KDL::Rotation::RotY(0.2), KDL::Vector(0.5, 0.0, 0.2)));
  }
  std::string ask(const std::string& path) {
    state.write(core::TaskState{std::string_view(path)});
    generator.call<void>("askCurrentGoal");
    clock.advance(10ms);
    std::string said;
    for (core::Event e; events.read(e) == core::FlowStatus::NewData;) said = e.name.str();
    return said;
  }
  /// The goal pair the answer put on desiredPoses (its second waypoint): right, left.
  std::pair<KDL::Frame, KDL::Frame> goalPair() {
    trajectory::MultiAxisPath path;
    EXPECT_NE(desired.read(path), core::FlowStatus::NoData);
    const auto pose = [&](std::size_t arm) {
      const double* v = path.waypoint(1).data() + arm * 7;
      return KDL::Frame(KDL::Rotation::Quaternion(v[3], v[4], v[5], v[6]), KDL::Vector(v[0], v[1], v[2]));
    };
    return {pose(0), pose(1)};
  }
};

/// The tool's pose at stitch-frame point `p` from the right target: x along the cut, z into the skin.
KDL::Frame expected(const KDL::Vector& from_centre) {
  const KDL::Vector centre = (kRight.p + kLeft.p) * 0.5;
  return KDL::Frame(KDL::Rotation(kStitchFrame.UnitX(), -kStitchFrame.UnitY(), -kStitchFrame.UnitZ()),
                    centre + kStitchFrame * from_centre);
}

void expectPose(const KDL::Frame& actual, const KDL::Frame& wanted) {
  EXPECT_NEAR((actual.p - wanted.p).Norm(), 0.0, 1e-12);
  EXPECT_TRUE(KDL::Equal(actual.M, wanted.M, 1e-9));
}

TEST(SuturingFrameGenerator, EachDatumIsAToolPoseOverTheCurrentStitch) {
  Bench b;
  b.start();
  b.plan();
  b.measure();
  const double w = 0.003;  // half the gap between kRight and kLeft
  ASSERT_EQ(b.ask("root.AutonomousMode.ApplyRightStitch.MoveInsideWound.AskingGoal"), "e_goal_ready");
  auto [right, left] = b.goalPair();
  expectPose(right, expected(KDL::Vector(0.0, 0.0, 0.0)));
  expectPose(left, KDL::Frame(KDL::Rotation::RotY(0.2), KDL::Vector(0.5, 0.0, 0.2)));  // hold
  ASSERT_EQ(b.ask("root.AutonomousMode.ApplyRightStitch.MoveToWoundEdge.AskingGoal"), "e_goal_ready");
  expectPose(b.goalPair().first, expected(KDL::Vector(0.0, -w, 0.0)));
  ASSERT_EQ(b.ask("root.AutonomousMode.ApplyLeftStitch.MoveToWoundEdge.AskingGoal"), "e_goal_ready");
  expectPose(b.goalPair().first, expected(KDL::Vector(0.0, w, 0.0)));
  ASSERT_EQ(b.ask("root.AutonomousMode.ApplyLeftStitch.DisengageNeedle.AskingGoal"), "e_goal_ready");
  expectPose(b.goalPair().first, expected(KDL::Vector(0.0, w, 0.01)));  // left_edge-0.01: 1 cm out of the skin
  ASSERT_EQ(b.ask("root.AutonomousMode.PullThread.AskingGoal"), "e_goal_ready");
  expectPose(b.goalPair().first, expected(KDL::Vector(0.0, 0.0, 0.037)));  // pull_offset's default
  // The thread leaves the skin beyond the left edge now (the last half asked for was the left one):
  // the stick's datums from the left target, outward = +y.
  ASSERT_EQ(b.ask("root.AutonomousMode.HookThread.AskingGoal"), "e_goal_ready");
  expectPose(b.goalPair().second, expected(KDL::Vector(0.0, w + 0.0005, 0.02)));
  ASSERT_EQ(b.ask("root.AutonomousMode.PushThread.AskingGoal"), "e_goal_ready");
  expectPose(b.goalPair().second, expected(KDL::Vector(-0.006, w + 0.0005, 0.02)));
  // After a right half, from the right target, outward = -y.
  ASSERT_EQ(b.ask("root.AutonomousMode.ApplyRightStitch.DisengageNeedle.AskingGoal"), "e_goal_ready");
  ASSERT_EQ(b.ask("root.AutonomousMode.HookThread.AskingGoal"), "e_goal_ready");
  expectPose(b.goalPair().second, expected(KDL::Vector(0.0, -w - 0.0005, 0.02)));
}

TEST(SuturingFrameGenerator, AnOffsetPropertyMovesItsDatum) {
  Bench b;
  b.generator.setProperty("hook_offset", KDL::Vector(0.001, 0.002, 0.03));
  b.start();
  b.plan();
  b.measure();
  ASSERT_EQ(b.ask("root.AutonomousMode.HookThread.AskingGoal"), "e_goal_ready");  // right half before any
  expectPose(b.goalPair().second, expected(KDL::Vector(0.001, -0.003 - 0.002, 0.03)));
}

TEST(SuturingFrameGenerator, ARowWithACheckPublishesTheMotionAfterItsGoal) {
  const std::string path = (::cobra::test_support::scratchPath("suturing_then_table.txt")).string();
  std::ofstream(path) << "state MoveOverWound right=centre-0.03 left=aside then_right=centre\n";
  Bench b(path);
  b.start();
  b.plan();
  b.measure();
  ASSERT_EQ(b.ask("root.AutonomousMode.ApplyRightStitch.MoveOverWound.AskingGoal"), "e_goal_ready");
  trajectory::MultiAxisPath goal;
  ASSERT_NE(b.goal.read(goal), core::FlowStatus::NoData);
  ASSERT_EQ(goal.size(), 1u);
  ASSERT_EQ(goal.waypoint(0).size(), 28u);  // goal pair, then pair (then_right=centre)
  const KDL::Frame over = expected(KDL::Vector(0.0, 0.0, 0.03));
  EXPECT_NEAR(goal.waypoint(0)[2], over.p.z(), 1e-12);
  EXPECT_NEAR(goal.waypoint(0)[14 + 2], expected(KDL::Vector(0.0, 0.0, 0.0)).p.z(), 1e-12);
  // The stick aside: aside_offset's default from the centre, in the stitch frame (+y: the left edge's side).
  const KDL::Frame aside = expected(KDL::Vector(-0.016, 0.018, 0.015));
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(goal.waypoint(0)[7 + i], aside.p[i], 1e-12);
  // The same place before the left half (not mirrored like the thread's datums).
  ASSERT_EQ(b.ask("root.AutonomousMode.ApplyLeftStitch.MoveOverWound.AskingGoal"), "e_goal_ready");
  ASSERT_NE(b.goal.read(goal), core::FlowStatus::NoData);
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(goal.waypoint(0)[7 + i], aside.p[i], 1e-12);
  std::filesystem::remove(path);
}

TEST(SuturingFrameGenerator, MissingDataAnswersNoDataNamingTheStateTheLineAndThePort) {
  Bench b;
  b.start();
  const std::string line = std::to_string(b.generator.table().find("root.AutonomousMode.PullThread")->line);
  EXPECT_EQ(b.ask("root.AutonomousMode.PullThread.AskingGoal"), "e_no_data");
  EXPECT_EQ(b.generator.call<std::string>("lastFailure"),
            "task state 'root.AutonomousMode.PullThread.AskingGoal' (" + kApp +
                "state_table.txt:" + line + "): right=pull: no stitch planned yet (rightStitchPose and leftStitchPose)");
  b.plan();
  EXPECT_EQ(b.ask("root.AutonomousMode.PullThread.AskingGoal"), "e_no_data");
  EXPECT_EQ(b.generator.call<std::string>("lastFailure"),
            "task state 'root.AutonomousMode.PullThread.AskingGoal' (" + kApp +
                "state_table.txt:" + line + "): left=hold: no pose on leftMeasPose yet");
  EXPECT_EQ(b.ask("root.WaitStitchesPlan"), "e_no_data");
  EXPECT_EQ(b.generator.call<std::string>("lastFailure"),
            "task state 'root.WaitStitchesPlan' matches no row of " + kApp + "state_table.txt");
  b.measure();
  EXPECT_EQ(b.ask("root.AutonomousMode.PullThread.AskingGoal"), "e_goal_ready");
  EXPECT_EQ(b.generator.call<std::string>("lastFailure"), "");
}

TEST(SuturingFrameGenerator, ABadTableIsRefusedWithItsFileAndLine) {
  const std::string path = (::cobra::test_support::scratchPath("suturing_bad_table.txt")).string();
  std::ofstream(path) << "state PullThread right=pull left=hold\nstate HookThread right=hold left=hook_it\n";
  Bench b(path);
  EXPECT_EQ(b.generator.configure().message,
            "component 'SutureFrames': " + path +
                ":2: unknown datum 'hook_it' (expected right_edge, left_edge, centre, pull, aside, hook, push, hold or a "
                "pose defined above)");
  std::ofstream(path) << "state PullThread needle=pull probe=hold\n";
  EXPECT_EQ(b.generator.configure().message,
            "component 'SutureFrames': " + path + ":1: 'state' needs right=");
  std::filesystem::remove(path);
}

TEST(SuturingFrameGenerator, AnsweringARowWithoutChecksAllocatesNothing) {
  Bench b;
  b.start();
  b.plan();
  b.measure();
  const char* states[] = {"root.AutonomousMode.PullThread.AskingGoal", "root.AutonomousMode.HookThread.AskingGoal",
                          "root.AutonomousMode.ApplyLeftStitch.MoveToWoundEdge.AskingGoal"};
  for (const char* s : states) ASSERT_EQ(b.ask(s), "e_goal_ready");  // the connections sized
  const long allocations = test_support::allocationsDuring([&] {
    for (const char* s : states) {
      b.state.write(core::TaskState{s});
      b.generator.askCurrentGoal();
      b.clock.advance(10ms);
    }
  });
  EXPECT_EQ(allocations, 0);
}

}  // namespace
}  // namespace cobra::components
