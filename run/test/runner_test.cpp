// The runner on the small test application (run/test/apps/threshold): it completes when its one
// chart is done, ends at the time limit otherwise, writes the run folder for any application, and
// refuses a `run` table naming an unknown port or one of a type it cannot record, in one line
// with file:line.

#include "cobra/run/runner.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "cobra/core/component.hpp"
#include "cobra/deploy/package_registry.hpp"
#include "cobra/test_support/test_support.hpp"

namespace cobra::run {
namespace {

using test_support::messageOf;

const std::filesystem::path kApp = std::filesystem::path(COBRA_SOURCE_DIR) / "run" / "test" / "apps" / "threshold";

std::string readFile(const std::filesystem::path& path) {
  std::ifstream in(path);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

/// A component whose update fails from 50 ms on (its hook throws: the component goes to Exception).
class Overheating : public core::Component {
 public:
  explicit Overheating(std::string name) : Component(std::move(name), core::Role::Bridge, "fails at 50 ms") {}

 protected:
  void updateHook() override {
    if (now() >= std::chrono::milliseconds(50)) throw std::runtime_error("overheated");
  }
};

RunOptions options(const std::filesystem::path& app = kApp) {
  RunOptions o;
  o.app = app;
  o.time_limit = 5.0;
  return o;
}

TEST(Runner, TheTestApplicationCompletesWhenItsChartIsDoneAndWritesTheRunFolder) {
  RunOptions o = options();
  o.report_folder = ::cobra::test_support::scratchPath("cobra_run_threshold");
  std::filesystem::remove_all(o.report_folder);
  std::vector<std::string> lines;
  o.progress = [&](const std::string& line) { lines.push_back(line); };
  const RunResult r = runApp(o);
  ASSERT_TRUE(r.completed()) << r.reason;
  EXPECT_EQ(r.outcome, Outcome::Completed);
  EXPECT_TRUE(r.reason.empty());
  // sin(2 pi t) > 0.9 from 0.178 s; under 0.85 again from 0.336 s; the chart steps every 10 ms.
  EXPECT_GT(r.duration, 0.33);
  EXPECT_LT(r.duration, 0.36);
  const std::vector<std::string> expected = {"task > root.waiting", "Detector: e_above_threshold", "task > root.high",
                                             "Detector: e_below_threshold", "task > root.done"};
  std::size_t at = 0;
  for (const std::string& line : r.log)
    if (at < expected.size() && line == expected[at]) ++at;
  EXPECT_EQ(at, expected.size()) << "missing in order: " << (at < expected.size() ? expected[at] : "");
  EXPECT_EQ(r.states_entered.at("task"), (std::vector<std::string>{"root.waiting", "root.high", "root.done"}));
  EXPECT_EQ(r.value("threshold crossings").values.size(), 1u);
  ASSERT_EQ(r.value("signal when high").values.size(), 1u);
  EXPECT_GT(r.value("signal when high").values[0], 0.9);
  EXPECT_FALSE(lines.empty());
  EXPECT_CONTAINS(lines.back(), "run ended: completed");
  // The run folder: events, the recorded ports every 10 ms, the report with the declared plot.
  EXPECT_EQ(r.report, o.report_folder / "report.html");
  const std::string events = readFile(o.report_folder / "events.csv");
  EXPECT_CONTAINS(events, ",Detector,e_above_threshold from Detector at 0.179 s,root.waiting\n");
  const std::string signals = readFile(o.report_folder / "signals.csv");
  EXPECT_EQ(signals.rfind("time [s],Sine.out [1],Gain.out [1]\n", 0), 0u);
  EXPECT_EQ(std::count(signals.begin(), signals.end(), '\n'), 1 + 34);  // header, 10 ms .. 340 ms
  const std::string html = readFile(r.report);
  EXPECT_CONTAINS(html, "The signal and its gain");
  EXPECT_CONTAINS(html, "threshold crossings");
  EXPECT_CONTAINS(html, "signals.csv");
}

// The folder is written at the end: one that cannot be written is refused before the run
// (here a path through a regular file, which no user, root included, can make a folder of).
TEST(Runner, WatchedAfterItsEndTheRunStepsOnWithItsOutcomeAndReasonUnchanged) {
  RunOptions o;
  o.app = kApp;
  o.time_limit = 5.0;
  const RunResult at_once = runApp(o);
  ASSERT_TRUE(at_once.completed()) << at_once.reason;
  o.watch_after_end = 0.5;
  const RunResult watched = runApp(o);
  ASSERT_TRUE(watched.completed()) << watched.reason;
  EXPECT_EQ(watched.reason, "");
  EXPECT_NEAR(watched.duration, at_once.duration + 0.5, 0.0015);
  EXPECT_EQ(std::count(watched.log.begin(), watched.log.end(), "run decided: completed"), 1);
}

TEST(Runner, AReportFolderThatCannotBeWrittenIsRefusedBeforeTheRun) {
  const std::filesystem::path file = ::cobra::test_support::scratchPath("cobra_run_report_is_a_file");
  std::filesystem::remove_all(file);
  std::ofstream(file) << "not a folder";
  RunOptions o = options();
  o.report_folder = file / "report";
  const std::string message = messageOf([&] { runApp(o); });
  EXPECT_THAT(message, ::testing::StartsWith("--report " + o.report_folder.string() + ": cannot create the folder ("));
  EXPECT_THAT(message, ::testing::EndsWith("; give a folder that can be written (it is made if missing)"));
  std::filesystem::remove_all(file);
}

// A configuration that cannot be applied (a text where a speed is expected) is refused when the
// chart asks for it: the safe stop says so with the configurator's own line (the file:line, the
// property and what it expects), not only the event's name. The tutorial, copied out of the tree
// (it finds cobra's charts through COBRA_CHARTS), with its slow configuration broken.
TEST(Runner, ARefusedConfigurationEndsTheRunWithTheConfiguratorsLineSayingWhy) {
  const std::filesystem::path app = ::cobra::test_support::scratchPath("cobra_run_bad_configuration");
  std::filesystem::remove_all(app);
  std::filesystem::copy(std::filesystem::path(COBRA_SOURCE_DIR) / "examples" / "07_task", app,
                        std::filesystem::copy_options::recursive);
  const std::filesystem::path slow = app / "configurations" / "slow.lua";
  std::string text = readFile(slow);
  const auto at = text.find("max_vel = 0.05");
  ASSERT_NE(at, std::string::npos) << text;
  text.replace(at, std::string("max_vel = 0.05").size(), "max_vel = \"slow\"");
  std::ofstream(slow) << text;
  RunOptions o = options(app / "07_task.lua");
  o.time_limit = 120.0;
  const RunResult r = runApp(o);
  EXPECT_EQ(r.outcome, Outcome::SafeStop) << r.reason;
  EXPECT_CONTAINS(r.reason, "ConfSup: e_configure_failed_slow at ");
  EXPECT_CONTAINS(r.reason, "; ConfSup asked for configuration 'slow': ");
  EXPECT_CONTAINS(r.reason, slow.string() + ":5: component 'TrajGen': property 'max_vel' is a double: cannot set it "
                            "from \"slow\"; expected a number");
  std::printf("%s\n", r.reason.c_str());
  std::filesystem::remove_all(app);
}

// A waypoint out of the robot's reach: the safe stop quotes the robot's own lastFailure(), with
// the refused pose, why and where the robot holds, not only the event's name. (The straight
// motion toward it is refused near the arm's outstretched singularity, before the pose leaves
// the workspace: the reason is the IK discontinuity there.)
TEST(Runner, AnUnreachableWaypointEndsTheRunWithTheRefusedPoseAndWhy) {
  RunOptions o = options(std::filesystem::path(COBRA_SOURCE_DIR) / "examples" / "07_task" / "07_task.lua");
  o.time_limit = 120.0;
  o.extra_lua = "ScanPath.waypoints = { 2.0, 0.0, 0.15, 0.70710678, 0.70710678, 0, 0 }";  // 2 m: the UR5 reaches 0.85 m
  const RunResult r = runApp(o);
  EXPECT_EQ(r.outcome, Outcome::SafeStop) << r.reason;
  EXPECT_CONTAINS(r.reason, "scan chart stopped safely in root.Scan");
  EXPECT_CONTAINS(r.reason, "UR5.lastFailure(): at ");
  EXPECT_CONTAINS(r.reason, " UR5 refused tool 0's pose (");
  EXPECT_CONTAINS(r.reason, "deg: reachable only on another IK branch, or beyond max_velocity in one step (an IK "
                            "discontinuity); it holds (");
}

TEST(Runner, PastItsTimeLimitTheRunEndsUnfinishedWithTheChartsStates) {
  RunOptions o = options();
  o.time_limit = 0.1;
  const RunResult r = runApp(o);
  EXPECT_FALSE(r.completed());
  EXPECT_EQ(r.outcome, Outcome::TimeLimit);
  EXPECT_NEAR(r.duration, 0.1, 1e-9);
  EXPECT_EQ(r.reason, "time limit 0.100 s reached; charts: task root.waiting; task chart in root.waiting since "
                      "0.001 s; it waits for e_above_threshold; no event arrived there");
}

// A transition waiting for a misspelled event (e_below_treshold) never fires: the run says, once
// the chart has stayed `stall_notice` s in its state, what the state waits for and which events
// arrived there that no transition took, and the time limit's reason says it again.
TEST(Runner, AChartThatStaysInAStateSaysWhatItWaitsForAndWhatArrivedUntaken) {
  const std::filesystem::path app = ::cobra::test_support::scratchPath("cobra_run_misspelled_event");
  std::filesystem::remove_all(app);
  std::filesystem::copy(kApp, app, std::filesystem::copy_options::recursive);
  std::string chart = readFile(app / "threshold_task.lua");
  const auto at = chart.find("events = { 'e_below_threshold' }");
  ASSERT_NE(at, std::string::npos) << chart;
  chart.replace(at, std::string("events = { 'e_below_threshold' }").size(), "events = { 'e_below_treshold' }");
  std::ofstream(app / "threshold_task.lua") << chart;
  RunOptions o = options(app / "threshold.lua");
  o.time_limit = 2.0;
  o.extra_lua = "run.stall_notice = 1";
  std::vector<std::string> said;
  o.progress = [&](const std::string& line) { said.push_back(line); };
  const RunResult r = runApp(o);
  EXPECT_EQ(r.outcome, Outcome::TimeLimit);
  const std::string stall = "task chart in root.high since 0.";
  const std::string why = "; it waits for e_below_treshold; heard there with no change of state: e_below_threshold (Detector at 0.";
  EXPECT_CONTAINS(r.reason, "time limit 2.000 s reached; charts: task root.high; " + stall);
  EXPECT_CONTAINS(r.reason, why);
  // Said once, when the chart had been 1 s in root.high (besides the end's reason).
  const auto notices = std::count_if(said.begin(), said.end(), [&](const std::string& line) {
    return line.find(stall) != std::string::npos && line.find(why) != std::string::npos &&
           line.find("time limit") == std::string::npos;
  });
  EXPECT_EQ(notices, 1) << r.reason;
  std::filesystem::remove_all(app);
}

TEST(Runner, AnInterruptEndsTheRunAfterTheStepWithTheChartsStates) {
  RunOptions o = options();
  const std::atomic<bool> interrupted{true};  // Ctrl-C came before the first step ended
  o.interrupt = &interrupted;
  const RunResult r = runApp(o);
  EXPECT_EQ(r.outcome, Outcome::Interrupted);
  EXPECT_NEAR(r.duration, 0.001, 1e-9);
  EXPECT_EQ(r.reason, "interrupted at 0.001 s; charts: task root.waiting");
  EXPECT_STREQ(toString(r.outcome), "interrupted");
}

TEST(Runner, APacedLockstepRunTakesAtLeastItsSimulatedTimeOverThePaceOnTheWallClock) {
  RunOptions o = options();
  o.time_limit = 0.2;  // s simulated
  o.pace = 2.0;        // simulated s per wall s: at least 0.1 s of wall clock (sleeps never end early)
  const auto start = std::chrono::steady_clock::now();
  const RunResult r = runApp(o);
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_EQ(r.outcome, Outcome::TimeLimit);
  EXPECT_GE(wall, 0.1);
}

TEST(Runner, InRealTimeTheTestApplicationCompletesOnTheWallClock) {
  RunOptions o = options();
  o.realtime = true;  // threaded activities; the time limit only bounds the wait
  const RunResult r = runApp(o);
  ASSERT_TRUE(r.completed()) << r.reason;
  EXPECT_EQ(r.states_entered.at("task").back(), "root.done");
  EXPECT_EQ(r.value("threshold crossings").values.size(), 1u);
}

/// Keeps the chart states of the last step it was shown.
class LastStates : public RunObserver {
 public:
  std::vector<std::string> last;
  void attach(const RunContext&) override {}
  void step(const StepView& now) override {
    last.clear();
    for (const std::string* state : now.states) last.push_back(*state);
  }
  void event(double, const std::string&, const std::string&) override {}
  bool nextInput(std::size_t&) override { return false; }
  std::vector<std::string> finished(const RunResult&) override { return {}; }
};

// On the wall clock one observation may find a chart several states on (it takes them in turn);
// the observer (cobra studio's panel) is shown the last of them too, so the run's final states
// reach it: a door run's panel once showed `release` beside "final door: root.done".
TEST(Runner, OnTheWallClockTheObserverIsShownEachChartsFinalState) {
  LastStates observer;
  RunOptions o = options();
  o.realtime = true;
  o.observer = &observer;
  const RunResult r = runApp(o);
  ASSERT_TRUE(r.completed()) << r.reason;
  ASSERT_EQ(observer.last.size(), r.final_states.size());
  for (std::size_t i = 0; i < observer.last.size(); ++i)
    EXPECT_EQ(observer.last[i], r.final_states[i].second) << r.final_states[i].first;
}

// The run's constructor listens to every component's state changes, then attaches the observer,
// which refuses a bad studio input: the constructor throws with its message, and the components
// (running: the deployment started them), stopped as the deployment is destroyed after that, no
// longer tell the destroyed listener (ComponentErrors leaves them in its destructor). A
// use-after-destroy before; AddressSanitizer's build (./do test --asan) is where it would show.
TEST(Runner, ABadStudioInputRefusesTheRunWithItsMessageAfterItListensToTheRunningComponents) {
  LastStates observer;
  RunOptions o = options(kApp / "bad_studio_input.lua");
  o.observer = &observer;
  const std::string message = messageOf([&] { runApp(o); });
  EXPECT_EQ(message, (kApp / "bad_studio_input.lua").string() +
                         ":6: unknown component 'Nobody' in call Nobody.say (run.studio.inputs.go); known components: "
                         "Sine, Gain, Detector, Recorder, TaskSup");
  // The same deployment again in this process: nothing of the refused run is left behind.
  o.observer = nullptr;
  EXPECT_TRUE(runApp(o).completed());
}

TEST(Runner, AComponentInExceptionEndsTheRunWithItsNameAndError) {
  RunOptions o = options(kApp / "faulty.lua");
  o.add_packages = [](deploy::PackageRegistry& packages) {
    packages.addBuiltin("run_test", [](deploy::PackageBuilder& package) {
      package.component<Overheating>("Overheating", "fails at 50 ms");
    });
  };
  const RunResult r = runApp(o);
  EXPECT_EQ(r.outcome, Outcome::ComponentError);
  EXPECT_NEAR(r.duration, 0.05, 0.0015);
  EXPECT_CONTAINS(r.reason, "component 'Heater' is in Exception: ");
  EXPECT_CONTAINS(r.reason, "overheated");
}

// With a chart that has a safe stop, a component in Exception is a failure like any other: the
// runner tells the charts (e_component_error, its source the component) and the run ends in the
// chart's safe stop, its reason naming the component and its error; the event is in the log.
TEST(Runner, AComponentErrorIsToldToTheChartsWhoseSafeStopNamesTheComponentAndItsError) {
  RunOptions o = options(kApp / "faulty_safe_stop.lua");
  o.add_packages = [](deploy::PackageRegistry& packages) {
    packages.addBuiltin("run_test", [](deploy::PackageBuilder& package) {
      package.component<Overheating>("Overheating", "fails at 50 ms");
    });
  };
  const RunResult r = runApp(o);
  ASSERT_EQ(r.outcome, Outcome::SafeStop) << r.reason;
  EXPECT_EQ(r.reason.rfind("task chart stopped safely in root.working: Heater: e_component_error at", 0), 0u) << r.reason;
  EXPECT_CONTAINS(r.reason, "; component 'Heater' is in Exception: component 'Heater': updateHook threw: overheated");
  EXPECT_EQ(std::count(r.log.begin(), r.log.end(), "Heater: e_component_error"), 1);  // told once
  ASSERT_EQ(r.final_states.size(), 1u);
  EXPECT_EQ(r.final_states[0].second, "root.stopped");
  // Told at the first step after the exception, taken at the chart's next update (10 ms period).
  const auto told = std::find_if(r.events.begin(), r.events.end(),
                                 [](const EventRecord& e) { return e.source == "Heater" && e.event == "e_component_error"; });
  ASSERT_NE(told, r.events.end());
  EXPECT_NEAR(told->time, 0.05, 0.0015);
  EXPECT_LT(r.duration, 0.05 + 0.03);
}

// A chart that cannot react must not hide the error: when no chart reaches its safe stop within
// safe_stop_linger (2 s) of being told, the run ends with the component error, saying so.
TEST(Runner, AComponentErrorNoChartStopsSafelyForEndsTheRunAfterTheLingerAsAComponentError) {
  RunOptions o = options(kApp / "faulty_safe_stop.lua");
  o.before_lua = "deaf = true";
  o.add_packages = [](deploy::PackageRegistry& packages) {
    packages.addBuiltin("run_test", [](deploy::PackageBuilder& package) {
      package.component<Overheating>("Overheating", "fails at 50 ms");
    });
  };
  const RunResult r = runApp(o);
  ASSERT_EQ(r.outcome, Outcome::ComponentError) << r.reason;
  EXPECT_EQ(r.reason.rfind("component 'Heater' is in Exception: component 'Heater': updateHook threw: overheated; no "
                           "chart reached its safe stop within 2.000 s of e_component_error (told at 0.05",
                           0),
            0u)
      << r.reason;
  EXPECT_CONTAINS(r.reason, "): task root.working");
  EXPECT_NEAR(r.duration, 0.05 + 2.0, 0.0015);
}

TEST(Runner, ARecordedPortOfAnotherTypeIsOneLineWithFileLinePortTypeAndWhatIsAccepted) {
  const std::string message = messageOf([] { runApp(options(kApp / "bad_record.lua")); });
  EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  EXPECT_EQ(message.rfind((kApp / "bad_record.lua").string() +
                              ":5: run.record: port Detector.events is a Event, whose CSV columns are text, not "
                              "numbers; types with numeric columns: double, int, bool, vector<double>, ",
                          0),
            0u)
      << message;
}

TEST(Runner, AnUnknownRecordedPortIsOneLineWithTheOutputPortsThereAre) {
  const std::string message = messageOf([] { runApp(options(kApp / "unknown_record.lua")); });
  EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  EXPECT_EQ(message.rfind((kApp / "unknown_record.lua").string() +
                              ":5: run.record: component 'Gain' has no port 'outt'; did you mean 'out'?",
                          0),
            0u)
      << message;
}

TEST(Runner, APlotOfAPortOfAnotherTypeNamesThePlotAndTheType) {
  const std::string message = messageOf([] { runApp(options(kApp / "bad_plot.lua")); });
  EXPECT_EQ(message.rfind((kApp / "bad_plot.lua").string() +
                              ":5: run.plots 'events': port TaskSup.outputEvents is a Event, whose CSV columns are "
                              "text, not numbers; types with numeric columns: double, ",
                          0),
            0u)
      << message;
  EXPECT_CONTAINS(message, "KDL.Frame, KDL.Twist, KDL.Wrench, KDL.JntArray");
}

}  // namespace
}  // namespace cobra::run
