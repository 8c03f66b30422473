// The cobra_drivers package through the Lua deployer: the three drivers are created by type
// name, configured from Lua and run on the deployer's lockstep clock.

#include "cobra/components/drivers/package.hpp"

#include <gtest/gtest.h>

#include <kdl/frames.hpp>

#include "cobra/deploy/deploy.hpp"
#include "cobra/deploy/lua_deployer.hpp"
#include "cobra/test_support/test_support.hpp"

namespace cobra::components {
namespace {

using namespace std::chrono_literals;

TEST(DriversPackage, DeploysConfiguresAndRunsTheThreeDrivers) {
  deploy::Configurator configurator;
  script::LuaState lua;
  deploy::LuaDeployer deployer{configurator, lua};
  configurator.packages().addBuiltin("cobra_drivers", registerDriversPackage);
  deployer.run(
      "initConfigurator({ 'cobra_drivers' }, {\n"
      "  { peer_name = 'Puma', component_type = 'Puma260EtherCATMaster' },\n"
      "  { peer_name = 'FTSens', component_type = 'FTSensDriver' },\n"
      "  { peer_name = 'Leap', component_type = 'LeapMotionDriver' } })\n"
      "setActivities({ { peer_name = 'Puma', period = 0.001 }, { peer_name = 'FTSens', period = 0.001 },\n"
      "                { peer_name = 'Leap', period = 0.001 } })",
      "deploy.lua");
  core::Component& puma = configurator.getReferences().get("Puma");
  core::InputPort<core::TaskState> state{"state", "", ""};
  core::InputPort<KDL::Wrench> wrench{"wrench", "", "N, N·m"};
  core::connectPorts(puma.port("currentState"), state);
  core::connectPorts(configurator.getReferences().get("FTSens").port("measWrench"), wrench);
  deployer.run("configureComponents({ 'Puma', 'FTSens', 'Leap' }) startComponents({ 'Puma', 'FTSens', 'Leap' })",
               "start.lua");
  configurator.clock().advance(20ms);
  core::TaskState s;
  ASSERT_NE(state.read(s), core::FlowStatus::NoData);
  EXPECT_EQ(s.path.str(), "Initialized");
  KDL::Wrench w;
  EXPECT_NE(wrench.read(w), core::FlowStatus::NoData);
  EXPECT_EQ(puma.getProperty<std::string>("control_mode"), "position");
}

}  // namespace
}  // namespace cobra::components
