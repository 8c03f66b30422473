// The door task (thesis §2.2, Figs. 2.5-2.6) from its files only: door.lua deployed by the Lua
// deployer on the lockstep clock, with the door from the loadable package cobra_door. The task
// chart must reach its final state through the five deployments and both configurations, and the
// simulated door must really be open then. What `cobra run apps/door` runs.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "cobra/components/builtin_packages.hpp"
#include "cobra/components/coordination/supervisor.hpp"
#include "cobra/deploy/deploy.hpp"
#include "cobra/deploy/lua_deployer.hpp"
#include "cobra/test_support/test_support.hpp"

namespace cobra {
namespace {

using namespace std::chrono_literals;

const std::string kDoor = std::string(COBRA_SOURCE_DIR) + "/apps/door/";

struct DoorRun {
  deploy::Configurator configurator{deploy::ConfiguratorOptions{.package_path = {COBRA_PACKAGE_DIR}, .host = {}}};
  script::LuaState lua;
  deploy::LuaDeployer deployer{configurator, lua};
  std::vector<std::string> log;  // "state X", "deployment Y", "configuration Z" as they change

  DoorRun() { components::addBuiltinPackages(configurator.packages()); }

  /// Runs until the task chart is in root.done or root.failed (or in `until`, when given), or
  /// `limit` of simulated time.
  std::string run(std::chrono::nanoseconds limit, const std::string& until = "") {
    const auto& task = dynamic_cast<const components::Supervisor&>(configurator.getReferences().get("TaskSup"));
    std::string state, deployment, configuration;
    while (configurator.clock().now() < limit && state != "root.done" && state != "root.failed" &&
           (until.empty() || state != until)) {
      configurator.clock().advance(10ms);
      if (task.activeState() != state) log.push_back("state " + (state = task.activeState()));
      if (configurator.currentDeployment() != deployment) log.push_back("deployment " + (deployment = configurator.currentDeployment()));
      if (configurator.currentConfiguration() != configuration)
        log.push_back("configuration " + (configuration = configurator.currentConfiguration()));
    }
    return state;
  }
  double seconds() { return std::chrono::duration<double>(configurator.clock().now()).count(); }
  /// A reader of one of the door's outputs, connected as a scope would be.
  std::unique_ptr<core::InputPortBase> door(const std::string& port) {
    auto& out = static_cast<core::OutputPortBase&>(configurator.getReferences().get("Door").port(port));
    auto reader = out.makeReader(port, "the door's " + port);
    out.connectTo(*reader, core::ConnPolicy::data());
    return reader;
  }
  std::unique_ptr<core::InputPortBase> doorAngle() { return door("doorAngle"); }
  /// The last sample of `reader` (a double port).
  static double value(core::InputPortBase& reader) {
    std::string text;
    EXPECT_NE(reader.readText(text), core::FlowStatus::NoData);
    return text.empty() ? 0.0 : std::stod(text);
  }
  /// How far the arm moves over the next `watch` of simulated time, m: the largest distance of
  /// Door.armPosition (sampled every 10 ms) from where it is now. The chart stays where it is.
  double armTravel(core::InputPortBase& arm, std::chrono::nanoseconds watch) {
    const double start = value(arm);
    double worst = 0.0;
    for (auto t = 0ns; t < watch; t += 10ms) {
      configurator.clock().advance(10ms);
      worst = std::max(worst, std::abs(value(arm) - start));
    }
    return worst;
  }
};

/// `lines` appear in `log` in this order.
void expectInOrder(const std::vector<std::string>& log, const std::vector<std::string>& lines) {
  std::size_t at = 0;
  std::string all;
  for (const std::string& l : log) all += "\n  " + l;
  for (const std::string& line : lines) {
    while (at < log.size() && log[at] != line) ++at;
    ASSERT_LT(at, log.size()) << "missing, in order: " << line << "; the run:" << all;
    ++at;
  }
}

TEST(DoorTask, TheThreeSupervisorsOpenTheDoorThroughItsDeploymentsAndConfigurations) {
  DoorRun r;
  r.deployer.runFile(kDoor + "door.lua");
  const auto angle = r.doorAngle();
  ASSERT_EQ(r.run(30s), "root.done");
  // Fig. 2.5: approach, grasp, turn (gently, then firmly: 1.2 N·m stops the handle short of the
  // latch), pull, release.
  expectInOrder(r.log, {"state root.opening.approach", "deployment approach", "configuration gentle",
                        "state root.opening.grasp", "deployment grasp", "state root.opening.turn", "deployment turn",
                        "configuration firm", "state root.opening.pull", "deployment pull", "state root.release",
                        "deployment release", "state root.done"});
  // The door really is open, past the DoorOpen detector's 1.2 rad.
  std::string text;
  ASSERT_NE(angle->readText(text), core::FlowStatus::NoData);
  EXPECT_GT(std::stod(text), 1.2);
  EXPECT_LT(r.seconds(), 15.0);
}

// Done means at rest: the gripper closed on an arm at rest at the handle (door.lua's AtHandle),
// so the arm, which the handle held wherever the gripper closed, does not move on once released.
TEST(DoorTask, TheArmHoldsStillOnceTheTaskIsDone) {
  DoorRun r;
  r.deployer.runFile(kDoor + "door.lua");
  const auto arm = r.door("armPosition");
  ASSERT_EQ(r.run(30s), "root.done");
  EXPECT_NEAR(DoorRun::value(*arm), 0.5, 2e-4);  // m: at the handle (Door.handle_position), at rest
  EXPECT_LT(r.armTravel(*arm, 1s), 2e-4);         // m over the second after done (the fault matrix: < 0.5 mm)
}

// A detector that stays silent (Unlatched stopped while the handle is turned) ends the wait: the
// handle is turned firmly after 2 s, then after the chart's detector_timeout (5 s) the chart goes
// to root.failed with e_detector_timeout, the gripper still on the handle and the arm holding.
TEST(DoorTask, ASilentDetectorEndsInTheSafeStopAfterItsTimeout) {
  DoorRun r;
  r.deployer.runFile(kDoor + "door.lua");
  const auto arm = r.door("armPosition");
  const auto gripped = r.door("gripped");
  const auto handle = r.door("handleAngle");
  ASSERT_EQ(r.run(30s, "root.opening.turn"), "root.opening.turn");
  const double turn = r.seconds();
  r.lua.run("stopComponents({'Unlatched'})");
  ASSERT_EQ(r.run(60s), "root.failed");
  expectInOrder(r.log, {"state root.opening.turn", "state root.opening.turn_firmly", "configuration firm", "state root.failed"});
  // 2 s gently, then 5 s firmly (the supervisor's 10 ms period and this loop's 10 ms apart).
  EXPECT_NEAR(r.seconds() - turn, 7.0, 0.05);
  EXPECT_GT(DoorRun::value(*handle), 0.7);  // rad: the handle did give (past the latch): only the detector was silent
  EXPECT_EQ(DoorRun::value(*gripped), 1.0);
  EXPECT_LT(r.armTravel(*arm, 1s), 1e-6);   // m: gripped, the arm holds
  const auto& task = dynamic_cast<const components::Supervisor&>(r.configurator.getReferences().get("TaskSup"));
  EXPECT_EQ(task.activeState(), "root.failed");
}

TEST(DoorTask, TheEntryFileDeclaresItsRunTable) {
  DoorRun r;
  r.deployer.runFile(kDoor + "door.lua");
  // What `cobra run apps/door` reads: the task chart's supervisor and final state, the recorded
  // ports (each must exist in the deployment).
  EXPECT_EQ(r.lua.evaluate("run.charts[1].supervisor"), "TaskSup");
  EXPECT_EQ(r.lua.evaluate("run.charts[1].done"), "root.done");
  const int ports = std::stoi(r.lua.evaluate("#run.record.ports"));
  ASSERT_GT(ports, 0);
  for (int i = 1; i <= ports; ++i) {
    const std::string path = r.lua.evaluate("run.record.ports[" + std::to_string(i) + "]");
    const auto dot = path.find('.');
    ASSERT_NE(dot, std::string::npos) << path;
    EXPECT_NE(r.configurator.getReferences().get(path.substr(0, dot)).findPort(path.substr(dot + 1)), nullptr) << path;
  }
}

}  // namespace
}  // namespace cobra
