// The console's interpreter driven line by line (console_pty_test drives the whole program).
#include "console.hpp"

#include <gtest/gtest.h>

#include <sstream>
#include <string>

#include "cobra/components/builtin_packages.hpp"
#include "cobra/components/signal/recorder.hpp"
#include "cobra/core/core.hpp"
#include "cobra/test_support/test_support.hpp"

namespace cobra::tools {
namespace {

using namespace std::chrono_literals;

const std::string kListing = std::string(COBRA_SOURCE_DIR) + "/apps/examples/signal_listing.lua";

/// A Supervision-like sink of events, to check what `event` sends.
class EventSink : public core::Component {
 public:
  explicit EventSink(std::string name) : Component(std::move(name), core::Role::Supervision, "keeps the events it reads") {
    addEventPort(input_events_);
  }
  std::vector<std::string> received;

 protected:
  void updateHook() override {
    core::Event event;
    while (input_events_.read(event) == core::FlowStatus::NewData) received.push_back(event.name.str());
  }

 private:
  core::InputPort<core::Event> input_events_{"inputEvents", "events to react to", ""};
};

struct ConsoleFixture : ::testing::Test {
  ConsoleFixture() { components::addBuiltinPackages(configurator.packages()); }
  deploy::Configurator configurator;  // simulation clock: nothing moves unless the console steps it
  script::LuaState lua;
  deploy::LuaDeployer deployer{configurator, lua};
  std::ostringstream out;
  Console console{configurator, deployer, out};

  /// Runs `line` and returns what it printed.
  std::string run(const std::string& line) {
    out.str("");
    EXPECT_TRUE(console.execute(line));
    return out.str();
  }
  void SetUp() override { run("load " + kListing); }
};

TEST(SplitCommandLine, KeepsBracketsAndQuotesTogetherAndDropsComments) {
  EXPECT_EQ(splitCommandLine("write C.in [1, 2, 3]  # a vector"),
            (std::vector<std::string>{"write", "C.in", "[1, 2, 3]"}));
  EXPECT_EQ(splitCommandLine("set Doc.text \"two words\""), (std::vector<std::string>{"set", "Doc.text", "two words"}));
  EXPECT_TRUE(splitCommandLine("   ").empty());
}

TEST_F(ConsoleFixture, ListsComponentsAndOneComponentsInterface) {
  const std::string top = run("ls");
  for (const char* name : {"MotPlan", "TrajGen", "TaskSup", "Reporter"}) EXPECT_CONTAINS(top, name);
  EXPECT_CONTAINS(top, "Calculation");
  EXPECT_CONTAINS(top, "lockstep every 1 ms");
  const std::string trajgen = run("ls TrajGen");
  EXPECT_CONTAINS(trajgen, "in(event) in : double");
  EXPECT_CONTAINS(trajgen, "-> TaskSup.in (data)");
  EXPECT_CONTAINS(trajgen, "property  k : double = 1");
  EXPECT_CONTAINS(run("ls Reporter"), "operation int count()");
}

TEST_F(ConsoleFixture, CdMakesMembersNameableAloneAndChangesThePrompt) {
  EXPECT_EQ(console.prompt(), "cobra> ");
  run("cd TrajGen");
  EXPECT_EQ(console.prompt(), "cobra:TrajGen> ");
  EXPECT_EQ(run("k"), "k = 1\n");
  EXPECT_EQ(run("set k 2.5"), "TrajGen.k = 2.5\n");
  EXPECT_EQ(configurator.getReferences().get("TrajGen").getProperty<double>("k"), 2.5);
  run("cd ..");
  EXPECT_EQ(console.prompt(), "cobra> ");
  EXPECT_CONTAINS(run("cd Trajgen"), "error: no component named 'Trajgen'");
}

TEST_F(ConsoleFixture, SetsPropertiesAsCommandsOrExpressionsAndRejectsBadValues) {
  EXPECT_EQ(run("TaskSup.threshold = 0.25"), "TaskSup.threshold = 0.25\n");
  EXPECT_EQ(run("get MotPlan.frequency"), "MotPlan.frequency = 1 [Hz]\n");
  EXPECT_CONTAINS(run("set TrajGen.k fast"), "error: ");
  EXPECT_CONTAINS(run("set TrajGen.k fast"), "TrajGen");
  EXPECT_CONTAINS(run("set Reporter.dropped 3"), "property 'dropped' is read-only");
  EXPECT_CONTAINS(run("set Reporter.capacity 0"), "out of range");
  EXPECT_EQ(configurator.getReferences().get("Reporter").getProperty<int>("capacity"), 10000);
}

TEST_F(ConsoleFixture, CallsOperationsWithEitherSyntax) {
  run("step 0.05");
  EXPECT_EQ(run("Reporter.count()"), "Reporter.count() = 5\n");  // MotPlan writes every 10 ms
  EXPECT_EQ(run("call Reporter.clear"), "Reporter.clear()\n");
  EXPECT_EQ(run("call Reporter.count"), "Reporter.count() = 0\n");
  EXPECT_CONTAINS(run("Reporter.count(3)"), "expects 0 argument(s), got 1");
  EXPECT_CONTAINS(run("Reporter.nothing()"), "nothing");
}

TEST_F(ConsoleFixture, ReadsTheLatestSampleOfOutputsAndOfWhatFeedsAnInput) {
  EXPECT_CONTAINS(run("read TrajGen.out"), "no sample yet since the console started watching it; step the clock");
  run("set TrajGen.k 0");
  run("step 0.02");
  EXPECT_EQ(run("read TrajGen.out"), "TrajGen.out = 0\n");
  EXPECT_EQ(run("read TrajGen.out"), "TrajGen.out = 0 (old)\n");
  EXPECT_EQ(run("TaskSup.in"), "TaskSup.in = 0 (old)\n");  // TaskSup.in is fed by TrajGen.out
}

TEST_F(ConsoleFixture, WritesIntoInputPortsOnly) {
  run("set TrajGen.k 2");
  run("stop MotPlan");  // only the console feeds TrajGen now
  run("read TrajGen.out");  // starts watching
  EXPECT_EQ(run("write TrajGen.in 1.5"), "wrote 1.5 to TrajGen.in\n");
  run("step 0.001");
  EXPECT_EQ(run("read TrajGen.out"), "TrajGen.out = 3\n");
  EXPECT_CONTAINS(run("write MotPlan.out 1"),
                  "error: port MotPlan.out is an output port, written by MotPlan; the console writes only into input ports");
  EXPECT_CONTAINS(run("write TrajGen.in [1, 2]"), "error: port console_writer is a double: cannot write \"[1, 2]\"");
}

TEST_F(ConsoleFixture, TracesTheNextSamplesWithTheirTimeOnTheLockstepClock) {
  const std::string trace = run("trace TrajGen.out 3");
  EXPECT_CONTAINS(trace, "t = 0.0010 s  TrajGen.out = 0\n");  // MotPlan writes at 0, TrajGen passes it at 1 ms
  EXPECT_CONTAINS(trace, "t = 0.0110 s  TrajGen.out = 0.0627905195");
  EXPECT_CONTAINS(trace, "t = 0.0210 s  TrajGen.out = 0.1253332335");
  EXPECT_EQ(run("time"), "t = 0.022 s (lockstep simulation clock)\n");
  EXPECT_CONTAINS(run("trace TrajGen.out many"), "trace: COUNT must be a whole number >= 1, got 'many'");
  run("stop MotPlan");
  EXPECT_CONTAINS(run("trace TrajGen.out 2"), "trace stopped after 0 of 2 samples (no more within 10 s)");
}

TEST_F(ConsoleFixture, DrivesLifecyclesAndExplainsRefusals) {
  EXPECT_EQ(run("stop TrajGen"), "TrajGen: Stopped\n");
  EXPECT_EQ(run("cleanup TrajGen"), "TrajGen: PreOperational\n");
  EXPECT_CONTAINS(run("start TrajGen"), "error: cannot start TrajGen: ");
  EXPECT_EQ(run("configure TrajGen"), "TrajGen: Stopped\n");
  EXPECT_EQ(run("start TrajGen"), "TrajGen: Running\n");
  EXPECT_CONTAINS(run("stop"), "error: no current component: name one, or cd into one");
}

TEST_F(ConsoleFixture, SendsEventsToTheCurrentComponentsEventInput) {
  auto& sink = configurator.getReferences().make<EventSink>("Sup");
  configurator.clock().add(sink, 0ns);
  ASSERT_TRUE(sink.configure());
  ASSERT_TRUE(sink.start());
  run("cd Sup");
  EXPECT_EQ(run("event e_go"), "sent e_go to Sup.inputEvents\n");
  EXPECT_EQ(run("event e_stop Sup.inputEvents"), "sent e_stop to Sup.inputEvents\n");
  run("step 0.001");
  EXPECT_EQ(sink.received, (std::vector<std::string>{"e_go", "e_stop"}));
  EXPECT_CONTAINS(run("event e_go TrajGen.in"), "error: port TrajGen.in carries double, not events; use write for data");
  run("cd TrajGen");
  EXPECT_CONTAINS(run("event e_go"), "component 'TrajGen' has no input port of type Event");
}

TEST_F(ConsoleFixture, SwitchesNamedDeploymentsAndConfigurations) {
  deployer.run(R"(
defineDeployment("quiet", { components = { "TrajGen" } })
)",
               "named.lua");
  EXPECT_EQ(run("deployments"), "deployments: quiet; current: (none)\nconfigurations: (none); current: (none)\n");
  EXPECT_EQ(run("apply deployment quiet"), "applied deployment quiet\n");
  EXPECT_CONTAINS(run("deployments"), "current: quiet");
  EXPECT_CONTAINS(run("apply deployment loud"), "error: no deployment named 'loud'");
  EXPECT_CONTAINS(run("apply configuration fast"), "error: no configuration named 'fast'");
  EXPECT_CONTAINS(run("apply something x"), "usage: apply deployment NAME | apply configuration NAME");
}

TEST_F(ConsoleFixture, UnknownCommandsGetASuggestionAndQuitEndsTheSession) {
  EXPECT_CONTAINS(run("trcae TrajGen.out"), "error: unknown command 'trcae'; did you mean 'trace'?");
  EXPECT_CONTAINS(run("step"), "usage: step SECONDS");
  EXPECT_CONTAINS(run("help"), "trace PORT [COUNT]");
  EXPECT_EQ(run("help step"), "step SECONDS\n  advance the lockstep clock (console started with --sim)\n");
  EXPECT_EQ(run("# a comment"), "");
  EXPECT_FALSE(console.execute("quit"));
  EXPECT_FALSE(console.execute("exit"));
}

TEST_F(ConsoleFixture, CompletesCommandsComponentsAndMembers) {
  EXPECT_EQ(console.complete("tr"), (std::vector<std::string>{"trace"}));
  EXPECT_EQ(console.complete("cd T"), (std::vector<std::string>{"TaskSup", "TrajGen"}));
  EXPECT_EQ(console.complete("read Traj"), (std::vector<std::string>{"TrajGen."}));
  EXPECT_EQ(console.complete("read TrajGen."),
            (std::vector<std::string>{"TrajGen.events", "TrajGen.in", "TrajGen.out"}));
  EXPECT_EQ(console.complete("set MotPlan.f"), (std::vector<std::string>{"MotPlan.frequency"}));
  EXPECT_EQ(console.complete("call Reporter."), (std::vector<std::string>{"Reporter.clear", "Reporter.count"}));
  EXPECT_EQ(console.complete("apply d"), (std::vector<std::string>{"deployment"}));
  run("cd TrajGen");
  EXPECT_EQ(console.complete("o"), (std::vector<std::string>{"out"}));
  EXPECT_EQ(console.complete("k"), (std::vector<std::string>{"k"}));
}

TEST_F(ConsoleFixture, LoadReportsTheDeploymentErrorWithFileAndLine) {
  const std::string bad = std::string(COBRA_SOURCE_DIR) + "/tools/cobra/test/unknown_type.lua";
  EXPECT_CONTAINS(run("load " + bad), "unknown_type.lua:4: unknown component type 'Gian'; did you mean 'Gain'");
  EXPECT_EQ(configurator.getReferences().find("Amp"), nullptr);
}

}  // namespace
}  // namespace cobra::tools
