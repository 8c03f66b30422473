#include "cobra/components/builtin_packages.hpp"
#include "cobra/deploy/lua_deployer.hpp"

#include <gtest/gtest.h>

#include "cobra/test_support/test_support.hpp"

#include <fstream>
#include <string>

#include "cobra/components/coordination/supervisor.hpp"
#include "cobra/core/core.hpp"

namespace cobra::deploy {
namespace {

using cobra::test_support::messageOf;

using namespace std::chrono_literals;

struct Fixture {
  Fixture() { components::addBuiltinPackages(configurator.packages()); }
  Configurator configurator;
  script::LuaState lua;
  LuaDeployer deployer{configurator, lua};
};

TEST(LuaDeployer, TheThesisConfiguratorListingRuns) {
  Fixture f;
  const std::string path = std::string(COBRA_SOURCE_DIR) + "/apps/examples/configurator_listing.lua";
  f.deployer.runFile(path);
  core::ComponentRegistry& refs = f.configurator.getReferences();
  for (const char* name : {"MotPlan", "TrajGen", "TaskSup", "Reporter"})
    EXPECT_EQ(refs.get(name).state(), core::State::Running) << name;
  EXPECT_EQ(f.configurator.peersOf("TaskSup"), (std::vector<std::string>{"MotPlan", "TrajGen"}));
  EXPECT_EQ(f.configurator.peersOf("Reporter"), std::vector<std::string>{"MotPlan"});
  EXPECT_EQ(refs.get("TrajGen").activity().period(), 1ms);
  EXPECT_EQ(refs.get("MotPlan").activity().period(), 0ms);  // the planner runs when asked
  // getReferences() made every instance reachable by name, as in the thesis' console.
  EXPECT_EQ(f.lua.evaluate("MotPlan:getState()"), "Running");
  EXPECT_EQ(f.lua.evaluate("TaskSup.fsm_path"), std::string(COBRA_SOURCE_DIR) + "/apps/examples/configurator_listing_task.lua");

  // A plan of both tools (needle, probe: x y z [m] qx qy qz qw each) on MotPlan's path port: the
  // task chart has TrajGen generate and follow it, and the Reporter records it.
  const auto& chart = dynamic_cast<const components::Supervisor&>(refs.get("TaskSup"));
  std::vector<std::string> states{std::string(chart.activeState())};
  f.lua.run("MotPlan.plannedPath:write('[[0, 0, 0.3, 0, 0, 0, 1, 0.2, 0, 0.3, 0, 0, 0, 1], "
            "[0.01, 0, 0.3, 0, 0, 0, 1, 0.2, 0.01, 0.3, 0, 0, 0, 1]]')",
            "=test");
  for (int ms = 0; ms < 2000; ++ms) {
    f.configurator.clock().advance(1ms);
    if (states.empty() || states.back() != chart.activeState()) states.emplace_back(chart.activeState());
  }
  EXPECT_EQ(states, (std::vector<std::string>{"root.Idle", "root.Generating", "root.Moving", "root.Idle"}));
  EXPECT_EQ(f.lua.evaluate("TrajGen:status()"), "WaitPath");
  ASSERT_TRUE(refs.get("Reporter").stop());  // the file is complete once stopped
  std::ifstream csv(refs.get("Reporter").getProperty<std::string>("file_path"));
  std::string header, row;
  std::getline(csv, header);
  std::getline(csv, row);
  EXPECT_EQ(header, "time [s],MotPlan.allowedContactDistance [m],MotPlan.primitiveContactDistance [m],"
                    "MotPlan.plannedPath [m],MotPlan.minDistance [m]");
  EXPECT_CONTAINS(row, "0.2, 0.01, 0.3");
}

TEST(LuaDeployer, EntriesGetTheLineTheyAreWrittenOn) {
  Fixture f;
  const std::string code =
      "packages_list = { \"cobra_signal\" }\n"                                     // 1
      "components_list = {\n"                                                      // 2
      "  { peer_name = \"Sine\", component_type = \"SineGenerator\" },\n"          // 3
      "  { peer_name = \"Amp\", component_type = \"Gian\" },\n"                    // 4
      "}\n"                                                                        // 5
      "initConfigurator(packages_list, components_list)\n";                        // 6
  const std::string message = messageOf([&] { f.deployer.run(code, "deploy.lua"); });
  EXPECT_CONTAINS(message, "deploy.lua:4: unknown component type 'Gian'");
  EXPECT_CONTAINS(message, "did you mean 'Gain'");
  EXPECT_EQ(f.configurator.getReferences().components().size(), 0U) << "nothing half-made";
}

TEST(LuaDeployer, ListsPassedByNameAreFoundAtTheirDefinitionNotAnEarlierListWithTheSameNames) {
  Fixture f;
  const std::string code =
      "initConfigurator({ \"cobra_signal\" }, {\n"                                 // 1
      "  { peer_name = \"Sine\", component_type = \"SineGenerator\" },\n"          // 2
      "  { peer_name = \"Amp\", component_type = \"Gain\" } })\n"                  // 3
      "connections_list = {\n"                                                     // 4
      "  { output = \"Sine.out\", input = \"Amp.in\" },\n"                         // 5
      "  { output = \"Sine.out\", input = \"Amp.nope\" },\n"                       // 6
      "}\n"                                                                        // 7
      "connectPorts(connections_list)\n";                                          // 8
  const std::string message = messageOf([&] { f.deployer.run(code, "deploy.lua"); });
  EXPECT_CONTAINS(message, "deploy.lua:6:");
  EXPECT_CONTAINS(message, "Amp");
  EXPECT_CONTAINS(message, "nope");
  EXPECT_FALSE(f.configurator.getReferences().get("Sine").port("out").connected()) << "rolled back";
}

TEST(LuaDeployer, StartListErrorsPointAtTheStartListEvenWhenAnotherListHasTheSameNames) {
  Fixture f;
  const std::string code =
      "initConfigurator({ \"cobra_signal\" }, { { peer_name = \"Sine\", component_type = \"SineGenerator\" } })\n"  // 1
      "configuration_list = { \"Sine\" }\n"                                                                          // 2
      "start_list = {\n"                                                                                             // 3
      "  \"Sine\",\n"                                                                                                // 4
      "}\n"                                                                                                          // 5
      "startComponents(start_list)\n";                                                                               // 6
  const std::string message = messageOf([&] { f.deployer.run(code, "deploy.lua"); });
  EXPECT_CONTAINS(message, "deploy.lua:4:");
  EXPECT_CONTAINS(message, "configure it first");
}

TEST(LuaDeployer, SyntaxErrorsAndBadTablesNameTheFileAndLine) {
  Fixture f;
  EXPECT_CONTAINS(messageOf([&] { f.deployer.run("components_list = {\n  { peer_name = }\n}", "bad.lua"); }),
                  "bad.lua:2:");
  EXPECT_CONTAINS(messageOf([&] { f.deployer.run("\n\ninitConfigurator({ 42 }, {})", "types.lua"); }),
                  "types.lua:3: every entry of packages_list must be a name (string), got number");
  EXPECT_CONTAINS(messageOf([&] { f.deployer.run("setActivities({ { peer_name = 7 } })", "act.lua"); }),
                  "act.lua:1: field 'peer_name' must be a string, got number");
  EXPECT_CONTAINS(messageOf([&] { f.deployer.run("rtt.Variable('int')", "var.lua"); }),
                  "only \"ConnPolicy\" is supported");
}

TEST(LuaDeployer, AnOwnPaceActivityBoundsItsHandOverAgeAndActivityFieldsAreChecked) {
  Fixture f;
  f.deployer.run("initConfigurator({ 'cobra_signal' }, {\n"
                 "  { peer_name = 'Sine', component_type = 'SineGenerator' },\n"
                 "  { peer_name = 'Gain', component_type = 'Gain' },\n"
                 "})\n"
                 "setActivities({ { peer_name = 'Gain', period = 0, own_pace = true, max_age = 0.25 },\n"
                 "                { peer_name = 'Sine', period = 0, own_pace = true } })",
                 "deployment.lua");
  EXPECT_EQ(f.configurator.activityOf("Gain")->max_age, 0.25);
  EXPECT_EQ(f.configurator.activityOf("Gain")->handoverBound(), 0.25);
  EXPECT_EQ(f.configurator.activityOf("Sine")->handoverBound(), ActivitySpec::kDefaultMaxAge) << "the default bound";
  EXPECT_CONTAINS(messageOf([&] { f.deployer.run("setActivities({ { peer_name = 'Sine', period = 0.001, max_agee = 1 } })", "act.lua"); }),
                  "act.lua:1: activity of 'Sine': unknown field 'max_agee'; expected peer_name, period, priority, "
                  "scheduler, own_pace or max_age");
  EXPECT_CONTAINS(messageOf([&] { f.deployer.run("setActivities({ { peer_name = 'Sine', period = 0.001, max_age = 1 } })", "act.lua"); }),
                  "act.lua:1: activity of 'Sine': max_age bounds the hand-over of a component at its own pace; add "
                  "own_pace = true or leave max_age out");
  EXPECT_CONTAINS(messageOf([&] { f.deployer.run("setActivities({ { peer_name = 'Sine', own_pace = true, max_age = -1 } })", "act.lua"); }),
                  "act.lua:1: activity of 'Sine': max_age must be a number of seconds > 0");
}

TEST(LuaDeployer, TheExecutorIsDeclaredOnceAndItsErrorsNameTheFileAndLine) {
  Fixture f;
  f.deployer.run("initConfigurator({ 'cobra_signal' }, {\n"
                 "  { peer_name = 'Sine', component_type = 'SineGenerator' },\n"
                 "  { peer_name = 'Gain', component_type = 'Gain' },\n"
                 "})\n"
                 "setActivities({\n"
                 "  { peer_name = 'Sine', period = 0.002 },\n"
                 "  { peer_name = 'Gain', period = 0, own_pace = true },\n"
                 "})",
                 "deployment.lua");
  EXPECT_TRUE(f.configurator.activityOf("Gain")->own_pace);
  EXPECT_EQ(messageOf([&] { f.deployer.run("\nsetExecutor({ priority = 120 })", "exec.lua"); }),
            "exec.lua:2: setExecutor: priority 120 is outside 1..99 for SCHED_FIFO");
  EXPECT_EQ(messageOf([&] { f.deployer.run("setExecutor({ periode = 0.001 })", "exec.lua"); }),
            "exec.lua:1: setExecutor: unknown field 'periode'; expected period, priority, scheduler, cpu, lock_memory, "
            "on_deadline_miss or safe_stop_after");
  EXPECT_CONTAINS(messageOf([&] { f.deployer.run("setExecutor({ cpu = 4096 })", "exec.lua"); }),
                  "exec.lua:1: setExecutor: cpu 4096 does not exist: this machine has CPUs 0..");
  EXPECT_EQ(messageOf([&] { f.deployer.run("setExecutor({ on_deadline_miss = 'panic' })", "exec.lua"); }),
            "exec.lua:1: setExecutor: on_deadline_miss is \"count\" or \"event\", got \"panic\"");
  EXPECT_EQ(messageOf([&] { f.deployer.run("setExecutor({ own_pace = true })", "exec.lua"); }).substr(0, 49),
            "exec.lua:1: setExecutor: unknown field 'own_pace'");
  EXPECT_EQ(f.configurator.executorMonitor(), nullptr) << "nothing of a refused setExecutor stays";

  // The tick defaults to the periods' greatest common divisor; a given one must divide them all.
  f.deployer.run("\n\nsetExecutor({ period = 0.003, safe_stop_after = 5 })", "exec.lua");
  EXPECT_EQ(messageOf([&] { (void)f.configurator.executorOptions(); }),
            "exec.lua:3: setExecutor: period 0.003 s does not divide the period 0.002 s of 'Sine' (its activity at "
            "deployment.lua:6); give a period that divides every periodic component's, or 0 for their greatest "
            "common divisor");
  EXPECT_EQ(messageOf([&] { f.deployer.run("setExecutor({})", "again.lua"); }),
            "again.lua:1: setExecutor: the executor is set already (exec.lua:3); set it once");
  ASSERT_NE(f.configurator.executorMonitor(), nullptr);
  EXPECT_EQ(f.configurator.executorMonitor()->name(), "Executor");
  EXPECT_EQ(f.configurator.executorMonitor()->state(), core::State::Running);
}

TEST(LuaDeployer, TheExecutorTickIsTheGreatestCommonDivisorOfThePeriods) {
  Fixture f;
  f.deployer.run("initConfigurator({ 'cobra_signal' }, {\n"
                 "  { peer_name = 'Sine', component_type = 'SineGenerator' },\n"
                 "  { peer_name = 'Gain', component_type = 'Gain' },\n"
                 "})\n"
                 "setActivities({ { peer_name = 'Sine', period = 0.004 }, { peer_name = 'Gain', period = 0.006 } })\n"
                 "setExecutor({ on_deadline_miss = 'event', safe_stop_after = 7 })",
                 "deployment.lua");
  const core::ExecutorOptions o = f.configurator.executorOptions();
  EXPECT_EQ(o.period, 2ms);
  EXPECT_EQ(o.priority, 80);
  EXPECT_TRUE(o.policy.emit_event);
  EXPECT_EQ(o.policy.safe_stop_after, 7);
  EXPECT_TRUE(static_cast<bool>(o.on_event)) << "the Executor component's events port carries them";
}

TEST(LuaDeployer, NamedDeploymentsAndConfigurationsSwitchFromLua) {
  Fixture f;
  const std::string code = R"(
initConfigurator({ "cobra_signal" }, {
  { peer_name = "Sine", component_type = "SineGenerator" },
  { peer_name = "Amp", component_type = "Gain" },
  { peer_name = "Rec", component_type = "Recorder" },
})
defineDeployment("open_loop", {
  components = { "Sine", "Rec" },
  activities = { { peer_name = "Sine", period = 0.001 } },
  connections = { { output = "Sine.out", input = "Rec.in", conn_policy = { type = "buffer", size = 8 } } },
})
defineDeployment("amplified", {
  components = { "Sine", "Amp", "Rec" },
  activities = { { peer_name = "Sine", period = 0.001 } },
  connections = {
    { output = "Sine.out", input = "Amp.in" },
    { output = "Amp.out", input = "Rec.in", conn_policy = { type = "buffer", size = 8 } },
  },
})
applyDeployment("open_loop")
)";
  f.deployer.run(code, "switch.lua");
  core::ComponentRegistry& refs = f.configurator.getReferences();
  EXPECT_EQ(refs.get("Amp").state(), core::State::PreOperational);
  EXPECT_EQ(refs.get("Rec").state(), core::State::Running);
  f.configurator.clock().advance(3ms);
  f.deployer.run("applyDeployment('amplified')", "switch2.lua");
  EXPECT_EQ(refs.get("Amp").state(), core::State::Running);
  EXPECT_TRUE(refs.get("Amp").port("out").connectedTo(refs.get("Rec").port("in")));
  EXPECT_FALSE(refs.get("Sine").port("out").connectedTo(refs.get("Rec").port("in")));
  EXPECT_CONTAINS(messageOf([&] { f.deployer.run("applyDeployment('nope')", "switch3.lua"); }), "nope");
  EXPECT_EQ(f.configurator.currentDeployment(), "amplified");
}

TEST(LuaDeployer, DeploymentsMayNameTheirScope) {
  Fixture f;
  f.deployer.run(R"(
initConfigurator({ "cobra_signal" }, {
  { peer_name = "Sine", component_type = "SineGenerator" },
  { peer_name = "Rec", component_type = "Recorder" },
})
defineDeployment("source", { scope = "needle_robot", components = { "Sine" } })
defineDeployment("sink", { scope = "probe_robot", components = { "Rec" } })
applyDeployment("source")
applyDeployment("sink")
)",
                 "scopes.lua");
  EXPECT_EQ(f.configurator.deploymentSet().deployment("source").scope, "needle_robot");
  EXPECT_EQ(f.configurator.currentDeployment("needle_robot"), "source");
  EXPECT_EQ(f.configurator.currentDeployment("probe_robot"), "sink");
  EXPECT_TRUE(f.configurator.getReferences().get("Sine").isRunning()) << "the probe robot's switch left it alone";
  EXPECT_CONTAINS(messageOf([&] { f.deployer.run("defineDeployment('x', { scope = 3 })", "bad_scope.lua"); }),
                  "bad_scope.lua:1: defineDeployment: scope must be a string");
}

TEST(LuaDeployer, ConfigurationFoldersMayHoldLuaTablesAndCfgFiles) {
  Fixture f;
  const std::string folder = std::string(COBRA_SOURCE_DIR) + "/deploy/lua/test/configurations";
  f.deployer.run("initConfigurator({ 'cobra_signal' }, {\n"
                 "  { peer_name = 'Sine', component_type = 'SineGenerator' },\n"
                 "  { peer_name = 'Amp', component_type = 'Gain' } }, '" + folder + "')\n",
                 "init.lua");
  EXPECT_EQ(f.configurator.deploymentSet().configurationNames(), (std::vector<std::string>{"fast", "slow"}));
  const ConfigurationSpec& fast = f.configurator.deploymentSet().configuration("fast");
  ASSERT_EQ(fast.values.size(), 3U);
  EXPECT_EQ(fast.values[0].component, "Amp");  // sorted: Lua's own table order is not reproducible
  EXPECT_EQ(fast.values[0].value, "0.5");
  EXPECT_EQ(fast.values[0].where.line, 7);
  EXPECT_EQ(fast.values[2].property, "frequency");
  EXPECT_EQ(fast.values[2].where.line, 4);
  f.deployer.run("applyConfiguration('fast')", "apply.lua");
  core::ComponentRegistry& refs = f.configurator.getReferences();
  EXPECT_EQ(refs.get("Sine").getProperty<double>("frequency"), 20.0);
  EXPECT_EQ(refs.get("Sine").getProperty<double>("amplitude"), 2.0);
  EXPECT_EQ(refs.get("Amp").getProperty<double>("k"), 0.5);
  f.deployer.run("applyConfiguration('slow')", "apply.lua");
  EXPECT_EQ(refs.get("Amp").getProperty<double>("k"), 4.0);
}

TEST(LuaDeployer, ABadLuaConfigurationNamesItsLineAndCreatesNothing) {
  Fixture f;
  const std::string folder = std::string(COBRA_SOURCE_DIR) + "/deploy/lua/test/configurations_bad";
  const std::string message = messageOf([&] {
    f.deployer.run("initConfigurator({ 'cobra_signal' }, { { peer_name = 'Sine', component_type = 'SineGenerator' } }, '" +
                       folder + "')",
                   "init.lua");
  });
  EXPECT_CONTAINS(message, "broken.lua:3: Sine.frequency must be a number, boolean, string or array of numbers, got function");
  EXPECT_EQ(f.configurator.getReferences().components().size(), 0U);
}

}  // namespace
}  // namespace cobra::deploy
