// Named deployments and configurations switched at run time on the lockstep clock.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <numbers>
#include <set>
#include <thread>

#include "cobra/components/builtin_packages.hpp"
#include "cobra/components/signal/recorder.hpp"
#include "cobra/deploy/deploy.hpp"
#include "cobra/test_support/test_support.hpp"
#include "test_components.hpp"

using namespace cobra;
using namespace std::chrono_literals;
using deploy::Configurator;
using deploy::SourceLocation;
using ::testing::HasSubstr;
using test_support::messageOf;

namespace {

SourceLocation at(const char* file, int line) { return {file, line}; }

/// Everything observable about a deployment: component states and activities, property
/// values, and connections ("A.out -> B.in (policy)").
struct Snapshot {
  std::map<std::string, std::string> states;
  std::map<std::string, std::string> properties;
  std::set<std::string> connections;
  friend bool operator==(const Snapshot&, const Snapshot&) = default;
};

Snapshot snapshot(const Configurator& configurator) {
  Snapshot s;
  for (const core::ComponentInfo& info : configurator.getReferences().describeAll()) {
    s.states[info.name] = std::string(core::toString(info.state)) + ", " + info.activity;
    for (const auto& p : info.properties) s.properties[info.name + "." + p.name] = p.value;
    for (const auto& p : info.ports)
      if (p.direction == core::PortDirection::Output)
        for (const auto& c : p.connections) s.connections.insert(info.name + "." + p.name + " -> " + c.peer + " (" + c.policy + ")");
  }
  return s;
}

/// Keys whose values differ between `a` and `b`.
std::map<std::string, std::pair<std::string, std::string>> changes(const std::map<std::string, std::string>& a,
                                                                   const std::map<std::string, std::string>& b) {
  std::map<std::string, std::pair<std::string, std::string>> out;
  for (const auto& [key, value] : b)
    if (a.at(key) != value) out[key] = {a.at(key), value};
  return out;
}

std::set<std::string> difference(const std::set<std::string>& a, const std::set<std::string>& b) {
  std::set<std::string> out;
  for (const auto& x : a)
    if (!b.count(x)) out.insert(x);
  return out;
}

/// Three deployments and three configurations of Sine, Gain, Rec, Det, Sup.
class SwitchTest : public ::testing::Test {
 protected:
  explicit SwitchTest(bool strict = false) : configurator_({deploy::ClockMode::Simulation, strict, {}, {}}) {
    components::addBuiltinPackages(configurator_.packages());
    configurator_.packages().addBuiltin("deploy_test_parts", deploy::test::registerTestParts);
    configurator_.initConfigurator({{"cobra_signal", at("app.lua", 1)}, {"deploy_test_parts", at("app.lua", 2)}},
                                   {{"Sine", "SineGenerator", at("app.lua", 4)},
                                    {"Gain", "Gain", at("app.lua", 5)},
                                    {"Rec", "Recorder", at("app.lua", 6)},
                                    {"Det", "ThresholdDetector", at("app.lua", 7)},
                                    {"Sup", "TaskSupervisor", at("app.lua", 8)},
                                    {"F", "Faulty", at("app.lua", 9)},
                                    {"Watch", "PoseWatchingSupervisor", at("app.lua", 10)}});
    auto& set = configurator_.deploymentSet();
    set.addDeployment({"record",
                       at("record.lua", 1),
                       {{"Sine", at("record.lua", 2)}, {"Gain", at("record.lua", 3)}, {"Rec", at("record.lua", 4)}},
                       {{"Sine", 0.001, 90, "ORO_SCHED_RT", at("record.lua", 6)}},
                       {{"Sine.out", "Gain.in", {"data", 1}, at("record.lua", 8)},
                        {"Gain.out", "Rec.in", {"buffer", 16}, at("record.lua", 9)}}});
    set.addDeployment({"detect",
                       at("detect.lua", 1),
                       {{"Sine", at("detect.lua", 2)}, {"Gain", at("detect.lua", 3)}, {"Det", at("detect.lua", 4)},
                        {"Sup", at("detect.lua", 5)}},
                       {{"Sine", 0.001, 90, "ORO_SCHED_RT", at("detect.lua", 7)}},
                       {{"Sine.out", "Gain.in", {"data", 1}, at("detect.lua", 9)},
                        {"Gain.out", "Det.in", {"buffer", 16}, at("detect.lua", 10)},
                        {"Det.events", "Sup.inputEvents", {"buffer", 8}, at("detect.lua", 11)}}});
    set.addDeployment({"fast_record",
                       at("fast.lua", 1),
                       {{"Sine", at("fast.lua", 2)}, {"Gain", at("fast.lua", 3)}, {"Rec", at("fast.lua", 4)}},
                       {{"Sine", 0.0005, 90, "ORO_SCHED_RT", at("fast.lua", 6)}},
                       {{"Sine.out", "Gain.in", {"data", 1}, at("fast.lua", 8)},
                        {"Gain.out", "Rec.in", {"buffer", 32}, at("fast.lua", 9)}}});
    set.addConfiguration({"unit", at("unit.cfg", 1), {{"Gain", "k", "1", at("unit.cfg", 2)}, {"Sine", "frequency", "50", at("unit.cfg", 3)}}});
    set.addConfiguration({"double", at("double.cfg", 1),
                          {{"Gain", "k", "2", at("double.cfg", 2)}, {"Det", "threshold", "1.5", at("double.cfg", 3)}}});
    set.addConfiguration({"quiet", at("quiet.cfg", 1),
                          {{"Gain", "k", "0.25", at("quiet.cfg", 2)},
                           {"Sine", "amplitude", "0.5", at("quiet.cfg", 3)},
                           {"Det", "hysteresis", "0.1", at("quiet.cfg", 4)}}});
  }

  const components::Recorder& rec() const {
    return dynamic_cast<const components::Recorder&>(configurator_.getReferences().get("Rec"));
  }

  Configurator configurator_;
};

class StrictSwitchTest : public SwitchTest {
 protected:
  StrictSwitchTest() : SwitchTest(true) {}
};

}  // namespace

TEST_F(SwitchTest, ConfigurationsChangeExactlyTheirPropertiesAtTheSwitch) {
  configurator_.applyConfiguration("unit");
  (void)configurator_.applyDeployment("record");
  configurator_.clock().advance(10ms);
  const Snapshot before = snapshot(configurator_);
  configurator_.clock().advance(5ms);
  EXPECT_EQ(snapshot(configurator_), before) << "nothing changes without a switch";

  configurator_.applyConfiguration("double");  // between two advances
  const Snapshot after = snapshot(configurator_);
  EXPECT_EQ(changes(before.properties, after.properties),
            (std::map<std::string, std::pair<std::string, std::string>>{{"Gain.k", {"1", "2"}},
                                                                        {"Det.threshold", {"1", "1.5"}}}));
  EXPECT_EQ(after.states, before.states);
  EXPECT_EQ(after.connections, before.connections);
  EXPECT_EQ(configurator_.currentConfiguration(), "double");
  configurator_.clock().advance(5ms);

  // Samples before t = 15 ms were scaled by 1, later ones by 2: the switch fell between steps.
  ASSERT_EQ(rec().samples().size(), 20u);
  for (const auto& sample : rec().samples()) {
    const double k = sample.time < 0.015 - 1e-9 ? 1.0 : 2.0;
    EXPECT_NEAR(sample.value, k * std::sin(2 * std::numbers::pi * 50.0 * sample.time), 1e-12) << sample.time;
  }

  configurator_.applyConfiguration("quiet");
  EXPECT_EQ(changes(after.properties, snapshot(configurator_).properties),
            (std::map<std::string, std::pair<std::string, std::string>>{
                {"Gain.k", {"2", "0.25"}}, {"Sine.amplitude", {"1", "0.5"}}, {"Det.hysteresis", {"0", "0.1"}}}));
}

TEST_F(SwitchTest, DeploymentsChangeExactlyTheRunningSetAndConnectionsAtTheSwitch) {
  configurator_.applyConfiguration("unit");
  (void)configurator_.applyDeployment("record");
  configurator_.clock().advance(10ms);
  const Snapshot record = snapshot(configurator_);
  EXPECT_EQ(record.states.at("Rec"), "Running, lockstep, when triggered");
  EXPECT_EQ(record.states.at("Det"), "PreOperational, lockstep, when triggered") << "the default activity, as in RTT";
  EXPECT_EQ(rec().samples().size(), 10u);

  (void)configurator_.applyDeployment("detect");
  const Snapshot detect = snapshot(configurator_);
  EXPECT_EQ(changes(record.states, detect.states),
            (std::map<std::string, std::pair<std::string, std::string>>{
                {"Rec", {"Running, lockstep, when triggered", "Stopped, lockstep, when triggered"}},
                {"Det", {"PreOperational, lockstep, when triggered", "Running, lockstep, when triggered"}},
                {"Sup", {"PreOperational, lockstep, when triggered", "Running, lockstep, when triggered"}}}));
  EXPECT_EQ(difference(record.connections, detect.connections), std::set<std::string>{"Gain.out -> Rec.in (buffer(16))"});
  EXPECT_EQ(difference(detect.connections, record.connections),
            (std::set<std::string>{"Gain.out -> Det.in (buffer(16))", "Det.events -> Sup.inputEvents (buffer(8))"}));
  EXPECT_EQ(detect.properties, record.properties) << "a deployment does not touch properties";
  configurator_.clock().advance(10ms);
  EXPECT_EQ(rec().samples().size(), 10u) << "the recorder stopped at the switch";
  EXPECT_EQ(configurator_.getReferences().get("Det").updateCount(), 10u) << "the detector started at the switch";

  // Same components, another period and buffer: Sine is restarted with its new activity.
  (void)configurator_.applyDeployment("fast_record");
  const Snapshot fast = snapshot(configurator_);
  EXPECT_EQ(fast.states.at("Sine"), "Running, lockstep every 500 us of simulated time");
  EXPECT_TRUE(fast.connections.count("Gain.out -> Rec.in (buffer(32))"));
  EXPECT_EQ(fast.states.at("Det"), "Stopped, lockstep, when triggered");
  const std::size_t recorded = rec().samples().size();
  configurator_.clock().advance(10ms);
  EXPECT_EQ(rec().samples().size(), recorded + 20) << "2 kHz for 10 ms";

  (void)configurator_.applyDeployment("record");
  const Snapshot again = snapshot(configurator_);
  EXPECT_EQ(again.connections, record.connections);
  EXPECT_EQ(again.states.at("Sine"), record.states.at("Sine")) << "back to 1 ms";
  EXPECT_EQ(again.states.at("Rec"), record.states.at("Rec"));
  EXPECT_EQ(again.states.at("Det"), "Stopped, lockstep, when triggered") << "configured once, stays configured";
  EXPECT_EQ(configurator_.currentDeployment(), "record");
}

TEST_F(SwitchTest, WrongValuesInAConfigurationApplyNothing) {
  configurator_.applyConfiguration("unit");
  configurator_.deploymentSet().addConfiguration({"broken",
                                                  at("broken.cfg", 1),
                                                  {{"Gain", "k", "3", at("broken.cfg", 2)},
                                                   {"Sine", "frequency", "fast", at("broken.cfg", 3)},
                                                   {"Rec", "capacity", "0", at("broken.cfg", 4)},
                                                   {"Gain", "kk", "1", at("broken.cfg", 5)},
                                                   {"Rec", "dropped", "3", at("broken.cfg", 6)}}});
  const Snapshot before = snapshot(configurator_);
  const std::string message = messageOf([&] { configurator_.applyConfiguration("broken"); });
  EXPECT_THAT(message, HasSubstr("configuration 'broken' (broken.cfg:1) has wrong values:"));
  EXPECT_THAT(message, HasSubstr("broken.cfg:3: component 'Sine': property 'frequency' is a double: cannot set it "
                                 "from \"fast\"; expected a number"));
  EXPECT_THAT(message, HasSubstr("broken.cfg:4: component 'Rec': property 'capacity' = 0 is out of range [1, 100000000]"));
  EXPECT_THAT(message, HasSubstr("broken.cfg:5: component 'Gain' has no property 'kk'; did you mean 'k'?"));
  EXPECT_THAT(message, HasSubstr("broken.cfg:6: component 'Rec': property 'dropped' is read-only"));
  EXPECT_THAT(message, HasSubstr("nothing was applied"));
  EXPECT_EQ(snapshot(configurator_), before) << "Gain.k = 3 (valid) must not have been applied";
  EXPECT_EQ(configurator_.currentConfiguration(), "unit");
  EXPECT_THAT(messageOf([&] { configurator_.applyConfiguration("dobule"); }),
              HasSubstr("no configuration named 'dobule'; did you mean 'double'?"));
}

TEST_F(SwitchTest, DeploymentsOfTwoScopesSwitchIndependently) {
  // One scope per "robot": switching one never stops the other's components or connections.
  auto& set = configurator_.deploymentSet();
  set.addDeployment({"a_source", at("a.lua", 1), {{"Sine", at("a.lua", 2)}, {"Gain", at("a.lua", 3)}}, {},
                     {{"Sine.out", "Gain.in", {"data", 1}, at("a.lua", 4)}}, "a"});
  set.addDeployment({"b_both", at("b.lua", 1), {{"Rec", at("b.lua", 2)}, {"Det", at("b.lua", 3)}}, {},
                     {{"Gain.out", "Rec.in", {"buffer", 16}, at("b.lua", 4)},
                      {"Gain.out", "Det.in", {"buffer", 16}, at("b.lua", 5)}}, "b"});
  set.addDeployment({"b_record", at("b.lua", 10), {{"Rec", at("b.lua", 11)}}, {},
                     {{"Gain.out", "Rec.in", {"buffer", 16}, at("b.lua", 12)}}, "b"});
  set.addDeployment({"a_greedy", at("a.lua", 10), {{"Sine", at("a.lua", 11)}, {"Rec", at("a.lua", 12)}}, {}, {}, "a"});
  (void)configurator_.applyDeployment("a_source");
  (void)configurator_.applyDeployment("b_both");
  configurator_.clock().advance(5ms);
  const Snapshot both = snapshot(configurator_);
  EXPECT_TRUE(both.connections.count("Sine.out -> Gain.in (data)"));
  EXPECT_TRUE(both.connections.count("Gain.out -> Det.in (buffer(16))"));

  (void)configurator_.applyDeployment("b_record");
  const Snapshot after = snapshot(configurator_);
  const auto& refs = configurator_.getReferences();
  EXPECT_TRUE(refs.get("Sine").isRunning()) << "scope a is untouched by a switch in scope b";
  EXPECT_TRUE(refs.get("Gain").isRunning());
  EXPECT_TRUE(refs.get("Rec").isRunning());
  EXPECT_FALSE(refs.get("Det").isRunning()) << "b_record does not run Det";
  EXPECT_TRUE(after.connections.count("Sine.out -> Gain.in (data)"));
  EXPECT_FALSE(after.connections.count("Gain.out -> Det.in (buffer(16))"));
  EXPECT_EQ(configurator_.currentDeployment("a"), "a_source");
  EXPECT_EQ(configurator_.currentDeployment("b"), "b_record");
  EXPECT_EQ(configurator_.currentDeployment(), "") << "nothing applied in the default scope";

  const std::string message = messageOf([&] { (void)configurator_.applyDeployment("a_greedy"); });
  EXPECT_THAT(message, HasSubstr("a.lua:12: 'Rec' is run by deployment 'b_record' of scope 'b'; a component belongs to "
                                 "the deployments of one scope"));
  EXPECT_EQ(snapshot(configurator_), after) << "a refused switch changes nothing";
  EXPECT_EQ(configurator_.currentDeployment("a"), "a_source");
}

TEST_F(SwitchTest, InvalidDeploymentChangesNothing) {
  (void)configurator_.applyDeployment("record");
  configurator_.clock().advance(3ms);
  configurator_.deploymentSet().addDeployment({"typo",
                                               at("typo.lua", 1),
                                               {{"Sine", at("typo.lua", 2)}, {"Det", at("typo.lua", 3)}},
                                               {},
                                               {{"Sine.out", "Det.inn", {"data", 1}, at("typo.lua", 5)}}});
  const Snapshot before = snapshot(configurator_);
  EXPECT_THAT(messageOf([&] { (void)configurator_.applyDeployment("typo"); }),
              HasSubstr("deployment 'typo' (typo.lua:1) not applied: typo.lua:5: component 'Det' has no port 'inn'; "
                        "did you mean 'in'?"));
  EXPECT_EQ(snapshot(configurator_), before);
  EXPECT_EQ(configurator_.currentDeployment(), "record");
  EXPECT_THAT(messageOf([&] { (void)configurator_.applyDeployment("recrod"); }),
              HasSubstr("no deployment named 'recrod'; did you mean 'record'?"));
}

TEST_F(SwitchTest, DeploymentFailingWhileApplyingRestoresThePreviousOne) {
  (void)configurator_.applyDeployment("record");
  configurator_.clock().advance(3ms);
  configurator_.getReferences().get("F").setProperty("refuse_start", true);
  configurator_.deploymentSet().addDeployment({"with_faulty",
                                               at("faulty.lua", 1),
                                               {{"Sine", at("faulty.lua", 2)},
                                                {"Gain", at("faulty.lua", 3)},
                                                {"Det", at("faulty.lua", 4)},
                                                {"F", at("faulty.lua", 5)}},
                                               {{"Sine", 0.002, 90, "ORO_SCHED_RT", at("faulty.lua", 7)}},
                                               {{"Sine.out", "Gain.in", {"data", 1}, at("faulty.lua", 9)},
                                                {"Gain.out", "Det.in", {"data", 1}, at("faulty.lua", 10)},
                                                {"Gain.out", "F.in", {"data", 1}, at("faulty.lua", 11)}}});
  const Snapshot before = snapshot(configurator_);
  const std::string message = messageOf([&] { (void)configurator_.applyDeployment("with_faulty"); });
  EXPECT_THAT(message, HasSubstr("deployment 'with_faulty' (faulty.lua:1) not applied: faulty.lua:5: cannot start 'F': "
                                 "component 'F': startHook refused to start; the "));
  EXPECT_THAT(message, HasSubstr("changes made before it were undone"));
  const Snapshot after = snapshot(configurator_);
  EXPECT_EQ(after.connections, before.connections);
  EXPECT_EQ(after.properties, before.properties);
  // Det was configured by the failed switch and cleaned up again; F was configured too.
  EXPECT_EQ(after.states.at("Det").substr(0, 14), "PreOperational");
  EXPECT_EQ(after.states.at("F").substr(0, 14), "PreOperational");
  for (const char* name : {"Sine", "Gain", "Rec"}) EXPECT_EQ(after.states.at(name), before.states.at(name)) << name;
  EXPECT_EQ(configurator_.currentDeployment(), "record");
  const std::size_t recorded = rec().samples().size();
  configurator_.clock().advance(2ms);
  EXPECT_EQ(rec().samples().size(), recorded + 2) << "the previous deployment runs on";
}

namespace {

deploy::DeploymentSpec watchingDeployment() {
  return {"watching",
          at("bad.lua", 1),
          {{"Sine", at("bad.lua", 2)}, {"Gain", at("bad.lua", 3)}, {"Watch", at("bad.lua", 4)}, {"Sup", at("bad.lua", 5)}},
          {},
          {{"Sine.out", "Gain.in", {"data", 1}, at("bad.lua", 7)},
           {"Gain.out", "Watch.level", {"data", 1}, at("bad.lua", 8)},
           {"Sine.events", "Sup.inputEvents", {"data", 1}, at("bad.lua", 9)}}};
}

constexpr const char* kWatchViolation =
    "bad.lua:8: Gain.out (Calculation) -> Watch.level (Supervision): a Supervision component may read only logic "
    "data, but double is pure data";

}  // namespace

TEST_F(SwitchTest, RoleViolationsOfADeploymentAreWarnings) {
  configurator_.deploymentSet().addDeployment(watchingDeployment());
  const auto violations = configurator_.applyDeployment("watching");
  ASSERT_EQ(violations.size(), 1u) << "Sine.events -> Sup.inputEvents is allowed: a component's own events";
  EXPECT_EQ(violations[0].message, kWatchViolation);
  EXPECT_EQ(configurator_.currentDeployment(), "watching");
  EXPECT_TRUE(configurator_.getReferences().get("Watch").isRunning());
  EXPECT_EQ(configurator_.warnings().back(), std::string("role rule: ") + kWatchViolation);
}

TEST_F(StrictSwitchTest, StrictModeRefusesADeploymentBreakingTheRoles) {
  (void)configurator_.applyDeployment("record");
  configurator_.deploymentSet().addDeployment(watchingDeployment());
  const Snapshot before = snapshot(configurator_);
  const std::string message = messageOf([&] { (void)configurator_.applyDeployment("watching"); });
  EXPECT_THAT(message, HasSubstr("deployment 'watching' (bad.lua:1) not applied: 1 role rule violation (strict mode "
                                 "refuses them):\n" + std::string(kWatchViolation)));
  EXPECT_EQ(snapshot(configurator_), before);
  EXPECT_EQ(configurator_.currentDeployment(), "record");
}

TEST(RealTimeSwitch, DeploymentsAndConfigurationsSwitchWhileThreadsRun) {
  Configurator configurator({deploy::ClockMode::RealTime, false, {}, {}});
  components::addBuiltinPackages(configurator.packages());
  configurator.initConfigurator({{"cobra_signal", at("rt.lua", 1)}}, {{"Sine", "SineGenerator", at("rt.lua", 3)},
                                                                      {"Gain", "Gain", at("rt.lua", 4)},
                                                                      {"Rec", "Recorder", at("rt.lua", 5)},
                                                                      {"Det", "ThresholdDetector", at("rt.lua", 6)}});
  auto& set = configurator.deploymentSet();
  set.addDeployment({"record", at("rt.lua", 10),
                     {{"Sine", at("rt.lua", 11)}, {"Gain", at("rt.lua", 12)}, {"Rec", at("rt.lua", 13)}},
                     {{"Sine", 0.001, 0, "ORO_SCHED_OTHER", at("rt.lua", 14)}},
                     {{"Sine.out", "Gain.in", {"buffer", 8}, at("rt.lua", 15)},
                      {"Gain.out", "Rec.in", {"buffer", 8}, at("rt.lua", 16)}}});
  set.addDeployment({"detect", at("rt.lua", 20),
                     {{"Sine", at("rt.lua", 21)}, {"Gain", at("rt.lua", 22)}, {"Det", at("rt.lua", 23)}},
                     {{"Sine", 0.002, 0, "ORO_SCHED_OTHER", at("rt.lua", 24)}},
                     {{"Sine.out", "Gain.in", {"buffer", 8}, at("rt.lua", 25)},
                      {"Gain.out", "Det.in", {"buffer", 8}, at("rt.lua", 26)}}});
  set.addConfiguration({"double", at("double.cfg", 1), {{"Gain", "k", "2", at("double.cfg", 2)}}});
  auto& registry = configurator.getReferences();
  auto waitForUpdates = [](const core::Component& c, std::uint64_t n) {
    // Waits for progress, not for a time: no timing assertion.
    while (c.updateCount() < n) std::this_thread::sleep_for(1ms);
  };

  (void)configurator.applyDeployment("record");
  EXPECT_THAT(registry.get("Sine").activity().describe(), HasSubstr("periodic 1 ms"));
  EXPECT_THAT(registry.get("Rec").activity().describe(), HasSubstr("event-driven"));
  waitForUpdates(registry.get("Rec"), 5);
  configurator.applyConfiguration("double");
  EXPECT_EQ(registry.get("Gain").getProperty<double>("k"), 2.0);

  (void)configurator.applyDeployment("detect");
  EXPECT_EQ(registry.get("Rec").state(), core::State::Stopped);
  EXPECT_FALSE(registry.get("Rec").port("in").connected());
  EXPECT_THAT(registry.get("Sine").activity().describe(), HasSubstr("periodic 2 ms"));
  const std::uint64_t recorded = registry.get("Rec").updateCount();
  waitForUpdates(registry.get("Det"), 5);
  EXPECT_EQ(registry.get("Rec").updateCount(), recorded) << "the recorder stopped at the switch";
}
