// Tutorial 07 runs as its README says, from its files only: the probe scan is deployed from
// 07_task.lua by the Lua deployer on the lockstep clock and must reach the chart's final state with
// the robot doing what it was told: the measured probe follows the commanded pose (tracking error),
// passes over every scan waypoint, never goes below the scan height over the part, and no command
// is refused. What `cobra run examples/07_task` runs.
#include <gtest/gtest.h>
#include <kdl/frames.hpp>

#include <chrono>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "cobra/components/builtin_packages.hpp"
#include "cobra/components/coordination/supervisor.hpp"
#include "cobra/deploy/deploy.hpp"
#include "cobra/deploy/lua_deployer.hpp"

namespace cobra {
namespace {

using namespace std::chrono_literals;

template <class T>
std::unique_ptr<core::InputPort<T>> tap(core::ComponentRegistry& refs, const std::string& component, const char* port,
                                        core::ConnPolicy policy = core::ConnPolicy::data()) {
  auto reader = std::make_unique<core::InputPort<T>>(port, "the test's probe", "");
  core::connectPorts(refs.get(component).port(port), *reader, policy);
  return reader;
}

TEST(TaskTutorial, TheProbeScanReachesDoneFollowingItsCommandsOverTheWholeRaster) {
  deploy::Configurator configurator;
  components::addBuiltinPackages(configurator.packages());
  script::LuaState lua;
  deploy::LuaDeployer deployer(configurator, lua);
  deployer.runFile(std::string(COBRA_EXAMPLES_DIR) + "/07_task/07_task.lua");
  core::ComponentRegistry& refs = configurator.getReferences();
  const auto& task = dynamic_cast<const components::Supervisor&>(refs.get("TaskSup"));
  auto commanded = tap<KDL::Frame>(refs, "TrajGen", "desCartPose_1");
  auto measured = tap<KDL::Frame>(refs, "UR5", "measCartPose");
  auto robot_events = tap<core::Event>(refs, "UR5", "events", core::ConnPolicy::buffer(64));

  // The scan's waypoints (07_task.lua): x, y at z = 0.15 m.
  const std::vector<KDL::Vector> raster = {KDL::Vector(0.35, -0.15, 0.15), KDL::Vector(0.35, 0.05, 0.15),
                                           KDL::Vector(0.40, 0.05, 0.15),  KDL::Vector(0.40, -0.15, 0.15),
                                           KDL::Vector(0.45, -0.15, 0.15), KDL::Vector(0.45, 0.05, 0.15)};
  std::vector<double> closest(raster.size(), INFINITY);
  double worst_mm = 0.0, worst_deg = 0.0, lowest = INFINITY;
  std::vector<std::string> refused, states;
  KDL::Frame cmd, meas;
  bool have_cmd = false;
  while (configurator.clock().now() < 120s) {
    configurator.clock().advance(1ms);
    const std::string state(task.activeState());
    if (states.empty() || states.back() != state) states.push_back(state);
    if (state == "root.Done" || state == "root.Failed") break;
    if (commanded->read(cmd) != core::FlowStatus::NoData) have_cmd = true;
    if (measured->read(meas) == core::FlowStatus::NoData || !have_cmd) continue;
    worst_mm = std::max(worst_mm, 1000.0 * (cmd.p - meas.p).Norm());
    worst_deg = std::max(worst_deg, (cmd.M.Inverse() * meas.M).GetRot().Norm() * 180.0 / M_PI);
    if (state.starts_with("root.Scan.Moving")) lowest = std::min(lowest, meas.p.z());
    for (std::size_t i = 0; i < raster.size(); ++i) closest[i] = std::min(closest[i], (meas.p - raster[i]).Norm());
  }
  for (core::Event e; robot_events->read(e) == core::FlowStatus::NewData;)
    if (e.name.view().starts_with("e_ik_") && e.name != "e_ik_solved") refused.push_back(e.name.str());

  std::string trace;
  for (const std::string& s : states) trace += " " + s;
  ASSERT_EQ(task.activeState(), "root.Done") << "states:" << trace;
  EXPECT_TRUE(refused.empty()) << refused.front();
  // The probe followed its commands: 2 mm and 1 deg (the acceptance for autonomous motions,
  // run/tracking.hpp).
  EXPECT_LT(worst_mm, 2.0);
  EXPECT_LT(worst_deg, 1.0);
  // It went over every corner of the raster, and never below the scan height over the part.
  for (std::size_t i = 0; i < raster.size(); ++i) EXPECT_LT(closest[i], 0.002) << "scan waypoint " << i;
  EXPECT_GT(lowest, 0.148);
  std::printf("scan done at %.3f s; worst tracking %.3f mm, %.3f deg\n",
              std::chrono::duration<double>(configurator.clock().now()).count(), worst_mm, worst_deg);
}

TEST(TaskTutorial, AScanPoseOutOfReachEndsTheTaskInFailedWithTheRobotHolding) {
  deploy::Configurator configurator;
  components::addBuiltinPackages(configurator.packages());
  script::LuaState lua;
  deploy::LuaDeployer deployer(configurator, lua);
  deployer.runFile(std::string(COBRA_EXAMPLES_DIR) + "/07_task/07_task.lua");
  // 2 m away: beyond the UR5's reach (0.85 m). Read when the scan's deployment configures ScanPath.
  lua.run("ScanPath.waypoints = { 2.0, 0.0, 0.15, 0.70710678, 0.70710678, 0, 0 }", "=test");
  core::ComponentRegistry& refs = configurator.getReferences();
  const auto& task = dynamic_cast<const components::Supervisor&>(refs.get("TaskSup"));
  auto measured = tap<KDL::Frame>(refs, "UR5", "measCartPose");
  auto chart_events = tap<core::Event>(refs, "TaskSup", "outputEvents", core::ConnPolicy::buffer(64));
  KDL::Frame at_failure, now;
  while (configurator.clock().now() < 60s && task.activeState() != "root.Failed" && task.activeState() != "root.Done")
    configurator.clock().advance(1ms);
  ASSERT_EQ(task.activeState(), "root.Failed");
  ASSERT_NE(measured->read(at_failure), core::FlowStatus::NoData);
  configurator.clock().advance(2s);
  ASSERT_NE(measured->read(now), core::FlowStatus::NoData);
  EXPECT_LT((now.p - at_failure.p).Norm(), 0.002);  // it holds where the refusal stopped it
  EXPECT_LT(now.p.Norm(), 0.85 + 0.12);  // within the arm's reach plus the probe: nothing swung out
  bool said = false;
  for (core::Event e; chart_events->read(e) == core::FlowStatus::NewData;) said = said || e.name == "e_scan_failed";
  EXPECT_TRUE(said);
}

}  // namespace
}  // namespace cobra
