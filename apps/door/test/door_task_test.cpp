// The door task (thesis §2.2, Figs. 2.5-2.6) from its files only: door.lua deployed by the Lua
// deployer on the lockstep clock, with the door from the loadable package cobra_door. The task
// chart must reach its final state through the five deployments and both configurations, and the
// simulated door must really be open then. What `cobra run apps/door` runs.
#include <gtest/gtest.h>

#include <chrono>
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

  /// Runs until the task chart is in root.done or root.failed, or `limit` of simulated time.
  std::string run(std::chrono::nanoseconds limit) {
    const auto& task = dynamic_cast<const components::Supervisor&>(configurator.getReferences().get("TaskSup"));
    std::string state, deployment, configuration;
    while (configurator.clock().now() < limit && state != "root.done" && state != "root.failed") {
      configurator.clock().advance(10ms);
      if (task.activeState() != state) log.push_back("state " + (state = task.activeState()));
      if (configurator.currentDeployment() != deployment) log.push_back("deployment " + (deployment = configurator.currentDeployment()));
      if (configurator.currentConfiguration() != configuration)
        log.push_back("configuration " + (configuration = configurator.currentConfiguration()));
    }
    return state;
  }
  /// A reader of the door's opening angle (rad), connected as a scope would be.
  std::unique_ptr<core::InputPortBase> doorAngle() {
    auto& out = static_cast<core::OutputPortBase&>(configurator.getReferences().get("Door").port("doorAngle"));
    auto reader = out.makeReader("doorAngle", "the door's opening");
    out.connectTo(*reader, core::ConnPolicy::data());
    return reader;
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
  const double seconds = std::chrono::duration<double>(r.configurator.clock().now()).count();
  EXPECT_LT(seconds, 15.0);
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
