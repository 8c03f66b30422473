#include "cobra/components/builtin_packages.hpp"
#include "cobra/deploy/lint.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "cobra/components/signal/gain.hpp"
#include "cobra/components/signal/recorder.hpp"
#include "cobra/components/signal/sine_generator.hpp"
#include "cobra/components/signal/threshold_detector.hpp"
#include "cobra/deploy/configurator.hpp"
#include "test_components.hpp"

using namespace cobra;
using deploy::ConnectionSpec;
using deploy::LintViolation;
using deploy::SourceLocation;
using ::testing::HasSubstr;

namespace {

SourceLocation at(int line) { return {"roles.lua", line}; }

class LintTest : public ::testing::Test {
 protected:
  LintTest() {
    registry_.make<components::SineGenerator>("Sine");
    registry_.make<components::Gain>("Gain");
    registry_.make<components::Recorder>("Rec");
    registry_.make<components::ThresholdDetector>("Det");
    registry_.make<deploy::test::TaskSupervisor>("TaskSup");
    registry_.make<deploy::test::PoseWatchingSupervisor>("Watch");
    registry_.make<deploy::test::ChattyCalculation>("Chatty");
    registry_.make<deploy::test::LeakyDecision>("Leaky");
    registry_.make<deploy::test::AlarmBridge>("Alarm");
    registry_.make<deploy::test::SensorBridge>("Sensor");
  }

  std::vector<LintViolation> lintOne(const char* output, const char* input, int line = 10) {
    return deploy::lint({{output, input, {}, at(line)}}, registry_);
  }

  core::ComponentRegistry registry_;
};

}  // namespace

TEST_F(LintTest, AWellDesignedChainHasNoViolations) {
  const std::vector<ConnectionSpec> chain{{"Sine.out", "Gain.in", {}, at(1)},
                                          {"Gain.out", "Rec.in", {}, at(2)},
                                          {"Gain.out", "Det.in", {}, at(3)},
                                          {"Det.events", "TaskSup.inputEvents", {}, at(4)},
                                          {"Gain.events", "TaskSup.inputEvents", {}, at(5)},
                                          {"TaskSup.outputEvents", "TaskSup.inputEvents", {}, at(6)},
                                          {"Sensor.force", "Gain.in", {}, at(7)},
                                          {"Sensor.contact", "TaskSup.inputEvents", {}, at(8)},
                                          {"Alarm.echo", "Rec.in", {}, at(9)},
                                          {"Rec.events", "Alarm.in", {}, at(10)}};
  const auto violations = deploy::lint(chain, registry_);
  EXPECT_TRUE(violations.empty()) << deploy::toText(violations);
}

TEST_F(LintTest, SupervisionMayReadOnlyLogicData) {
  const auto violations = lintOne("Chatty.pose", "Watch.pose", 12);
  ASSERT_EQ(violations.size(), 1u);
  EXPECT_EQ(violations[0].message,
            "roles.lua:12: Chatty.pose (Calculation) -> Watch.pose (Supervision): a Supervision component may read "
            "only logic data, but KDL.Frame is pure data");
  EXPECT_EQ(violations[0].output, "Chatty.pose");
  EXPECT_EQ(violations[0].input, "Watch.pose");
  EXPECT_EQ(violations[0].output_role, core::Role::Calculation);
  EXPECT_EQ(violations[0].input_role, core::Role::Supervision);
  EXPECT_EQ(violations[0].rule, "a Supervision component may read only logic data");
}

TEST_F(LintTest, CalculationReadsPureDataAndWritesEventsOnlyOnItsEventsPort) {
  auto violations = lintOne("Det.events", "Chatty.trigger");
  ASSERT_EQ(violations.size(), 1u);
  EXPECT_THAT(violations[0].message, HasSubstr("Det.events (Decision) -> Chatty.trigger (Calculation): a Calculation "
                                               "component may read only pure data, but Event is logic data"));
  violations = lintOne("Chatty.status", "TaskSup.inputEvents");
  ASSERT_EQ(violations.size(), 1u);
  EXPECT_THAT(violations[0].message,
              HasSubstr("Chatty.status (Calculation) -> TaskSup.inputEvents (Supervision): a Calculation component may "
                        "write only pure data (and events about its own behaviour on its 'events' port), but Event is "
                        "logic data"));
  EXPECT_TRUE(lintOne("Chatty.events", "TaskSup.inputEvents").empty());
}

TEST_F(LintTest, DecisionReadsPureDataAndWritesLogicData) {
  auto violations = lintOne("Leaky.out", "Gain.in");
  ASSERT_EQ(violations.size(), 1u);
  EXPECT_THAT(violations[0].message, HasSubstr("Leaky.out (Decision) -> Gain.in (Calculation): a Decision component "
                                               "may write only logic data, but double is pure data"));
  violations = lintOne("TaskSup.outputEvents", "Chatty.trigger");
  ASSERT_EQ(violations.size(), 1u) << "Supervision writes logic data: only the reader breaks a rule";
  violations = lintOne("Chatty.status", "Chatty.trigger");
  EXPECT_EQ(violations.size(), 2u) << "both ends can break a rule: " << deploy::toText(violations);
}

TEST_F(LintTest, BridgeWritesTheKindItReads) {
  const auto violations = lintOne("Alarm.alarm", "TaskSup.inputEvents", 20);
  ASSERT_EQ(violations.size(), 1u);
  EXPECT_EQ(violations[0].message,
            "roles.lua:20: Alarm.alarm (Bridge) -> TaskSup.inputEvents (Supervision): a Bridge component writes the "
            "same kind of data it reads, and Alarm reads only pure data, but Event is logic data");
  EXPECT_TRUE(lintOne("Alarm.echo", "Gain.in").empty()) << "pure in, pure out";
  EXPECT_TRUE(lintOne("Sensor.contact", "TaskSup.inputEvents").empty()) << "a Bridge without inputs is a source";
  EXPECT_TRUE(lintOne("TaskSup.outputEvents", "Alarm.in").empty())
      << "a Bridge may read any kind (that the types differ is the deployer's check, not the linter's)";
}

TEST_F(LintTest, EntriesNamingUnknownPortsAreLeftToTheDeployer) {
  EXPECT_TRUE(lintOne("Nobody.out", "Gain.in").empty());
  EXPECT_TRUE(lintOne("Gain.nothing", "Gain.in").empty());
  EXPECT_TRUE(lintOne("Gain", "Gain.in").empty());
}

TEST(LintConfigurator, WarnsByDefaultAndRefusesWhenStrict) {
  for (const bool strict : {false, true}) {
    deploy::Configurator configurator({deploy::ClockMode::Simulation, strict, {}, {}});
    components::addBuiltinPackages(configurator.packages());
    configurator.packages().addBuiltin("deploy_test_parts", deploy::test::registerTestParts);
    configurator.initConfigurator({{"cobra_signal", at(1)}, {"deploy_test_parts", at(2)}},
                                  {{"Gain", "Gain", at(4)}, {"TaskSup", "PoseWatchingSupervisor", at(5)},
                                   {"Sine", "SineGenerator", at(6)}});
    const std::vector<ConnectionSpec> list{{"Sine.out", "Gain.in", {}, at(8)}, {"Gain.out", "TaskSup.level", {}, at(9)}};
    const std::string expected =
        "roles.lua:9: Gain.out (Calculation) -> TaskSup.level (Supervision): a Supervision component may read only "
        "logic data, but double is pure data";
    auto& gain_out = configurator.getReferences().get("Gain").port("out");
    if (!strict) {
      const auto violations = configurator.connectPorts(list);
      ASSERT_EQ(violations.size(), 1u);
      EXPECT_EQ(violations[0].message, expected);
      EXPECT_TRUE(gain_out.connected()) << "warn mode connects anyway";
      ASSERT_EQ(configurator.warnings().size(), 1u);
      EXPECT_EQ(configurator.warnings()[0], "role rule: " + expected);
    } else {
      try {
        (void)configurator.connectPorts(list);
        FAIL() << "strict mode must refuse";
      } catch (const core::Error& e) {
        EXPECT_EQ(std::string(e.what()), "connectPorts: nothing was connected: 1 role rule violation (strict mode "
                                         "refuses them):\n" + expected);
      }
      EXPECT_FALSE(gain_out.connected());
      EXPECT_FALSE(configurator.getReferences().get("Sine").port("out").connected());
    }
  }
}
