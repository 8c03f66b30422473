// The Robot Visualizer Bridge (studio/src/bridge.cpp) on real runs: the runner's test application
// with a studio table (signals, an input, the recording, the errors naming the file:line) and the
// puncturing application (robots drawn from the planning scene's models: link poses equal forward
// kinematics at the base; the published step allocates nothing).

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include <kdl/frames.hpp>

#include "cobra/planning/robot_adapters.hpp"
#include "cobra/planning/scene.hpp"
#include "cobra/run/runner.hpp"
#include "cobra/studio/bridge.hpp"
#include "cobra/studio/json.hpp"
#include "cobra/test_support/counting_new.hpp"
#include "cobra/test_support/test_support.hpp"
#include "json_numbers.hpp"

namespace cobra::studio {
namespace {

const std::string kSource = COBRA_SOURCE_DIR;
const std::string kApps = kSource + "/studio/test/apps/";

std::string readFile(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// Member `key` of the recording, written compactly (empty when absent).
std::string memberText(const std::string& recording, const char* key) {
  const json::Json whole = json::parse(recording);
  const json::Json* member = json::find(whole, key);
  return member != nullptr ? member->dump() : std::string();
}

std::size_t count(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (auto at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

// Forwards to the bridge, counting the allocations of its steps and giving inputs on request.
class CountingObserver final : public run::RunObserver {
 public:
  explicit CountingObserver(VisualizerBridge& bridge) : bridge_(bridge) {}
  void attach(const run::RunContext& run) override { bridge_.attach(run); }
  void step(const run::StepView& now) override {
    const long before = test_support::newCalls();
    bridge_.step(now);
    allocations += test_support::newCalls() - before;
    ++steps;
    if (press_at > 0.0 && now.t >= press_at) {
      answer = bridge_.input(press);
      press_at = -1.0;
    }
    // The console's user: presses a button once the first chart is in a state containing `when`.
    for (auto& [when, input] : press_in_state)
      if (!when.empty() && now.states[0]->find(when) != std::string::npos) {
        answer = bridge_.input(input);
        when.clear();
      }
  }
  void event(double t, const std::string& source, const std::string& name) override { bridge_.event(t, source, name); }
  bool nextInput(std::size_t& index) override { return bridge_.nextInput(index); }
  std::vector<std::string> finished(const run::RunResult& result) override { return bridge_.finished(result); }

  long allocations = 0, steps = 0;
  double press_at = -1.0;
  std::string press;
  std::vector<std::pair<std::string, std::string>> press_in_state;  // state part -> input
  InputAnswer answer;

 private:
  VisualizerBridge& bridge_;
};

TEST(VisualizerBridge, RecordsThirtyFramesPerSimulatedSecondAndTheEventsIntoTheRunFolder) {
  const auto folder = ::cobra::test_support::scratchPath("cobra_studio_bridge_recording");
  std::filesystem::remove_all(folder);
  VisualizerBridge bridge;
  run::RunOptions options;
  options.app = kApps + "threshold_studio.lua";
  options.report_folder = folder;
  options.observer = &bridge;
  const run::RunResult result = run::runApp(options);
  ASSERT_TRUE(result.completed()) << result.reason;

  const std::string recording = readFile(folder / "studio" / "recording.json");
  const std::string model(memberText(recording, "model"));
  EXPECT_NE(model.find("\"mode\":\"replay\""), std::string::npos) << model;
  // Every state and the transitions leaving them (the chart's description), and in a replay the
  // states the run entered, in order.
  EXPECT_NE(model.find("\"scopes\":[\"\"],"), std::string::npos) << model;
  EXPECT_NE(model.find("\"charts\":[{\"name\":\"task\",\"scope\":\"\",\"states\":[\"root\",\"root.done\",\"root.high\",\"root.waiting\"],"
                       "\"transitions\":[{\"src\":\"root.high\",\"tgt\":\"root.done\",\"events\":[\"e_below_threshold\"],\"guarded\":false},"
                       "{\"src\":\"root.waiting\",\"tgt\":\"root.high\",\"events\":[\"e_above_threshold\"],\"guarded\":false}],"
                       "\"entered\":[\"root.waiting\",\"root.high\",\"root.done\"]}],"),
            std::string::npos) << model;
  EXPECT_NE(model.find("\"signals\":[{\"name\":\"Sine.out\",\"unit\":\"1\"}"), std::string::npos) << model;
  EXPECT_NE(model.find("{\"name\":\"clear_recorder\",\"label\":\"Clear the recorder\",\"target\":\"Recorder.clear\",\"event\":\"\"}"),
            std::string::npos) << model;
  // One frame at the first step (t = 1 ms: k = 0), then one at the first step at or after each k/30 s.
  const std::string frames(memberText(recording, "frames"));
  const std::size_t expected = 1 + static_cast<std::size_t>(std::floor(result.duration * 30.0 + 1e-9));
  EXPECT_EQ(count(frames, "\"type\":\"frame\""), expected) << "duration " << result.duration;
  EXPECT_EQ(count(frames, "\"charts\":{\"task\":\"root.waiting\"}"), 6u);  // 0.001 .. 0.168 s: under 0.9
  const std::string events(memberText(recording, "events"));
  EXPECT_NE(events.find("\"source\":\"Detector\",\"name\":\"e_above_threshold\""), std::string::npos) << events;
  EXPECT_NE(events.find("\"source\":\"task\",\"name\":\"root.done\""), std::string::npos) << events;
  // The page opened from the file system reads the same recording.
  EXPECT_EQ(readFile(folder / "studio" / "recording.js"), "window.COBRA_RECORDING = " + recording + ";\n");
  EXPECT_NE(readFile(folder / "report.html").find("studio/recording.json"), std::string::npos);
  // How the run ended, as `cobra run` says it.
  std::string end(memberText(recording, "end"));
  char line[64];
  std::snprintf(line, sizeof line, "completed in %.3f s", result.duration);
  EXPECT_EQ(run::endLine(result), line);
  EXPECT_NE(end.find(std::string("\"outcome\":\"completed\",\"message\":\"\",\"status\":0,\"line\":\"") + line +
                     "\",\"states\":{\"task\":\"root.done\"}}"),
            std::string::npos) << end;
}

TEST(VisualizerBridge, ARunThatStopsSafelyRecordsItsOutcomeStatusTheLineCobraRunPrintsAndTheFinalStates) {
  const auto folder = ::cobra::test_support::scratchPath("cobra_studio_bridge_safe_stop");
  std::filesystem::remove_all(folder);
  VisualizerBridge bridge;
  run::RunOptions options;
  options.app = kSource + "/apps/puncturing";
  options.faults_file = kSource + "/apps/puncturing/test/faults/planner_fails_again.lua";
  options.report_folder = folder;
  options.observer = &bridge;
  const run::RunResult result = run::runApp(options);
  ASSERT_EQ(result.outcome, run::Outcome::SafeStop) << result.reason;
  EXPECT_EQ(run::exitStatus(result), 1);
  EXPECT_EQ(run::endLine(result), "cobra run: safe stop: " + result.reason);
  const std::string recording = readFile(folder / "studio" / "recording.json");
  const std::string end(memberText(recording, "end"));
  const json::Json end_value = json::parse(end);
  const std::string message = json::stringMember(end_value, "message").value_or("(none)");
  const std::string line = json::stringMember(end_value, "line").value_or("(none)");
  EXPECT_EQ(message, result.reason);
  EXPECT_EQ(line, run::endLine(result));
  EXPECT_EQ(message.rfind("needle chart stopped safely in root.MakeRoomForProbe: NeedlePlanner: e_plan_failed at", 0), 0u) << message;
  EXPECT_NE(end.find("\"outcome\":\"safe stop\""), std::string::npos) << end;
  EXPECT_NE(end.find("\"status\":1,"), std::string::npos) << end;
  EXPECT_NE(end.find("\"states\":{\"needle\":\"root.SafeStop\",\"us\":\"root.SafeStop\"}"), std::string::npos) << end;
}

TEST(VisualizerBridge, PlaysAnInputOfTheConsoleAndRefusesAnUnknownOneNamingTheInputs) {
  VisualizerBridge bridge;
  CountingObserver observer(bridge);
  observer.press_at = 0.05;
  observer.press = "clear_recorder";
  run::RunOptions options;
  options.app = kApps + "threshold_studio.lua";
  options.observer = &observer;
  const run::RunResult result = run::runApp(options);
  ASSERT_TRUE(result.completed()) << result.reason;
  EXPECT_EQ(observer.answer.status, 200) << observer.answer.error;
  EXPECT_NE(std::find(result.log.begin(), result.log.end(), "input clear_recorder"), result.log.end());

  const InputAnswer unknown = bridge.input("needle_mounted");
  EXPECT_EQ(unknown.status, 400);
  EXPECT_EQ(unknown.error, "no input 'needle_mounted': expected one of clear_recorder");
}

TEST(VisualizerBridge, AnUnknownPortOfTheStudioTableNamesTheAppFileLineAndThePort) {
  VisualizerBridge bridge;
  run::RunOptions options;
  options.app = kApps + "bad_port.lua";
  options.observer = &bridge;
  EXPECT_EQ(test_support::messageOf([&] { run::runApp(options); }),
            kApps + "bad_port.lua:6: run.studio.signals: component 'Gain' has no port 'outt'; "
                    "did you mean 'out'? known output ports: events, out");
  bridge.fail("the message");
  int status = 0;
  EXPECT_EQ(bridge.model(status), "{\"error\":\"the message\"}");
  EXPECT_EQ(status, 500);
}

TEST(VisualizerBridge, AnInputCallingAnUnknownOperationNamesTheAppFileLine) {
  VisualizerBridge bridge;
  run::RunOptions options;
  options.app = kApps + "bad_input.lua";
  options.observer = &bridge;
  const std::string message = test_support::messageOf([&] { run::runApp(options); });
  EXPECT_EQ(message.rfind(kApps + "bad_input.lua:6: component 'Recorder' has no operation 'clean'", 0), 0u) << message;
}

std::vector<std::string> interactiveNeedleStates(bool mount) {
  VisualizerBridge bridge;
  CountingObserver surgeon(bridge);
  surgeon.press_in_state = {{"WaitIceballConfig", "iceball_configured"}};
  if (mount) surgeon.press_in_state.emplace_back("WaitNeedleMounted", "needle_mounted");
  run::RunOptions options;
  options.app = kSource + "/apps/puncturing";
  options.interactive = true;  // no surgeon script: the buttons are the surgeon
  options.time_limit = 40.0;   // s
  options.observer = &surgeon;
  const run::RunResult result = run::runApp(options);
  EXPECT_EQ(surgeon.answer.status, 200) << surgeon.answer.error;
  return result.states_entered.at("needle");
}

TEST(VisualizerBridge, InAnInteractivePuncturingRunTheNeedleMountedButtonAdvancesTheNeedleChart) {
  const auto waiting = [](const std::vector<std::string>& states) {
    return std::find(states.begin(), states.end(), "root.InsertingNeedles.WaitNeedleMounted") != states.end();
  };
  const std::vector<std::string> unmounted = interactiveNeedleStates(false);
  ASSERT_TRUE(waiting(unmounted));
  EXPECT_EQ(unmounted.back(), "root.InsertingNeedles.WaitNeedleMounted") << "no script: the chart waits for the button";
  const std::vector<std::string> mounted = interactiveNeedleStates(true);
  ASSERT_TRUE(waiting(mounted));
  EXPECT_NE(mounted.back(), "root.InsertingNeedles.WaitNeedleMounted");
  EXPECT_NE(std::find(mounted.begin(), mounted.end(), "root.InsertingNeedles.MoveToSkin.Approach"), mounted.end());
}

TEST(VisualizerBridge, PuncturingLinksAreTheSceneModelsForwardKinematicsAtTheirBasesAndTheStepAllocatesNothing) {
  VisualizerBridge bridge;  // no recording: the step is the copy into the snapshot alone
  CountingObserver observer(bridge);
  run::RunOptions options;
  options.app = kSource + "/apps/puncturing";
  options.time_limit = 0.5;  // s
  options.observer = &observer;
  const run::RunResult result = run::runApp(options);
  EXPECT_EQ(result.outcome, run::Outcome::TimeLimit);
  EXPECT_EQ(observer.steps, 500);
  EXPECT_EQ(observer.allocations, 0);
  EXPECT_GE(bridge.stats().published, 15);

  int status = 0;
  const std::string model = bridge.model(status);
  ASSERT_EQ(status, 200) << model;
  EXPECT_NE(model.find("{\"name\":\"isur\",\"joints\":[\"q1\",\"q2\",\"q3\",\"q4\",\"q5\",\"q6\",\"q7\",\"q8\"],\"links\":6,\"tools\":1}"),
            std::string::npos) << model;
  EXPECT_NE(model.find("{\"name\":\"needle\",\"group\":\"micro\",\"robot\":\"isur\",\"link\":5,\"shape\":{\"type\":\"cylinder\","
                       "\"size\":[0.0008,0.15]},\"pose\":[-0.075,0,0,"), std::string::npos) << model;
  EXPECT_NE(model.find("{\"name\":\"iceball\",\"kind\":\"sphere\",\"frame\":\"world\"}"), std::string::npos);
  EXPECT_NE(model.find("\"app\":\"puncturing\",\"scenario\":\"two_needles\""), std::string::npos) << model;
  // Live: every state of each chart (no "entered"), the transitions with their events, the scopes
  // and the event each input sends.
  EXPECT_NE(model.find("\"scopes\":[\"needle\",\"probe\"],"), std::string::npos) << model;
  EXPECT_NE(model.find("\"charts\":[{\"name\":\"needle\",\"scope\":\"needle\",\"states\":[\"root\","), std::string::npos) << model;
  EXPECT_NE(model.find("{\"name\":\"us\",\"scope\":\"probe\",\"states\":[\"root\","), std::string::npos) << model;
  EXPECT_NE(model.find("\"root.InsertingNeedles.WaitNeedleMounted\""), std::string::npos) << model;
  EXPECT_NE(model.find("{\"src\":\"root.WaitReaction\",\"tgt\":\"root.NeedleTeleoperation.initial\",\"events\":[\"e_take_over\"],"
                       "\"guarded\":false}"), std::string::npos) << model;
  EXPECT_EQ(model.find("\"entered\""), std::string::npos) << model;
  EXPECT_NE(model.find("\"target\":\"Surgeon.say\",\"event\":\"e_take_over\"}"), std::string::npos) << model;
  EXPECT_NE(model.find("\"failures\":[\"e_forbidden_region\","), std::string::npos) << model;

  std::uint64_t seq = 0;
  std::string frame;
  ASSERT_TRUE(bridge.latestFrame(seq, frame));
  EXPECT_FALSE(bridge.latestFrame(seq, frame)) << "no newer frame than the one taken";
  // Cross-check: the scene file's own robots and models, placed at the scene's bases.
  const planning::SceneDescription scene = planning::loadScene(kSource + "/apps/puncturing/deployment/puncturing.scene");
  planning::RobotModels models = planning::makeRobotModels(scene);
  for (const char* name : {"isur", "ur5"}) {
    const auto at = frame.find(std::string("\"") + name + "\":{\"q\":");
    ASSERT_NE(at, std::string::npos) << frame;
    const std::vector<double> q = numbersAfter(frame, "q", at);
    const std::vector<double> links = numbersAfter(frame, "links", at);
    planning::RobotModel& robot = *models.at(name);
    ASSERT_EQ(q.size(), robot.jointCount());
    ASSERT_EQ(links.size(), 7 * robot.linkCount());
    std::vector<KDL::Frame> frames(robot.linkCount());
    ASSERT_TRUE(robot.linkFramesAt(q, frames));
    const KDL::Frame base = scene.robots[scene.robotIndex(name)].base_in_world;
    for (std::size_t l = 0; l < frames.size(); ++l) {
      const KDL::Frame world = base * frames[l];
      const double* p = &links[7 * l];
      EXPECT_NEAR(p[0], world.p.x(), 1e-6) << name << " link " << l;
      EXPECT_NEAR(p[1], world.p.y(), 1e-6) << name << " link " << l;
      EXPECT_NEAR(p[2], world.p.z(), 1e-6) << name << " link " << l;
      const KDL::Rotation r = KDL::Rotation::Quaternion(p[3], p[4], p[5], p[6]);
      EXPECT_LT(KDL::diff(r, world.M).Norm(), 1e-6) << name << " link " << l;
    }
  }
  EXPECT_NE(frame.find("\"charts\":{\"needle\":\"root."), std::string::npos) << frame;
  // Each scope's deployment and configuration: both robots' configurations are applied in the
  // same step at 1 ms, and each scope shows its own.
  EXPECT_NE(frame.find("\"deployments\":{\"needle\":\"needle_autonomous_planning\",\"probe\":\"probe_autonomous_planning\"},"
                       "\"configurations\":{\"needle\":\"needle_free_motion\",\"probe\":\"probe_free_motion\"}"),
            std::string::npos) << frame;
}

}  // namespace
}  // namespace cobra::studio

namespace cobra::studio {
namespace {

TEST(VisualizerBridge, SuturingWoundEdgesAreTwoLinesOfAVectorPortAndTheStepAllocatesNothing) {
  VisualizerBridge bridge;
  CountingObserver observer(bridge);
  run::RunOptions options;
  options.app = kSource + "/apps/suturing";
  options.time_limit = 0.2;  // s
  options.observer = &observer;
  run::runApp(options);
  EXPECT_EQ(observer.allocations, 0);
  int status = 0;
  const std::string model = bridge.model(status);
  EXPECT_NE(model.find("{\"name\":\"wound_edges\",\"kind\":\"polyline\",\"frame\":\"world\",\"strands\":2}"), std::string::npos) << model;
  EXPECT_NE(model.find("{\"name\":\"isur\",\"joints\":[\"q1\""), std::string::npos) << model;
  std::uint64_t seq = 0;
  std::string frame;
  ASSERT_TRUE(bridge.latestFrame(seq, frame));
  const auto at = frame.find("\"wound_edges\":{\"points\":[[");
  ASSERT_NE(at, std::string::npos) << frame;
  const std::vector<double> xyz = numbersAfter(frame, "points", at);
  EXPECT_GE(xyz.size(), 6u) << "both edges' points";
  EXPECT_LE(xyz.size(), 3u * 400u) << "at most max = 400 points";
  EXPECT_EQ(xyz.size() % 3, 0u);
}

}  // namespace
}  // namespace cobra::studio

namespace cobra::studio {
namespace {

// Forwards to the bridge and, after each step, takes the newest frame and the events as the
// server's thread does every 1/30 s (here on the run's thread: the bridge cannot tell).
class ServerTick final : public run::RunObserver {
 public:
  explicit ServerTick(VisualizerBridge& bridge) : bridge_(bridge) {}
  void attach(const run::RunContext& run) override { bridge_.attach(run); }
  void step(const run::StepView& now) override {
    bridge_.step(now);
    std::string frame;
    if (bridge_.latestFrame(seq_, frame)) frames.push_back(frame);
    std::vector<std::string> messages;
    bridge_.takeMessages(messages);
    events.insert(events.end(), messages.begin(), messages.end());
  }
  void event(double t, const std::string& source, const std::string& name) override { bridge_.event(t, source, name); }
  bool nextInput(std::size_t& index) override { return bridge_.nextInput(index); }
  std::vector<std::string> finished(const run::RunResult& result) override { return bridge_.finished(result); }

  std::vector<std::string> frames, events;  // what the server's thread took, in order

 private:
  VisualizerBridge& bridge_;
  std::uint64_t seq_ = 0;
};

// GET /api/recording of a live run: {"frames":[...],"events":[...]} as the list of each's texts.
std::vector<std::string> historyOf(const std::string& recording, const char* key) {
  std::vector<std::string> out;
  const json::Json whole = json::parse(recording);
  for (const json::Json& item : whole.at(key)) out.push_back(item.dump());
  return out;
}

std::vector<std::string> dumped(const std::vector<std::string>& texts) {
  std::vector<std::string> out;
  for (const std::string& t : texts) out.push_back(json::parse(t).dump());
  return out;
}

TEST(VisualizerBridge, ALatePageGetsTheNewestFramesAndEventsTheServerTookBounded) {
  for (const std::size_t bound : {std::size_t{9000}, std::size_t{10}}) {
    BridgeOptions o;  // a live run without recording: the history is the server's thread's
    o.history_frames = bound;
    o.history_events = bound == 10 ? 3 : 4096;
    VisualizerBridge bridge(o);
    ServerTick server(bridge);
    run::RunOptions options;
    options.app = kApps + "threshold_studio.lua";
    options.observer = &server;
    ASSERT_TRUE(run::runApp(options).completed());
    ASSERT_GT(server.frames.size(), 10u);
    ASSERT_GT(server.events.size(), 3u);
    const std::string recording = bridge.recording();
    const auto newest = [](const std::vector<std::string>& all, std::size_t n) {
      return dumped(std::vector<std::string>(all.end() - static_cast<long>(std::min(n, all.size())), all.end()));
    };
    EXPECT_EQ(historyOf(recording, "frames"), newest(server.frames, o.history_frames)) << "bound " << bound;
    EXPECT_EQ(historyOf(recording, "events"), newest(server.events, o.history_events)) << "bound " << bound;
  }
}

TEST(VisualizerBridge, TheModelSaysWhetherAPersonIsAskedLiveOnlyWhenTheRunIsInteractive) {
  for (const bool interactive : {false, true}) {
    BridgeOptions o;
    o.interactive = interactive;
    VisualizerBridge bridge(o);
    run::RunOptions options;
    options.app = kApps + "threshold_studio.lua";
    options.observer = &bridge;
    const std::filesystem::path report = std::filesystem::temp_directory_path() / "cobra_bridge_interactive";
    options.report_folder = report;
    ASSERT_TRUE(run::runApp(options).completed());
    int status = 0;
    EXPECT_EQ(json::parse(bridge.model(status))["interactive"], interactive);
    // The replay asks no one, whatever the run was.
    EXPECT_EQ(json::parse(readFile(report / "studio" / "recording.json"))["model"]["interactive"], false);
    std::filesystem::remove_all(report);
  }
}

}  // namespace
}  // namespace cobra::studio
