// The Puncturing Frame Generator (thesis §4.5.5) on the lockstep clock, with the two_needles
// scenario and the app's state table: goals checked against cobra::puncturing computing them
// independently and against hand-computed values.
#include "cobra/components/puncturing/frame_generator.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "cobra/core/core.hpp"
#include "cobra/test_support/counting_new.hpp"
#include "cobra/test_support/test_support.hpp"

namespace cobra::components {
namespace {

using namespace std::chrono_literals;
namespace pp = cobra::puncturing;

const std::string kApp = std::string(COBRA_SOURCE_DIR) + "/apps/puncturing/";
const std::string kScenario = kApp + "scenarios/two_needles/";

KDL::Frame frame(double x, double y, double z, double rx, double ry, double rz) {
  return {KDL::Rotation::RPY(rx, ry, rz), KDL::Vector(x, y, z)};
}

/// A frame generator on a 10 ms lockstep clock with test peers on all its ports.
struct Bench {
  PuncturingFrameGenerator generator{"NeedleFrames"};
  core::LockstepClock clock;
  core::OutputPort<KDL::Frame> abdomen{"abdomen", "test registration", "m"};
  core::OutputPort<core::TaskState> state{"taskState", "test supervisor", ""};
  core::OutputPort<KDL::Frame> needle_meas{"needleMeas", "test robot", "m"};
  core::OutputPort<KDL::Frame> us_meas{"usMeas", "test robot", "m"};
  core::InputPort<trajectory::MultiAxisPath> desired{"desired", "test trajectory generator", "m"};
  core::InputPort<trajectory::MultiAxisPath> goal{"goal", "test planner", "m"};
  core::InputPort<KDL::Frame> target{"target", "test monitor", "m"};
  core::InputPort<core::Event> events{"events", "test supervisor", ""};
  pp::PuncturingPlan plan = pp::loadPlan(kScenario + "preoperative.txt", kScenario + "cryo_plan.txt",
                                         kScenario + "us_plan.txt");
  pp::StateTable table = pp::parseStateTable(pp::readText(kApp + "state_table.txt"), "state_table.txt");

  explicit Bench(const std::string& cryo_plan = kScenario + "cryo_plan.txt",
                 const std::string& state_table = kApp + "state_table.txt") {
    generator.setProperty("preoperative_info_file", kScenario + "preoperative.txt");
    generator.setProperty("cryo_plan_file", cryo_plan);
    generator.setProperty("US_pose_plan_file", kScenario + "us_plan.txt");
    generator.setProperty("state_table_file", state_table);
    clock.add(generator, 10ms);
    core::connectPorts(generator.port("events"), events, core::ConnPolicy::buffer(64));
  }
  bool configure() {
    if (!generator.configure()) return false;
    core::connectPorts(abdomen, generator.port("abdomenFrame"));
    core::connectPorts(state, generator.port("currentTaskState"));
    core::connectPorts(needle_meas, generator.port("needleMeasPose"));
    core::connectPorts(us_meas, generator.port("USMeasPose"));
    core::connectPorts(generator.port("desiredPoses"), desired);
    core::connectPorts(generator.port("goalPoses"), goal);
    core::connectPorts(generator.port("needleTarget"), target);
    return static_cast<bool>(generator.start());
  }
  /// Asks for the goal in task state `path`; returns the events it answered.
  std::vector<std::string> ask(const std::string& path) {
    state.write(core::TaskState{std::string_view(path)});
    generator.call<void>("askCurrentGoal");
    clock.advance(10ms);
    return takeEvents();
  }
  std::vector<std::string> takeEvents() {
    std::vector<std::string> names;
    core::Event e;
    while (events.read(e) == core::FlowStatus::NewData) names.push_back(e.name.str());
    return names;
  }
  std::vector<std::vector<KDL::Frame>> desiredPath() {
    trajectory::MultiAxisPath path;
    EXPECT_NE(desired.read(path), core::FlowStatus::NoData);
    return decodeCartesianPath(path, 2);
  }
  /// The goal pair of goal alternative `alternative` (a waypoint of goalPoses); `checks` (when
  /// given) gets the rest of its waypoint: where the motion after the goal goes (then_*), then the
  /// start and end pairs of each room_for_* (empty for a row without either).
  std::vector<KDL::Frame> goalPair(std::vector<KDL::Frame>* checks = nullptr, std::size_t alternative = 0) {
    trajectory::MultiAxisPath path;
    EXPECT_NE(goal.read(path), core::FlowStatus::NoData);
    const std::vector<std::vector<KDL::Frame>> alternatives = decodeCartesianPath(path, path.axisCount() / kValuesPerArm);
    const std::vector<KDL::Frame>& pairs = alternatives.at(alternative);
    if (checks != nullptr) *checks = std::vector<KDL::Frame>(pairs.begin() + 2, pairs.end());
    return {pairs[0], pairs[1]};
  }
  std::size_t alternatives() {
    trajectory::MultiAxisPath path;
    EXPECT_NE(goal.read(path), core::FlowStatus::NoData);
    return path.size();
  }
  std::string lastFailure() { return generator.call<std::string>("lastFailure"); }
};

const KDL::Frame kNeedleMeas = frame(0.4, -0.1, 0.3, 3.0, 0.1, 0.2);
const KDL::Frame kUsMeas = frame(0.6, 0.15, 0.25, 2.9, -0.2, 1.0);

/// Expects desiredPoses = [measured pair, goal pair] and goalPoses = the goal pair.
void expectPublished(Bench& b, const KDL::Frame& needle_goal, const KDL::Frame& probe_goal, const std::string& what) {
  const auto path = b.desiredPath();
  ASSERT_EQ(path.size(), 2u) << what;
  EXPECT_TRUE(KDL::Equal(path[0][0], kNeedleMeas, 1e-12)) << what;
  EXPECT_TRUE(KDL::Equal(path[0][1], kUsMeas, 1e-12)) << what;
  EXPECT_TRUE(KDL::Equal(path[1][0], needle_goal, 1e-12)) << what;
  EXPECT_TRUE(KDL::Equal(path[1][1], probe_goal, 1e-12)) << what;
  const auto goal = b.goalPair();
  EXPECT_TRUE(KDL::Equal(goal[0], needle_goal, 1e-12)) << what;
  EXPECT_TRUE(KDL::Equal(goal[1], probe_goal, 1e-12)) << what;
}

TEST(PuncturingFrameGenerator, PublishesTheGoalPairOfEachTaskStateAsTheLibraryComputesIt) {
  Bench b;
  ASSERT_TRUE(b.configure()) << b.generator.lastError();
  b.needle_meas.write(kNeedleMeas);
  b.us_meas.write(kUsMeas);
  const KDL::Frame a = b.plan.preoperative.abdomen_in_task;  // no abdomenFrame sample yet: the nominal one
  const pp::PlannedNeedle& n1 = b.plan.needles[0];

  EXPECT_EQ(b.ask("root.InsertingNeedles.MoveToSkin.Approach.AskingGoal"), std::vector<std::string>{"e_goal_ready"});
  expectPublished(b, a * pp::alongZ(pp::needleEntryPose(n1), -0.02), kUsMeas, "Approach");
  EXPECT_EQ(b.ask("root.InsertingNeedles.MoveToSkin.Descend.AskingGoal"), std::vector<std::string>{"e_goal_ready"});
  expectPublished(b, a * pp::alongZ(pp::needleEntryPose(n1), 0.004), kUsMeas, "Descend");
  EXPECT_EQ(b.ask("root.InsertingNeedles.MoveToTumor.AskingGoal"), std::vector<std::string>{"e_goal_ready"});
  expectPublished(b, a * pp::needleTargetPose(n1), kUsMeas, "MoveToTumor");
  EXPECT_EQ(b.ask("root.InsertingNeedles.MoveToNeedleChange.Planning"), std::vector<std::string>{"e_goal_ready"});
  expectPublished(b, *b.table.pose("needle_change"), kUsMeas, "MoveToNeedleChange (a task-frame pose)");
  // The ultrasound chart's rows: the needle holds, the probe goes to its planned pose.
  EXPECT_EQ(b.ask("root.MoveToSkin.Approach.AskingGoal"), std::vector<std::string>{"e_goal_ready"});
  expectPublished(b, kNeedleMeas, a * pp::alongZ(b.plan.probes[0].pose, -0.03), "us Approach");
  // The approach's row names the descent that follows it (then_probe): goalPoses' second waypoint,
  // the needle staying where it holds.
  std::vector<KDL::Frame> follow_on;
  b.goalPair(&follow_on);
  ASSERT_EQ(follow_on.size(), 2u);
  EXPECT_TRUE(KDL::Equal(follow_on[0], kNeedleMeas, 1e-12));
  EXPECT_TRUE(KDL::Equal(follow_on[1], a * pp::alongZ(b.plan.probes[0].pose, 0.004), 1e-12));
  EXPECT_EQ(b.generator.call<int>("needleCount"), 2);
}

TEST(PuncturingFrameGenerator, PublishesTheGoalAlternativesOfARowWithTheRoomEachMustLeave) {
  Bench b;
  ASSERT_TRUE(b.configure()) << b.generator.lastError();
  b.needle_meas.write(kNeedleMeas);
  b.us_meas.write(kUsMeas);
  const KDL::Frame a = b.plan.preoperative.abdomen_in_task;
  // Back to a needle change pose (state_table.txt): the alternatives in the table's order, each
  // with the probe holding, the follow-on "stay" and the room for the probe's next approach and
  // descent (next_probe: the second needle's probe pose) beside that needle pose.
  EXPECT_EQ(b.ask("root.InsertingNeedles.MoveToNeedleChange.Planning"), std::vector<std::string>{"e_goal_ready"});
  const KDL::Frame needle_poses[] = {*b.table.pose("needle_change"), kNeedleMeas, *b.table.pose("needle_change_aside"),
                                     *b.table.pose("needle_change_far")};
  ASSERT_EQ(b.alternatives(), 4u);
  for (std::size_t k = 0; k < 4; ++k) {
    std::vector<KDL::Frame> checks;
    const std::vector<KDL::Frame> goal = b.goalPair(&checks, k);
    EXPECT_TRUE(KDL::Equal(goal[0], needle_poses[k], 1e-12)) << k;
    EXPECT_TRUE(KDL::Equal(goal[1], kUsMeas, 1e-12)) << k;
    ASSERT_EQ(checks.size(), 6u) << k;
    EXPECT_TRUE(KDL::Equal(checks[0], goal[0], 1e-12));  // no then_*: the goal again
    EXPECT_TRUE(KDL::Equal(checks[1], goal[1], 1e-12));
    EXPECT_TRUE(KDL::Equal(checks[2], needle_poses[k], 1e-12));  // the needle waits at its goal
    EXPECT_TRUE(KDL::Equal(checks[3], a * pp::alongZ(b.plan.probes[1].pose, -0.03), 1e-12));
    EXPECT_TRUE(KDL::Equal(checks[4], needle_poses[k], 1e-12));
    EXPECT_TRUE(KDL::Equal(checks[5], a * pp::alongZ(b.plan.probes[1].pose, 0.004), 1e-12));
  }
  expectPublished(b, needle_poses[0], kUsMeas, "desiredPoses: the first alternative");
  // Before the probe's first approach the room is for the current needle's probe pose.
  EXPECT_EQ(b.ask("root.MakeRoomForProbe.AskingGoal"), std::vector<std::string>{"e_goal_ready"});
  ASSERT_EQ(b.alternatives(), 3u);
  std::vector<KDL::Frame> checks;
  b.goalPair(&checks, 2);
  ASSERT_EQ(checks.size(), 6u);
  EXPECT_TRUE(KDL::Equal(checks[3], a * pp::alongZ(b.plan.probes[0].pose, -0.03), 1e-12));
  // At the last needle no probe motion follows: the room check is left out.
  b.generator.call<void>("nextNeedle");
  b.clock.advance(10ms);
  b.takeEvents();
  EXPECT_EQ(b.ask("root.InsertingNeedles.MoveToNeedleChange.Planning"), std::vector<std::string>{"e_goal_ready"});
  ASSERT_EQ(b.alternatives(), 4u);
  b.goalPair(&checks, 0);
  EXPECT_EQ(checks.size(), 2u);  // the follow-on pair only
}

TEST(PuncturingFrameGenerator, MatchesHandComputedPosesOfTheFirstNeedle) {
  Bench b;
  ASSERT_TRUE(b.configure());
  b.needle_meas.write(kNeedleMeas);
  b.us_meas.write(kUsMeas);
  // n1: entry (-0.02, -0.006, 0), target (-0.005, 0, -0.058) in A; A at (0, 0, 0.1), not rotated
  // (preoperative.txt of two_needles).
  const KDL::Vector axis = KDL::Vector(0.015, 0.006, -0.058) / std::sqrt(0.015 * 0.015 + 0.006 * 0.006 + 0.058 * 0.058);
  ASSERT_EQ(b.ask("root.InsertingNeedles.MoveToTumor.Moving"), std::vector<std::string>{"e_goal_ready"});
  KDL::Frame tip = b.goalPair()[0];
  EXPECT_NEAR((tip.p - KDL::Vector(-0.005, 0.0, 0.042)).Norm(), 0.0, 1e-12);
  EXPECT_NEAR((tip.M.UnitZ() - axis).Norm(), 0.0, 1e-12);
  ASSERT_EQ(b.ask("root.ExtractingNeedle.MoveToExtractionPoint.AskingGoal"), std::vector<std::string>{"e_goal_ready"});
  tip = b.goalPair()[0];  // 6 cm back along the needle from the entry point (-0.02, -0.006, 0.1)
  EXPECT_NEAR((tip.p - (KDL::Vector(-0.02, -0.006, 0.1) - axis * 0.06)).Norm(), 0.0, 1e-12);
  KDL::Frame target;
  ASSERT_NE(b.target.read(target), core::FlowStatus::NoData);
  EXPECT_NEAR((target.p - KDL::Vector(-0.005, 0.0, 0.042)).Norm(), 0.0, 1e-12);
}

TEST(PuncturingFrameGenerator, MapsThePlanThroughTheMeasuredAbdomenFrame) {
  Bench b;
  ASSERT_TRUE(b.configure());
  b.needle_meas.write(kNeedleMeas);
  b.us_meas.write(kUsMeas);
  const KDL::Frame abdomen = frame(0.45, 0.08, 0.1, 0.1, -0.05, 0.6);
  b.abdomen.write(abdomen);
  ASSERT_EQ(b.ask("root.InsertingNeedles.MoveToTumor.AskingGoal"), std::vector<std::string>{"e_goal_ready"});
  const KDL::Frame target_in_a = pp::needleTargetPose(b.plan.needles[0]);
  EXPECT_TRUE(KDL::Equal(b.goalPair()[0], abdomen * target_in_a, 1e-12));
  // Position by hand: A's origin plus the rotated tip position.
  EXPECT_NEAR((b.goalPair()[0].p - (abdomen.p + abdomen.M * KDL::Vector(-0.005, 0, -0.058))).Norm(), 0.0, 1e-12);
  KDL::Frame target;
  ASSERT_NE(b.target.read(target), core::FlowStatus::NoData);
  EXPECT_TRUE(KDL::Equal(target, abdomen * target_in_a, 1e-12));
  EXPECT_TRUE(KDL::Equal(b.generator.call<KDL::Frame>("plannedTarget", 1),
                         abdomen * pp::needleTargetPose(b.plan.needles[1]), 1e-12));
  // The offset stays along the needle in the world: Approach is 2 cm above the entry on the needle axis.
  ASSERT_EQ(b.ask("root.InsertingNeedles.MoveToSkin.Approach.AskingGoal"), std::vector<std::string>{"e_goal_ready"});
  const KDL::Frame approach = b.goalPair()[0];
  const KDL::Vector entry = abdomen * b.plan.needles[0].entry;
  EXPECT_NEAR((approach.p - entry).Norm(), 0.02, 1e-12);
  EXPECT_NEAR(KDL::dot(entry - approach.p, approach.M.UnitZ()), 0.02, 1e-12);
  // The probe's planned pose too.
  ASSERT_EQ(b.ask("root.MoveToSkin.Descend.AskingGoal"), std::vector<std::string>{"e_goal_ready"});
  EXPECT_TRUE(KDL::Equal(b.goalPair()[1], abdomen * pp::alongZ(b.plan.probes[0].pose, 0.004), 1e-12));
  EXPECT_THROW(b.generator.call<KDL::Frame>("plannedTarget", 2), core::Error);
}

TEST(PuncturingFrameGenerator, HoldUsesTheLatestMeasuredPoseAndNeedsOne) {
  Bench b;
  b.generator.setProperty("arm", std::string("probe"));
  ASSERT_TRUE(b.configure());
  b.us_meas.write(kUsMeas);
  EXPECT_EQ(b.ask("root.MoveToSkin.Approach.AskingGoal"), std::vector<std::string>{"e_no_data"});
  // The table line of the row, found in the shipped table.
  std::ifstream table(kApp + "state_table.txt");
  std::string text;
  int row = 0;
  for (int n = 1; std::getline(table, text); ++n)
    if (text.rfind("state root.MoveToSkin.Approach ", 0) == 0) row = n;
  ASSERT_GT(row, 0);
  EXPECT_EQ(b.lastFailure(), "task state 'root.MoveToSkin.Approach.AskingGoal' (" + kApp + "state_table.txt:" +
                                 std::to_string(row) + "): needle=hold: no pose on needleMeasPose yet");
  b.needle_meas.write(kNeedleMeas);
  EXPECT_EQ(b.ask("root.MoveToSkin.Approach.AskingGoal"), std::vector<std::string>{"e_goal_ready"});
  EXPECT_TRUE(KDL::Equal(b.goalPair()[0], kNeedleMeas, 1e-12));
  EXPECT_EQ(b.lastFailure(), "");
  const KDL::Frame moved = frame(0.41, -0.09, 0.31, 3.0, 0.1, 0.25);
  b.needle_meas.write(moved);
  EXPECT_EQ(b.ask("root.USPositioned.SearchingNeedle.AskingGoal"), std::vector<std::string>{"e_goal_ready"});
  EXPECT_TRUE(KDL::Equal(b.goalPair()[0], moved, 1e-12));
  EXPECT_TRUE(KDL::Equal(b.desiredPath()[0][0], moved, 1e-12));
}

TEST(PuncturingFrameGenerator, AnswersNoDataForAStateWithoutARowOrWithoutATaskState) {
  Bench b;
  ASSERT_TRUE(b.configure());
  b.needle_meas.write(kNeedleMeas);
  b.us_meas.write(kUsMeas);
  b.generator.call<void>("askCurrentGoal");
  EXPECT_TRUE(b.takeEvents().empty());  // answered in the generator's next step
  b.clock.advance(10ms);
  EXPECT_EQ(b.takeEvents(), std::vector<std::string>{"e_no_data"});
  EXPECT_EQ(b.lastFailure(), "no task state on currentTaskState yet");
  EXPECT_EQ(b.ask("root.WaitCryoCycle"), std::vector<std::string>{"e_no_data"});
  EXPECT_EQ(b.lastFailure(), "task state 'root.WaitCryoCycle' matches no row of " + kApp + "state_table.txt");
  trajectory::MultiAxisPath path;
  EXPECT_EQ(b.desired.read(path), core::FlowStatus::NoData);  // nothing published
}

TEST(PuncturingFrameGenerator, NextNeedleMovesToTheSecondNeedleThenSaysAllNeedlesDone) {
  Bench b;
  ASSERT_TRUE(b.configure());
  b.needle_meas.write(kNeedleMeas);
  b.us_meas.write(kUsMeas);
  const KDL::Frame a = b.plan.preoperative.abdomen_in_task;
  EXPECT_EQ(b.generator.call<int>("currentNeedle"), 0);
  b.generator.call<void>("nextNeedle");
  EXPECT_EQ(b.generator.call<int>("currentNeedle"), 0);  // answered in the generator's next step
  b.clock.advance(10ms);
  EXPECT_EQ(b.takeEvents(), std::vector<std::string>{"e_needle_selected"});
  EXPECT_EQ(b.generator.call<int>("currentNeedle"), 1);
  ASSERT_EQ(b.ask("root.InsertingNeedles.MoveToTumor.AskingGoal"), std::vector<std::string>{"e_goal_ready"});
  EXPECT_TRUE(KDL::Equal(b.goalPair()[0], a * pp::needleTargetPose(b.plan.needles[1]), 1e-12));
  ASSERT_EQ(b.ask("root.MoveToSkin.Approach.AskingGoal"), std::vector<std::string>{"e_goal_ready"});
  EXPECT_TRUE(KDL::Equal(b.goalPair()[1], a * pp::alongZ(b.plan.probes[1].pose, -0.03), 1e-12));
  b.generator.call<void>("nextNeedle");
  b.clock.advance(10ms);
  EXPECT_EQ(b.takeEvents(), std::vector<std::string>{"e_all_needles_done"});
  EXPECT_EQ(b.ask("root.InsertingNeedles.MoveToTumor.AskingGoal"), std::vector<std::string>{"e_no_data"});
  const pp::StateRow* row = b.table.find("root.InsertingNeedles.MoveToTumor.AskingGoal");
  ASSERT_NE(row, nullptr);
  EXPECT_EQ(b.lastFailure(), "task state 'root.InsertingNeedles.MoveToTumor.AskingGoal' (" + kApp + "state_table.txt:" +
                                 std::to_string(row->line) +
                                 "): needle=target: no more needles (all planned needles are done)");
  // A row without plan data still answers: the needle goes to its change pose.
  EXPECT_EQ(b.ask("root.InsertingNeedles.MoveToNeedleChange.AskingGoal"), std::vector<std::string>{"e_goal_ready"});
  b.generator.call<void>("nextNeedle");
  b.clock.advance(10ms);
  EXPECT_EQ(b.takeEvents(), std::vector<std::string>{"e_all_needles_done"});
  EXPECT_EQ(b.generator.call<int>("currentNeedle"), 2);
}

/// Writes `text` to a fresh file in the test's temporary folder and returns its path.
std::string writeFile(const std::string& name, const std::string& text) {
  const auto dir = ::cobra::test_support::scratchPath("cobra_frame_generator_test");
  std::filesystem::create_directories(dir);
  const auto path = dir / name;
  std::ofstream(path) << text;
  return path.string();
}

TEST(PuncturingFrameGenerator, RefusesToConfigureWithBadFilesNamingFileAndLine) {
  {
    Bench b(writeFile("cryo_plan.txt", "# two needles\nneedle n1 entry=-0.02,-0.006,0 target=-0.005,0,-0.058\n"
                                       "needle n2 entry=0.02,0.006,0 tip=0.005,0,-0.062\n"));
    EXPECT_FALSE(b.configure());
    EXPECT_CONTAINS(b.generator.lastError(), "component 'NeedleFrames'");
    EXPECT_CONTAINS(b.generator.lastError(), "cryo_plan.txt:3:");
  }
  {
    Bench b(kScenario + "cryo_plan.txt",
            writeFile("state_table.txt",
                      "pose change xyz=0,0,0.3 rpy=0,0,0\nstate MoveToSkin needle=nowhere probe=hold\n"));
    EXPECT_FALSE(b.configure());
    EXPECT_CONTAINS(b.generator.lastError(), "state_table.txt:2: unknown datum 'nowhere'");
  }
  {
    Bench b;
    b.generator.setProperty("arm", std::string("left"));
    EXPECT_FALSE(b.configure());
    EXPECT_CONTAINS(b.generator.lastError(), "property arm is 'left'; expected needle or probe");
  }
  {
    Bench b;
    b.generator.setProperty("state_table_file", std::string(""));
    EXPECT_FALSE(b.configure());
    EXPECT_CONTAINS(b.generator.lastError(), "property state_table_file is empty");
  }
}

TEST(PuncturingFrameGenerator, AnsweringAskCurrentGoalAllocatesNothingOnceWarm) {
  Bench b;
  ASSERT_TRUE(b.configure());
  b.needle_meas.write(kNeedleMeas);
  b.us_meas.write(kUsMeas);
  // Rows of one goal without then_* or room_for_* (the motion primitives'): a row with checks
  // builds its goalPoses (the planned motions', answered outside the control loop's hot path).
  const char* states[] = {"root.InsertingNeedles.MoveToSkin.Descend.AskingGoal", "root.MoveToSkin.Descend.AskingGoal",
                          "root.InsertingNeedles.MoveToTumor.AskingGoal"};
  for (int warm = 0; warm < 4; ++warm) {  // sizes every slot of the connections
    for (const char* s : states) {
      b.state.write(core::TaskState{s});
      b.generator.askCurrentGoal();
      b.clock.advance(10ms);
    }
  }
  b.takeEvents();
  const long allocations = test_support::allocationsDuring([&] {
    for (const char* s : states) {
      b.state.write(core::TaskState{s});
      b.generator.askCurrentGoal();
      b.clock.advance(10ms);
    }
  });
  EXPECT_EQ(allocations, 0);
  EXPECT_EQ(b.takeEvents(), (std::vector<std::string>{"e_goal_ready", "e_goal_ready", "e_goal_ready"}));
}

namespace navigated {

/// A Frame Generator with plan_source = navigation (its cryo and probe plan files left empty),
/// a navigation's plan and refusal ports connected.
struct NavigatedBench : Bench {
  core::OutputPort<types::PointList> plan_out{"plan_out", "test navigation", "m"};
  core::InputPort<std::string> refusal{"refusal_in", "test navigation", ""};
  NavigatedBench() {
    generator.setProperty("plan_source", "navigation");
    generator.setProperty("cryo_plan_file", "");
    generator.setProperty("US_pose_plan_file", "");
  }
  bool up() {
    if (!configure()) return false;
    core::connectPorts(plan_out, generator.port("plan"));
    core::connectPorts(generator.port("refusal"), refusal, core::ConnPolicy::buffer(4));
    needle_meas.write(kNeedleMeas);
    us_meas.write(kUsMeas);
    return true;
  }
  /// two_needles' plan as points, frame A (m).
  types::PointList points() const {
    types::PointList list;
    for (const pp::PlannedNeedle& n : plan.needles) {
      list.add(n.name + ".entry", "plan", n.entry);
      list.add(n.name + ".target", "plan", n.target);
    }
    return list;
  }
  std::string status() { return generator.call<std::string>("navigationStatus"); }
};

TEST(PuncturingFrameGenerator, NavigatedItTakesThePlanAndRegistrationOnceBothCameAndAnswersTheWait) {
  NavigatedBench b;
  ASSERT_TRUE(b.up());
  b.generator.call<void>("awaitNavigation");
  b.clock.advance(10ms);
  const KDL::Frame registered(KDL::Rotation::RotZ(0.01), b.plan.preoperative.abdomen_in_task.p + KDL::Vector(0.001, 0, 0));
  b.abdomen.write(registered);
  b.clock.advance(10ms);
  EXPECT_TRUE(b.takeEvents().empty()) << "no plan yet";
  EXPECT_EQ(b.ask("root.InsertingNeedles.MoveToTumor.AskingGoal"), std::vector<std::string>{"e_no_data"});
  b.plan_out.write(b.points());
  b.clock.advance(10ms);
  EXPECT_EQ(b.takeEvents(), std::vector<std::string>{"e_navigation_received"});
  EXPECT_CONTAINS(b.status(), "navigation: registration (1.0, 0.0, 100.0 mm; 0.00, -0.00, 0.57 deg), plan of 2 needles: "
                              "n1 entry (-20.0, -6.0, 0.0 mm) target (-5.0, 0.0, -58.0 mm)");
  ASSERT_EQ(b.ask("root.InsertingNeedles.MoveToTumor.AskingGoal"), std::vector<std::string>{"e_goal_ready"});
  EXPECT_TRUE(KDL::Equal(b.goalPair()[0], registered * pp::needleTargetPose(b.plan.needles[0]), 1e-12));
  // The probe plan is probePlan()'s (the shipped us_plan.txt to its 6 decimals).
  ASSERT_EQ(b.ask("root.MoveToSkin.Approach.AskingGoal"), std::vector<std::string>{"e_goal_ready"});
  EXPECT_TRUE(KDL::Equal(b.goalPair()[1], registered * pp::alongZ(b.plan.probes[0].pose, -0.03), 1e-5));
  // Taken once: a later registration or plan changes nothing (the procedure was verified for these).
  b.abdomen.write(frame(0.1, 0.1, 0.1, 0, 0, 1));
  types::PointList other = b.points();
  other.points[1].position = KDL::Vector(0, 0, -0.06);
  b.plan_out.write(other);
  ASSERT_EQ(b.ask("root.InsertingNeedles.MoveToTumor.AskingGoal"), std::vector<std::string>{"e_goal_ready"});
  EXPECT_TRUE(KDL::Equal(b.goalPair()[0], registered * pp::needleTargetPose(b.plan.needles[0]), 1e-12));
  EXPECT_TRUE(KDL::Equal(b.generator.call<KDL::Frame>("plannedTarget", 1),
                         registered * pp::needleTargetPose(b.plan.needles[1]), 1e-12));
  std::string line;
  EXPECT_EQ(b.refusal.read(line), core::FlowStatus::NoData);
}

TEST(PuncturingFrameGenerator, NavigatedARefusedPlanOrNoneInTimeAnswersTheWaitWithWhyOnTheRefusalPort) {
  {
    NavigatedBench b;
    ASSERT_TRUE(b.up());
    types::PointList outside = b.points();
    outside.points[3].position = KDL::Vector(0.005, 0, -0.19);
    b.plan_out.write(outside);
    b.abdomen.write(b.plan.preoperative.abdomen_in_task);
    b.generator.call<void>("awaitNavigation");
    b.clock.advance(10ms);
    EXPECT_EQ(b.takeEvents(), std::vector<std::string>{"e_navigation_refused"});
    const std::string why = "navigation refused: navigation plan:3: needle 'n2': target is 130.1 mm from the tumour "
                            "centre, outside its radius 12.0 mm";
    EXPECT_EQ(b.status(), why);
    std::string line;
    ASSERT_EQ(b.refusal.read(line), core::FlowStatus::NewData);
    EXPECT_EQ(line, why);
    EXPECT_EQ(b.ask("root.InsertingNeedles.MoveToTumor.AskingGoal"), std::vector<std::string>{"e_no_data"});
  }
  {
    NavigatedBench b;
    b.generator.setProperty("navigation_timeout", 0.05);
    ASSERT_TRUE(b.up());
    b.generator.call<void>("awaitNavigation");
    for (int i = 0; i < 5; ++i) b.clock.advance(10ms);
    EXPECT_TRUE(b.takeEvents().empty());
    b.clock.advance(10ms);
    EXPECT_EQ(b.takeEvents(), std::vector<std::string>{"e_navigation_timeout"});
    const std::string why = "navigation timed out: no plan (POINT) and no registration (TRANSFORM) from the navigation "
                            "within 0.05 s";
    EXPECT_EQ(b.status(), why);
    std::string line;
    ASSERT_EQ(b.refusal.read(line), core::FlowStatus::NewData);
    EXPECT_EQ(line, why);
  }
  {  // With files the plan is there: the wait is answered at once.
    Bench b;
    ASSERT_TRUE(b.configure());
    b.generator.call<void>("awaitNavigation");
    b.clock.advance(10ms);
    EXPECT_EQ(b.takeEvents(), std::vector<std::string>{"e_navigation_received"});
  }
}

TEST(PuncturingFrameGenerator, NavigatedWaitingForThePlanAndAnsweringGoalsAfterAllocateNothing) {
  NavigatedBench b;
  ASSERT_TRUE(b.up());
  b.generator.call<void>("awaitNavigation");
  b.abdomen.write(b.plan.preoperative.abdomen_in_task);
  b.clock.advance(10ms);
  // Waiting: the registration read every step, no plan yet.
  EXPECT_EQ(test_support::allocationsDuring([&] {
              for (int i = 0; i < 20; ++i) {
                b.abdomen.write(b.plan.preoperative.abdomen_in_task);
                b.clock.advance(10ms);
              }
            }),
            0);
  b.plan_out.write(b.points());  // taken in the next step (allocates, once)
  b.clock.advance(10ms);
  ASSERT_EQ(b.takeEvents(), std::vector<std::string>{"e_navigation_received"});
  const char* state = "root.InsertingNeedles.MoveToTumor.AskingGoal";
  for (int warm = 0; warm < 4; ++warm) {
    b.state.write(core::TaskState{state});
    b.generator.askCurrentGoal();
    b.clock.advance(10ms);
  }
  b.takeEvents();
  EXPECT_EQ(test_support::allocationsDuring([&] {
              for (int i = 0; i < 5; ++i) {
                b.plan_out.write(b.points());  // later plans and registrations change nothing
                b.state.write(core::TaskState{state});
                b.generator.askCurrentGoal();
                b.clock.advance(10ms);
              }
            }),
            0);
}

}  // namespace navigated

}  // namespace
}  // namespace cobra::components
