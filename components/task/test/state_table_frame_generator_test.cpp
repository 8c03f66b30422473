// The generic StateTableFrameGenerator (package cobra_task) on the lockstep clock: a table of
// fixed poses and holds answered on desiredPoses and goalPoses, e_no_data naming the state, the
// line and the port, a bad table refused with its file:line, and its step allocating nothing and
// writing nothing to stderr, also when it checks goals or answers e_no_data.
#include "cobra/components/task/state_table_frame_generator.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include <unistd.h>

#include "cobra/core/core.hpp"
#include "cobra/test_support/counting_new.hpp"
#include "cobra/test_support/test_support.hpp"

namespace cobra::components {
namespace {

using namespace std::chrono_literals;

/// A task's Frame Generator with a datum of its own: `cup` (Missing until `cup_ready`) and
/// `next_cup` (NotComing unless `next_coming`).
class CupFrameGenerator final : public StateTableFrameGenerator {
 public:
  explicit CupFrameGenerator(std::string name)
      : StateTableFrameGenerator(std::move(name), "CupFrameGenerator", "a test task's Frame Generator",
                                 task::TableVocabulary{{"arm1", "arm2"}, {"cup", "next_cup"}},
                                 {MeasuredPort{"arm1MeasPose", "arm1's tool, world"},
                                  MeasuredPort{"arm2MeasPose", "arm2's tool, world"}}) {}
  bool cup_ready = true, next_coming = true;

 protected:
  Outcome resolveTaskDatum(const task::Datum& datum, std::size_t, KDL::Frame& pose, const char*& why) override {
    if (datum.name == "cup") {
      if (!cup_ready) {
        why = "no cup yet";
        return Outcome::Missing;
      }
      pose = KDL::Frame(KDL::Vector(0.5, 0, 0));
      return Outcome::Resolved;
    }
    if (!next_coming) {
      why = "no cup after this one";
      return Outcome::NotComing;
    }
    pose = KDL::Frame(KDL::Vector(0.6, 0, 0));
    return Outcome::Resolved;
  }
};

template <class Generator>
struct BenchOf {
  std::filesystem::path table =
      std::filesystem::temp_directory_path() / ("cobra_state_table_test_" + std::to_string(::getpid()) + ".txt");
  Generator generator{"Frames"};
  core::LockstepClock clock;
  core::OutputPort<core::TaskState> state{"taskState", "", ""};
  core::OutputPort<KDL::Frame> meas1{"m1", "", "m"}, meas2{"m2", "", "m"};
  core::InputPort<trajectory::MultiAxisPath> desired{"desired", "", "m"}, goal{"goal", "", "m"};
  core::InputPort<core::Event> events{"events", "", ""};

  explicit BenchOf(const std::string& text) {
    std::ofstream(table) << text;
    generator.setProperty("state_table_file", table.string());
    clock.add(generator, 10ms);
    core::connectPorts(generator.port("events"), events, core::ConnPolicy::buffer(16));
    core::connectPorts(state, generator.port("currentTaskState"));
    core::connectPorts(meas1, generator.port("arm1MeasPose"));
    core::connectPorts(meas2, generator.port("arm2MeasPose"));
    core::connectPorts(generator.port("desiredPoses"), desired);
    core::connectPorts(generator.port("goalPoses"), goal);
  }
  ~BenchOf() { std::filesystem::remove(table); }
  std::string ask(const std::string& path) {
    state.write(core::TaskState{std::string_view(path)});
    generator.template call<void>("askCurrentGoal");
    clock.advance(10ms);
    std::string said;
    for (core::Event e; events.read(e) == core::FlowStatus::NewData;) said = e.name.str();
    return said;
  }
  /// One step answering the task state `path`: true when it answered e_goal_ready. Allocates nothing.
  bool step(std::string_view path) {
    state.write(core::TaskState{path});
    generator.askCurrentGoal();
    clock.advance(10ms);
    bool ready = false;
    for (core::Event e; events.read(e) == core::FlowStatus::NewData;) ready = e.name == "e_goal_ready";
    return ready;
  }
};
using Bench = BenchOf<StateTableFrameGenerator>;

const char* kTable =
    "pose home xyz=0.1,0.2,0.3\n"
    "state Reach arm1=home+0.01 arm2=hold\n"
    "state Back arm1=hold|home arm2=home\n";

TEST(StateTableFrameGenerator, AnswersFixedPosesAndHoldsForTheTaskState) {
  Bench b(kTable);
  ASSERT_TRUE(b.generator.configure());
  ASSERT_TRUE(b.generator.start());
  b.meas1.write(KDL::Frame(KDL::Vector(1, 0, 0)));
  b.meas2.write(KDL::Frame(KDL::Vector(0, 1, 0)));
  ASSERT_EQ(b.ask("root.Reach.AskingGoal"), "e_goal_ready") << b.generator.call<std::string>("lastFailure");
  trajectory::MultiAxisPath path;
  ASSERT_EQ(b.desired.read(path), core::FlowStatus::NewData);
  ASSERT_EQ(path.waypoints().size(), 2u);
  EXPECT_DOUBLE_EQ(path.waypoint(0)[0], 1.0);          // measured arm1
  EXPECT_DOUBLE_EQ(path.waypoint(1)[2], 0.3 + 0.01);   // home moved 1 cm along its z
  EXPECT_DOUBLE_EQ(path.waypoint(1)[7 + 1], 1.0);      // arm2 holds where it was measured
  ASSERT_EQ(b.goal.read(path), core::FlowStatus::NewData);
  EXPECT_EQ(path.waypoints().size(), 1u);
  ASSERT_EQ(b.ask("root.Back.AskingGoal"), "e_goal_ready");
  ASSERT_EQ(b.goal.read(path), core::FlowStatus::NewData);
  EXPECT_EQ(path.waypoints().size(), 2u);  // one waypoint per alternative
}

TEST(StateTableFrameGenerator, MissingDataAnswersNoDataNamingTheStateTheLineAndThePort) {
  Bench b(kTable);
  ASSERT_TRUE(b.generator.configure());
  ASSERT_TRUE(b.generator.start());
  EXPECT_EQ(b.ask("root.Reach"), "e_no_data");
  EXPECT_EQ(b.generator.call<std::string>("lastFailure"),
            "task state 'root.Reach' (" + b.table.string() + ":2): arm2=hold: no pose on arm2MeasPose yet");
  EXPECT_EQ(b.ask("root.Wait"), "e_no_data");
  EXPECT_EQ(b.generator.call<std::string>("lastFailure"),
            "task state 'root.Wait' matches no row of " + b.table.string());
}

TEST(StateTableFrameGenerator, ABadTableIsRefusedWithItsFileAndLine) {
  Bench b("state Reach arm1=cup arm2=hold\n");
  EXPECT_EQ(b.generator.configure().message,
            "component 'Frames': " + b.table.string() + ":1: unknown datum 'cup' (expected hold or a pose defined above)");
}

TEST(StateTableFrameGenerator, AnsweringARowWithoutChecksAllocatesNothing) {
  Bench b(kTable);
  ASSERT_TRUE(b.generator.configure());
  ASSERT_TRUE(b.generator.start());
  b.meas1.write(KDL::Frame::Identity());
  b.meas2.write(KDL::Frame::Identity());
  for (int i = 0; i < 3; ++i) ASSERT_EQ(b.ask("root.Reach"), "e_goal_ready");  // sizes the connections
  const long allocations = test_support::allocationsDuring([&] {
    b.state.write(core::TaskState{"root.Reach"});
    b.generator.askCurrentGoal();
    b.clock.advance(10ms);
  });
  EXPECT_EQ(allocations, 0);
}

TEST(StateTableFrameGenerator, CheckingGoalsAndAnsweringNoDataAllocateNothingAndWriteNothingToStderr) {
  BenchOf<CupFrameGenerator> b(
      "pose home xyz=0.1,0.2,0.3\n"
      "state Reach arm1=cup|home arm2=hold then_arm1=cup+0.01 room_for_arm2=next_cup..next_cup+0.02\n");
  ASSERT_TRUE(b.generator.configure());
  ASSERT_TRUE(b.generator.start());
  b.meas1.write(KDL::Frame::Identity());
  b.meas2.write(KDL::Frame::Identity());
  const auto cycle = [&b](int i) {
    b.generator.cup_ready = i % 4 != 2;   // every 4th answer: e_no_data (a datum missing)
    b.generator.next_coming = i % 4 != 1;  // the room for a motion that will not come is left out
    const bool ready = b.step(i % 4 == 3 ? "root.Wait" : "root.Reach.AskingGoal");  // no row
    return ready == (i % 4 < 2);
  };
  for (int i = 0; i < 12; ++i) ASSERT_TRUE(cycle(i)) << i;  // sizes the slots of the connections
  testing::internal::CaptureStderr();
  bool answered_as_expected = true;
  const long allocations = test_support::allocationsDuring([&] {
    for (int i = 0; i < 200; ++i) answered_as_expected = cycle(i) && answered_as_expected;
  });
  EXPECT_EQ(testing::internal::GetCapturedStderr(), "");
  EXPECT_TRUE(answered_as_expected);
  EXPECT_EQ(allocations, 0);
  // What the step kept of the last failures, read between steps (the operation runs there).
  ASSERT_FALSE(b.step("root.Wait"));
  EXPECT_EQ(b.generator.call<std::string>("lastFailure"), "task state 'root.Wait' matches no row of " + b.table.string());
  b.generator.cup_ready = false;
  ASSERT_FALSE(b.step("root.Reach.AskingGoal"));
  EXPECT_EQ(b.generator.call<std::string>("lastFailure"),
            "task state 'root.Reach.AskingGoal' (" + b.table.string() + ":2): arm1=cup: no cup yet");
  b.generator.cup_ready = true;
  ASSERT_TRUE(b.step("root.Reach.AskingGoal"));
  EXPECT_EQ(b.generator.call<std::string>("lastFailure"), "");
  trajectory::MultiAxisPath goals;
  ASSERT_EQ(b.goal.read(goals), core::FlowStatus::NewData);
  ASSERT_EQ(goals.size(), 2u);  // cup, home
  EXPECT_EQ(goals.waypoint(0).size(), 4 * 14u);  // goal pair, then pair, room's start and end pairs
  EXPECT_DOUBLE_EQ(goals.waypoint(0)[14 + 2], 0.01);  // then_arm1: the cup 1 cm along its z
}

}  // namespace
}  // namespace cobra::components
