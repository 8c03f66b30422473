#include "cobra/components/builtin_packages.hpp"
#include "cobra/deploy/configurator.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <numbers>
#include <thread>

#include "cobra/components/signal/recorder.hpp"
#include "cobra/test_support/test_support.hpp"
#include "test_components.hpp"
#include "cobra/test_support/test_support.hpp"

using namespace cobra;
using namespace std::chrono_literals;
using deploy::ActivitySpec;
using deploy::ComponentSpec;
using deploy::ConnectionSpec;
using deploy::Configurator;
using deploy::NameEntry;
using deploy::SourceLocation;
using ::testing::HasSubstr;
using test_support::messageOf;

namespace {

SourceLocation at(int line) { return {"deploy.lua", line}; }

std::vector<NameEntry> names(std::initializer_list<const char*> list, int first_line) {
  std::vector<NameEntry> out;
  for (const char* name : list) out.push_back({name, at(first_line++)});
  return out;
}

/// The thesis' tables for Sine (1 kHz) -> Gain -> Recorder, Gain -> Detector.
struct SignalDeployment {
  std::vector<NameEntry> packages_list{{"cobra_signal", at(2)}};
  std::vector<ComponentSpec> components_list{{"Sine", "SineGenerator", at(5)},
                                             {"Gain", "Gain", at(6)},
                                             {"Rec", "Recorder", at(7)},
                                             {"Det", "ThresholdDetector", at(8)}};
  std::vector<ActivitySpec> activities_list{{"Sine", 0.001, 95, "ORO_SCHED_RT", at(11)},
                                            {"Gain", 0.0, 0, "ORO_SCHED_OTHER", at(12)},
                                            {"Rec", 0.0, 0, "ORO_SCHED_OTHER", at(13)},
                                            {"Det", 0.0, 0, "ORO_SCHED_OTHER", at(14)}};
  std::vector<ConnectionSpec> connections_list{{"Sine.out", "Gain.in", {"data", 1}, at(17)},
                                               {"Gain.out", "Rec.in", {"buffer", 16}, at(18)},
                                               {"Gain.out", "Det.in", {"circular", 16}, at(19)}};
  std::vector<NameEntry> configuration_list = names({"Sine", "Gain", "Rec", "Det"}, 22);
  std::vector<NameEntry> start_list = names({"Rec", "Det", "Gain", "Sine"}, 28);
};

const components::Recorder& recorder(const Configurator& configurator, const std::string& name) {
  return dynamic_cast<const components::Recorder&>(configurator.getReferences().get(name));
}

}  // namespace

TEST(Configurator, ThesisSequenceRunsOnTheLockstepClock) {
  SignalDeployment d;
  Configurator configurator;
  components::addBuiltinPackages(configurator.packages());
  configurator.initConfigurator(d.packages_list, d.components_list, "");
  configurator.setActivities(d.activities_list);
  EXPECT_TRUE(configurator.connectPorts(d.connections_list).empty()) << "the signal chain respects the roles";
  configurator.configureComponents(d.configuration_list);
  configurator.getReferences().get("Gain").setProperty("k", 3.0);
  configurator.getReferences().get("Sine").setProperty("frequency", 50.0);
  configurator.startComponents(d.start_list);
  configurator.addPeers({{"Det", {"Gain", "Rec"}, at(33)}});

  configurator.clock().advance(20ms);

  const auto& samples = recorder(configurator, "Rec").samples();
  ASSERT_EQ(samples.size(), 20u);
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const double t = 1e-3 * static_cast<double>(i);
    EXPECT_DOUBLE_EQ(samples[i].time, t);
    EXPECT_NEAR(samples[i].value, 3.0 * std::sin(2 * std::numbers::pi * 50.0 * t), 1e-12);
  }
  EXPECT_EQ(configurator.getReferences().get("Det").updateCount(), 20u);
  EXPECT_EQ(configurator.peersOf("Det"), (std::vector<std::string>{"Gain", "Rec"}));
  EXPECT_TRUE(configurator.peersOf("Sine").empty());
  EXPECT_TRUE(configurator.warnings().empty()) << "priority 95 is a valid real-time priority";
}

TEST(Configurator, RealTimeModeRunsThreads) {
  SignalDeployment d;
  Configurator configurator({deploy::ClockMode::RealTime, false, {}, {}});
  components::addBuiltinPackages(configurator.packages());
  for (auto& a : d.activities_list) a.scheduler = "ORO_SCHED_OTHER";
  configurator.initConfigurator(d.packages_list, d.components_list);
  configurator.setActivities(d.activities_list);
  (void)configurator.connectPorts(d.connections_list);
  configurator.configureComponents(d.configuration_list);
  configurator.startComponents(d.start_list);
  EXPECT_THAT(configurator.getReferences().get("Sine").activity().describe(), HasSubstr("periodic 1 ms"));
  EXPECT_THAT(configurator.getReferences().get("Gain").activity().describe(), HasSubstr("event-driven"));
  EXPECT_THROW(configurator.clock(), core::Error);
  // Waits for data, not for a time: no timing assertion.
  auto& registry = configurator.getReferences();
  while (registry.get("Det").updateCount() < 5 || registry.get("Rec").updateCount() < 5)
    std::this_thread::sleep_for(1ms);
  configurator.stopComponents(d.start_list);
  // Several triggers may be served by one update, so updates bound the samples only from below.
  EXPECT_GE(recorder(configurator, "Rec").samples().size(), 1u);
  for (const char* name : {"Sine", "Gain", "Rec", "Det"}) EXPECT_EQ(registry.get(name).state(), core::State::Stopped);
}

TEST(Configurator, DuplicateInstanceNameCreatesNothing) {
  Configurator configurator;
  components::addBuiltinPackages(configurator.packages());
  const std::string message = messageOf([&] {
    configurator.initConfigurator({{"cobra_signal", at(2)}},
                                  {{"Sine", "SineGenerator", at(5)}, {"Gain", "Gain", at(6)}, {"Sine", "Gain", at(7)}});
  });
  EXPECT_THAT(message, HasSubstr("deploy.lua:7: duplicate instance name 'Sine': it is already created at deploy.lua:5"));
  EXPECT_TRUE(configurator.getReferences().components().empty());
}

TEST(Configurator, UnknownPackageAndTypeAreReportedWithTheirLine) {
  Configurator configurator;
  components::addBuiltinPackages(configurator.packages());
  EXPECT_THAT(messageOf([&] { configurator.initConfigurator({{"cobra_sgnal", at(2)}}, {}); }),
              HasSubstr("deploy.lua:2: unknown package 'cobra_sgnal'; did you mean 'cobra_signal'?"));
  const std::string message = messageOf([&] {
    configurator.initConfigurator({{"cobra_signal", at(2)}}, {{"Sine", "SineGenerator", at(5)}, {"G", "Gian", at(12)}});
  });
  EXPECT_THAT(message, HasSubstr("deploy.lua:12: unknown component type 'Gian'; did you mean 'Gain'? known types: "));
  EXPECT_TRUE(configurator.getReferences().components().empty()) << "Sine must not have been created";
}

TEST(Configurator, BadConfigurationFileCreatesNothing) {
  const auto folder = ::cobra::test_support::scratchPath("cobra_deploy_bad_configuration");
  std::filesystem::create_directories(folder);
  std::ofstream(folder / "slow.cfg") << "# slow\nGain.k = 0.5\nSine.frequency = fast\n";
  Configurator configurator;
  components::addBuiltinPackages(configurator.packages());
  const std::string message = messageOf([&] {
    configurator.initConfigurator({{"cobra_signal", at(2)}}, {{"Sine", "SineGenerator", at(5)}, {"Gain", "Gain", at(6)}},
                                  folder);
  });
  EXPECT_THAT(message, HasSubstr((folder / "slow.cfg").string() + ":3: component 'Sine': property 'frequency' is a "
                                                                    "double: cannot set it from \"fast\""));
  EXPECT_THAT(message, HasSubstr("the 2 changes made before it were undone"));
  EXPECT_TRUE(configurator.getReferences().components().empty());
  EXPECT_TRUE(configurator.deploymentSet().configurationNames().empty());
}

TEST(Configurator, UnknownComponentAndPortAreReportedWithTheClosestName) {
  SignalDeployment d;
  Configurator configurator;
  components::addBuiltinPackages(configurator.packages());
  configurator.initConfigurator(d.packages_list, d.components_list);
  EXPECT_THAT(messageOf([&] { (void)configurator.connectPorts({{"Sine.out", "Gian.in", {}, at(20)}}); }),
              HasSubstr("deploy.lua:20: no component named 'Gian'; did you mean 'Gain'?"));
  EXPECT_THAT(messageOf([&] { (void)configurator.connectPorts({{"Gain.ouf", "Rec.in", {}, at(21)}}); }),
              HasSubstr("deploy.lua:21: component 'Gain' has no port 'ouf'; did you mean 'out'? known ports of "
                        "Gain: events, in, out"));
  EXPECT_THAT(messageOf([&] { (void)configurator.connectPorts({{"Gain", "Rec.in", {}, at(22)}}); }),
              HasSubstr("deploy.lua:22: 'Gain' is not a port path; write it as \"Component.port\""));
}

TEST(Configurator, TypeMismatchAndOutputToOutputAreRefusedAndNothingIsConnected) {
  SignalDeployment d;
  Configurator configurator;
  components::addBuiltinPackages(configurator.packages());
  configurator.initConfigurator(d.packages_list, d.components_list);
  const auto& sine_out = configurator.getReferences().get("Sine").port("out");
  std::string message = messageOf([&] {
    (void)configurator.connectPorts({{"Sine.out", "Gain.in", {}, at(17)}, {"Det.events", "Rec.in", {}, at(18)}});
  });
  EXPECT_THAT(message, HasSubstr("deploy.lua:18: cannot connect Det.events (Event) to Rec.in (double): the types "
                                 "differ (Event vs double); connect ports of the same type"));
  EXPECT_FALSE(sine_out.connected()) << "entry 17 was valid but the list is all-or-nothing";

  message = messageOf([&] { (void)configurator.connectPorts({{"Sine.out", "Gain.out", {}, at(19)}}); });
  EXPECT_THAT(message, HasSubstr("deploy.lua:19: cannot connect Sine.out (double) to Gain.out (double): Gain.out is "
                                 "an output port; the second port must be an input"));
  message = messageOf([&] { (void)configurator.connectPorts({{"Gain.in", "Rec.in", {}, at(23)}}); });
  EXPECT_THAT(message, HasSubstr("deploy.lua:23: cannot connect Gain.in (double) to Rec.in (double): Gain.in is an "
                                 "input port; the first port must be an output"));
  message = messageOf([&] { (void)configurator.connectPorts({{"Sine.out", "Gain.in", {"buffr", 4}, at(24)}}); });
  EXPECT_THAT(message, HasSubstr("deploy.lua:24: unknown connection policy type 'buffr'"));
  message = messageOf([&] {
    (void)configurator.connectPorts({{"Sine.out", "Gain.in", {}, at(25)}, {"Sine.out", "Gain.in", {}, at(26)}});
  });
  EXPECT_THAT(message, HasSubstr("deploy.lua:26: Sine.out -> Gain.in appears twice in this list"));
  EXPECT_FALSE(sine_out.connected());
}

TEST(Configurator, FailingConfigureHookCleansUpTheComponentsConfiguredBefore) {
  Configurator configurator;
  components::addBuiltinPackages(configurator.packages());
  configurator.packages().addBuiltin("deploy_test_parts", deploy::test::registerTestParts);
  configurator.initConfigurator({{"cobra_signal", at(1)}, {"deploy_test_parts", at(2)}},
                                {{"A", "Gain", at(4)}, {"B", "Faulty", at(5)}, {"F", "Faulty", at(6)}, {"C", "Gain", at(7)}});
  auto& registry = configurator.getReferences();
  registry.get("F").setProperty("refuse_configure", true);
  std::string message = messageOf([&] { configurator.configureComponents(names({"A", "B", "F", "C"}, 30)); });
  EXPECT_THAT(message, HasSubstr("deploy.lua:32: cannot configure 'F': component 'F': configureHook refused the "
                                 "configuration; the 2 changes made before it were undone"));
  for (const char* name : {"A", "B", "F", "C"}) EXPECT_EQ(registry.get(name).state(), core::State::PreOperational) << name;
  EXPECT_EQ(dynamic_cast<deploy::test::Faulty&>(registry.get("B")).cleanups, 1);

  // A hook that throws leaves its component in Exception; the rollback recovers it.
  registry.get("F").setProperty("refuse_configure", false);
  registry.get("F").setProperty("throw_configure", true);
  message = messageOf([&] { configurator.configureComponents(names({"A", "B", "F", "C"}, 30)); });
  EXPECT_THAT(message, HasSubstr("deploy.lua:32: cannot configure 'F': component 'F': configureHook threw: "
                                 "calibration file missing (F was recovered to PreOperational)"));
  for (const char* name : {"A", "B", "F", "C"}) EXPECT_EQ(registry.get(name).state(), core::State::PreOperational) << name;

  EXPECT_THAT(messageOf([&] { configurator.configureComponents({{"A", at(40)}, {"Z", at(41)}}); }),
              HasSubstr("deploy.lua:41: no component named 'Z'"));
  EXPECT_EQ(registry.get("A").state(), core::State::PreOperational) << "unknown names are found before configuring";
}

TEST(Configurator, FailingStartStopsTheComponentsStartedBefore) {
  Configurator configurator;
  components::addBuiltinPackages(configurator.packages());
  configurator.packages().addBuiltin("deploy_test_parts", deploy::test::registerTestParts);
  configurator.initConfigurator({{"cobra_signal", at(1)}, {"deploy_test_parts", at(2)}},
                                {{"A", "Gain", at(4)}, {"F", "Faulty", at(5)}, {"C", "Gain", at(6)}});
  auto& registry = configurator.getReferences();
  configurator.configureComponents(names({"A", "F", "C"}, 10));
  registry.get("F").setProperty("refuse_start", true);
  const std::string message = messageOf([&] { configurator.startComponents(names({"A", "F", "C"}, 20)); });
  EXPECT_THAT(message, HasSubstr("deploy.lua:21: cannot start 'F': component 'F': startHook refused to start"));
  for (const char* name : {"A", "F", "C"}) EXPECT_EQ(registry.get(name).state(), core::State::Stopped) << name;
}

TEST(Configurator, ActivitiesAreCheckedBeforeAnyIsSet) {
  SignalDeployment d;
  Configurator configurator;
  components::addBuiltinPackages(configurator.packages());
  configurator.initConfigurator(d.packages_list, d.components_list);
  EXPECT_THAT(messageOf([&] {
                configurator.setActivities({{"Sine", 0.001, 50, "ORO_SCHED_RT", at(11)}, {"Gain", 0.0, 0, "RT", at(12)}});
              }),
              HasSubstr("deploy.lua:12: unknown scheduler 'RT'; use \"ORO_SCHED_RT\""));
  EXPECT_EQ(configurator.getReferences().get("Sine").activity().describe(), "lockstep, when triggered")
      << "entry 11 was valid, but the list is all-or-nothing: Sine keeps its default activity";
  EXPECT_THAT(messageOf([&] { configurator.setActivities({{"Sine", -1.0, 50, "ORO_SCHED_RT", at(13)}}); }),
              HasSubstr("deploy.lua:13: activity of 'Sine': period must be a number of seconds >= 0"));
  EXPECT_THAT(messageOf([&] { configurator.setActivities({{"Sine", 0.01, 120, "ORO_SCHED_RT", at(14)}}); }),
              HasSubstr("deploy.lua:14: activity of 'Sine': priority 120 is outside 1..99"));

  // Priority 0 with a real-time scheduler (as in the thesis' example) is raised to 1.
  configurator.setActivities({{"Sine", 0.01, 0, "ORO_SCHED_RT", at(15)}});
  ASSERT_EQ(configurator.warnings().size(), 1u);
  EXPECT_THAT(configurator.warnings()[0], HasSubstr("deploy.lua:15: activity of 'Sine': priority 0 is not a real-time "
                                                    "priority; using 1"));
  configurator.configureComponents({{"Sine", at(20)}});
  configurator.startComponents({{"Sine", at(21)}});
  EXPECT_THAT(messageOf([&] { configurator.setActivities({{"Sine", 0.002, 10, "ORO_SCHED_RT", at(16)}}); }),
              HasSubstr("deploy.lua:16: activity of 'Sine': it is Running; stop it before changing its activity"));
}

TEST(Configurator, PeersMustExist) {
  SignalDeployment d;
  Configurator configurator;
  components::addBuiltinPackages(configurator.packages());
  configurator.initConfigurator(d.packages_list, d.components_list);
  EXPECT_THAT(messageOf([&] { configurator.addPeers({{"Det", {"Gain"}, at(30)}, {"Rec", {"Sine", "Gainn"}, at(31)}}); }),
              HasSubstr("deploy.lua:31: no component named 'Gainn'; did you mean 'Gain'?"));
  EXPECT_TRUE(configurator.peersOf("Det").empty()) << "the whole peers_list is refused";
  configurator.addPeers({{"Det", {"Gain", "Gain"}, at(30)}});
  EXPECT_EQ(configurator.peersOf("Det"), std::vector<std::string>{"Gain"});
}

TEST(Configurator, DestructionStopsEverythingStillRunning) {
  SignalDeployment d;
  auto configurator = std::make_unique<Configurator>(deploy::ConfiguratorOptions{deploy::ClockMode::RealTime, false, {}, {}});
  components::addBuiltinPackages(configurator->packages());
  for (auto& a : d.activities_list) a.scheduler = "ORO_SCHED_OTHER";
  configurator->initConfigurator(d.packages_list, d.components_list);
  configurator->setActivities(d.activities_list);
  (void)configurator->connectPorts(d.connections_list);
  configurator->configureComponents(d.configuration_list);
  configurator->startComponents(d.start_list);
  configurator.reset();  // must join every thread without a crash (ASan/TSan runs check it)
  SUCCEED();
}

TEST(Configurator, ActivityOfAComponentFedByARunningThreadChangesSafely) {
  SignalDeployment d;
  Configurator configurator({deploy::ClockMode::RealTime, false, {}, {}});
  components::addBuiltinPackages(configurator.packages());
  configurator.initConfigurator(d.packages_list, d.components_list);
  configurator.setActivities({{"Sine", 0.001, 0, "ORO_SCHED_OTHER", at(11)}});
  (void)configurator.connectPorts(d.connections_list);
  configurator.configureComponents(d.configuration_list);
  configurator.startComponents({{"Sine", at(28)}, {"Rec", at(29)}});
  auto& registry = configurator.getReferences();
  while (registry.get("Sine").updateCount() < 3) std::this_thread::sleep_for(1ms);

  // Sine's thread keeps writing into Gain's event port while Gain's activity is replaced
  // (ThreadSanitizer runs of this test check that the two never race).
  for (int i = 0; i < 20; ++i)
    configurator.setActivities({{"Gain", i % 2 == 0 ? 0.0 : 0.002, 10, "ORO_SCHED_OTHER", at(40 + i)}});
  const auto gain_in = core::describe(registry.get("Gain")).ports;
  const auto in = std::find_if(gain_in.begin(), gain_in.end(), [](const core::PortInfo& p) { return p.name == "in"; });
  ASSERT_EQ(in->connections.size(), 1u);
  EXPECT_EQ(in->connections[0].peer, "Sine.out");
  EXPECT_EQ(in->connections[0].policy, "data") << "the connection is made again with its policy";

  configurator.startComponents({{"Gain", at(30)}});
  EXPECT_THAT(registry.get("Gain").activity().describe(), HasSubstr("periodic 2 ms"));
  while (registry.get("Rec").updateCount() < 3) std::this_thread::sleep_for(1ms);
}
