// Faults files (run_spec.hpp: readFaults; runner.hpp: RunOptions::faults_file) on the test
// application: a fault on a time, a state entry and an event, each once; a fault the task does
// not recover from ends the run as "fault unhandled"; a fault naming an unknown component or
// operation is one line with faults.lua:line, the name and what exists; a throw makes the named
// component's next update throw (its Exception ends the run).

#include "cobra/run/runner.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>

#include "cobra/test_support/test_support.hpp"

namespace cobra::run {
namespace {

using test_support::messageOf;

const std::filesystem::path kApp = std::filesystem::path(COBRA_SOURCE_DIR) / "run" / "test" / "apps" / "threshold";
const std::filesystem::path kFaults = kApp / "faults";

RunOptions options(const std::string& faults) {
  RunOptions o;
  o.app = kApp;
  o.time_limit = 2.0;
  o.faults_file = kFaults / faults;
  return o;
}

TEST(Faults, AFaultTheTaskDoesNotRecoverFromEndsTheRunAsUnhandledNamingTheFault) {
  const RunResult r = runApp(options("gain_zero.lua"));
  EXPECT_EQ(r.outcome, Outcome::UnhandledFault);
  EXPECT_EQ(r.reason, "time limit 2.000 s reached after fault " + (kFaults / "gain_zero.lua").string() +
                          ":3 (set Gain.k): the task did not recover; charts: task root.waiting");
  EXPECT_EQ(std::count(r.log.begin(), r.log.end(), "fault " + (kFaults / "gain_zero.lua").string() + ":3"), 1);
  EXPECT_EQ(std::count(r.log.begin(), r.log.end(), "Detector: e_above_threshold"), 0);
}

TEST(Faults, AScenarioFoldersFaultsFileIsPlayedUnlessAnotherIsGiven) {
  RunOptions o = options("after_high.lua");
  o.faults_file.clear();
  o.scenario = kApp / "gain_zero_scenario";
  const RunResult from_scenario = runApp(o);
  EXPECT_EQ(from_scenario.outcome, Outcome::UnhandledFault);
  EXPECT_EQ(std::count(from_scenario.log.begin(), from_scenario.log.end(),
                       "fault " + (kApp / "gain_zero_scenario" / "faults.lua").string() + ":3"),
            1);
  o.faults_file = kFaults / "after_high.lua";  // --faults wins over the scenario's
  EXPECT_TRUE(runApp(o).completed());
}

TEST(Faults, StateAndEventTriggersFireOnceEachAfterTheirDelay) {
  const RunResult r = runApp(options("after_high.lua"));
  ASSERT_TRUE(r.completed()) << r.reason;
  const std::string first = "fault " + (kFaults / "after_high.lua").string() + ":4";
  const std::string second = "fault " + (kFaults / "after_high.lua").string() + ":5";
  EXPECT_EQ(std::count(r.log.begin(), r.log.end(), first), 1);
  EXPECT_EQ(std::count(r.log.begin(), r.log.end(), second), 1);
  // The doubled gain keeps the signal above 0.85 until 2 sin(2 pi t) < 0.85: t > 0.43 s.
  EXPECT_GT(r.duration, 0.43);
  const auto high = std::find(r.log.begin(), r.log.end(), "task > root.high");
  const auto doubled = std::find(r.log.begin(), r.log.end(), first);
  const auto below = std::find(r.log.begin(), r.log.end(), "Detector: e_below_threshold");
  const auto offset = std::find(r.log.begin(), r.log.end(), second);
  EXPECT_LT(high, doubled);
  EXPECT_LT(doubled, below);
  EXPECT_LT(below, offset);
}

TEST(Faults, AWrittenPortAndACalledOperationActOnTheDeployment) {
  const RunResult r = runApp(options("write_and_call.lua"));
  ASSERT_TRUE(r.completed()) << r.reason;
  // The spike made the detector fire at 50 ms, long before the sine itself reaches 0.9 (178 ms).
  ASSERT_EQ(r.value("threshold crossings").times.size(), 1u);
  EXPECT_NEAR(r.value("threshold crossings").times[0], 0.05, 0.0015);
  EXPECT_LT(r.duration, 0.1);
  EXPECT_EQ(std::count(r.log.begin(), r.log.end(), "fault " + (kFaults / "write_and_call.lua").string() + ":5"), 1);
}

TEST(Faults, AnOperationThatFailsEndsTheRunWithTheFaultsLineAndTheError) {
  const std::string message = messageOf([] { runApp(options("call_with_bad_args.lua")); });
  EXPECT_EQ(message, (kFaults / "call_with_bad_args.lua").string() +
                         ":3: call Recorder.clear failed at 0.010 s: component 'Recorder': operation 'void clear()' "
                         "expects 0 argument(s), got 1");
}

TEST(Faults, AnUnknownComponentIsOneLineWithFileLineTheNameAndTheComponentsThereAre) {
  const std::string message = messageOf([] { runApp(options("unknown_component.lua")); });
  EXPECT_EQ(message, (kFaults / "unknown_component.lua").string() +
                         ":5: unknown component 'Gian' in set Gian.k; did you mean 'Gain'? known components: "
                         "Sine, Gain, Detector, Recorder, TaskSup");
}

TEST(Faults, AThrowMakesTheComponentsNextUpdateThrowAndTheRunEndsWithItsComponentError) {
  const RunResult r = runApp(options("throw_in_gain.lua"));
  EXPECT_EQ(r.outcome, Outcome::ComponentError);
  const std::string where = (kFaults / "throw_in_gain.lua").string() + ":4";
  EXPECT_EQ(r.reason, "component 'Gain' is in Exception: component 'Gain': updateHook threw: injected fault (" + where + ")");
  EXPECT_EQ(std::count(r.log.begin(), r.log.end(), "fault " + where), 1);
  EXPECT_NEAR(r.duration, 0.05, 0.0015);  // the next step after the fault
}

TEST(Faults, AnEntryPlayedEveryPeriodWithAChancePlaysTheSameRandomPeriodsInEveryRun) {
  const std::string where = (kFaults / "clear_at_random.lua").string() + ":4";
  const auto plays = [&](const RunResult& r) {
    for (const std::string& line : r.log)
      if (line.rfind("fault " + where + " played ", 0) == 0) return std::stoi(line.substr(line.rfind("played ") + 7));
    return 0;
  };
  const RunResult first = runApp(options("clear_at_random.lua"));
  ASSERT_TRUE(first.completed()) << first.reason;
  EXPECT_EQ(std::count(first.log.begin(), first.log.end(), "fault " + where), 1);  // logged once
  // Every 10 ms from 0.05 s to the end (about 30 periods), about one in five played.
  const int periods = static_cast<int>((first.duration - 0.05) / 0.01) + 1;
  EXPECT_GT(periods, 20);
  EXPECT_GT(plays(first), 0);
  EXPECT_LT(plays(first), periods);
  EXPECT_EQ(plays(runApp(options("clear_at_random.lua"))), plays(first));  // seeded
}

TEST(Faults, AChanceWithoutEveryIsRefused) {
  const std::string message = messageOf([] { runApp(options("chance_without_every.lua")); });
  EXPECT_EQ(message, (kFaults / "chance_without_every.lua").string() +
                         ":3: fault 1: `chance` needs `every` (s): each period's play happens with that probability");
}

TEST(Faults, AThrowNamingAnUnknownComponentIsOneLine) {
  const std::string message = messageOf([] { runApp(options("throw_in_gian.lua")); });
  EXPECT_EQ(message, (kFaults / "throw_in_gian.lua").string() +
                         ":3: unknown component 'Gian' in throw in Gian.updateHook; did you mean 'Gain'? known components: "
                         "Sine, Gain, Detector, Recorder, TaskSup");
}

TEST(Faults, AnUnknownOperationIsOneLineWithTheOperationsOfTheComponent) {
  const std::string message = messageOf([] { runApp(options("unknown_operation.lua")); });
  EXPECT_EQ(message.rfind((kFaults / "unknown_operation.lua").string() +
                              ":3: component 'Sine' has no operation 'strat' (call Sine.strat)",
                          0),
            0u)
      << message;
  EXPECT_EQ(message.find('\n'), std::string::npos) << message;
}

// Every name and value of a faults file is checked before the run starts: a state path the chart
// does not have would never fire, a value a property or port cannot take would fail only when the
// fault fires, mid-procedure.
TEST(Faults, AMisspelledStatePathIsOneLineWithTheChartsStatesBeforeTheRun) {
  const std::string message = messageOf([] { runApp(options("misspelled_state.lua")); });
  EXPECT_EQ(message.rfind((kFaults / "misspelled_state.lua").string() +
                              ":3: chart 'task' has no state 'root.hihg' (state = \"task:root.hihg\": the fault would "
                              "never fire); did you mean 'root.high'? known states: root, root.done, root.high, root.waiting",
                          0),
            0u)
      << message;
  EXPECT_EQ(message.find('\n'), std::string::npos) << message;
}

TEST(Faults, AValueThePropertyCannotTakeIsOneLineNamingThePropertyAndWhatItExpects) {
  const std::string message = messageOf([] { runApp(options("bad_set_value.lua")); });
  const std::string at = (kFaults / "bad_set_value.lua").string() + ":3: set Gain.k: ";
  EXPECT_EQ(message.rfind(at, 0), 0u) << message;
  EXPECT_CONTAINS(message, "'k' is a double: cannot set it from \"twice\"; expected a number");
  EXPECT_EQ(message.find('\n'), std::string::npos) << message;
}

TEST(Faults, AValueThePortCannotCarryIsOneLineNamingThePortAndItsLuaForm) {
  const std::string message = messageOf([] { runApp(options("bad_write_value.lua")); });
  EXPECT_EQ(message.rfind((kFaults / "bad_write_value.lua").string() + ":3: write Sine.out: port 'out' carries double: ", 0), 0u)
      << message;
  EXPECT_EQ(message.find('\n'), std::string::npos) << message;
}

TEST(Faults, AMalformedEntryNamesItsLineAndTheFormsThereAre) {
  const std::filesystem::path file = ::cobra::test_support::scratchPath("cobra_run_bad_faults.lua");
  std::ofstream(file) << "return {\n  { on = { time = 1 }, after = 0.5 },\n}\n";
  RunOptions o = options("gain_zero.lua");
  o.faults_file = file;
  EXPECT_CONTAINS(messageOf([&] { runApp(o); }),
                  file.string() + ":2: fault 1: give exactly one of call = \"Comp.operation\", write = { port = , "
                                  "value = }, set = { property = , value = }, lua = \"deployer code\"");
}

TEST(Faults, AStateTriggerOfAnUnknownChartIsRefused) {
  const std::filesystem::path file = ::cobra::test_support::scratchPath("cobra_run_bad_chart.lua");
  std::ofstream(file) << "return {\n  { on = { state = \"tsak:root.high\" }, call = \"Sine.start\" },\n}\n";
  RunOptions o = options("gain_zero.lua");
  o.faults_file = file;
  EXPECT_EQ(messageOf([&] { runApp(o); }), file.string() + ":2: unknown chart 'tsak' in state 'tsak:root.high'; did "
                                                           "you mean 'task'? known charts (run.charts): task");
}

}  // namespace
}  // namespace cobra::run
