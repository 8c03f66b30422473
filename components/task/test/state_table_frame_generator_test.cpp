// The generic StateTableFrameGenerator (package cobra_task) on the lockstep clock: a table of
// fixed poses and holds answered on desiredPoses and goalPoses, e_no_data naming the state, the
// line and the port, a bad table refused with its file:line, and an answer without checks
// allocating nothing.
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

struct Bench {
  std::filesystem::path table =
      std::filesystem::temp_directory_path() / ("cobra_state_table_test_" + std::to_string(::getpid()) + ".txt");
  StateTableFrameGenerator generator{"Frames"};
  core::LockstepClock clock;
  core::OutputPort<core::TaskState> state{"taskState", "", ""};
  core::OutputPort<KDL::Frame> meas1{"m1", "", "m"}, meas2{"m2", "", "m"};
  core::InputPort<trajectory::MultiAxisPath> desired{"desired", "", "m"}, goal{"goal", "", "m"};
  core::InputPort<core::Event> events{"events", "", ""};

  explicit Bench(const std::string& text) {
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
  ~Bench() { std::filesystem::remove(table); }
  std::string ask(const std::string& path) {
    state.write(core::TaskState{std::string_view(path)});
    generator.call<void>("askCurrentGoal");
    clock.advance(10ms);
    std::string said;
    for (core::Event e; events.read(e) == core::FlowStatus::NewData;) said = e.name.str();
    return said;
  }
};

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

}  // namespace
}  // namespace cobra::components
