// The cobra_drivers package through the Lua deployer, with the simulated devices of cobra_sim: the
// three drivers find their buses and device by the `bus` / `device` property, configure from Lua
// and run on the deployer's lockstep clock; swapping to a real backend changes that property only
// (SocketCAN here: the build machine has no CAN interface, so it refuses, naming the interface).

#include "cobra/components/drivers/package.hpp"

#include <gtest/gtest.h>

#include <kdl/frames.hpp>

#include "cobra/components/builtin_packages.hpp"
#include "cobra/deploy/deploy.hpp"
#include "cobra/deploy/lua_deployer.hpp"
#include "cobra/test_support/test_support.hpp"

namespace cobra::components {
namespace {

using namespace std::chrono_literals;

constexpr const char* kDeployment = R"(
packages_list = { "cobra_sim", "cobra_drivers" }
components_list = {
  { peer_name = "PumaSim", component_type = "SimulatedPuma260" },
  { peer_name = "FTSensSim", component_type = "SimulatedFTSens" },
  { peer_name = "LeapSim", component_type = "SimulatedLeapMotion" },
  { peer_name = "Puma", component_type = "Puma260EtherCATMaster" },
  { peer_name = "FTSens", component_type = "FTSensDriver" },
  { peer_name = "Leap", component_type = "LeapMotionDriver" },
}
initConfigurator(packages_list, components_list, "")
getReferences()
Puma.bus = "sim:PumaSim"      -- "soem:eth0" on the real robot, would a SOEM package register it
FTSens.bus = "sim:FTSensSim"  -- "socketcan:can0" on the real sensor
Leap.device = "sim:LeapSim"
names = { "PumaSim", "FTSensSim", "LeapSim", "Puma", "FTSens", "Leap" }
activities_list = {}
for _, n in ipairs(names) do activities_list[#activities_list + 1] = { peer_name = n, period = 0.001 } end
setActivities(activities_list)
)";

TEST(DriversPackage, DeploysTheThreeDriversOnTheSimulatedDevicesOfCobraSim) {
  deploy::Configurator configurator;
  script::LuaState lua;
  deploy::LuaDeployer deployer{configurator, lua};
  addBuiltinPackages(configurator.packages());
  deployer.run(kDeployment, "drivers.lua");
  core::ComponentRegistry& peers = configurator.getReferences();
  core::InputPort<core::TaskState> state{"state", "", ""};
  core::InputPort<KDL::Wrench> wrench{"wrench", "", "N, N·m"};
  core::InputPort<KDL::Frame> hand{"hand", "", "m"};
  core::OutputPort<KDL::Wrench> truth{"truth", "", "N, N·m"};
  core::OutputPort<KDL::Frame> right{"right", "", "m"};
  core::connectPorts(peers.get("Puma").port("currentState"), state);
  core::connectPorts(peers.get("FTSens").port("measWrench"), wrench);
  core::connectPorts(peers.get("Leap").port("measRightPose"), hand);
  core::connectPorts(truth, peers.get("FTSensSim").port("trueWrench"));
  core::connectPorts(right, peers.get("LeapSim").port("rightHand"));
  deployer.run("configureComponents(names) startComponents(names)", "start.lua");
  truth.write(KDL::Wrench(KDL::Vector(0, 0, 25.0), KDL::Vector::Zero()));
  right.write(KDL::Frame(KDL::Vector(0.0, 0.0, 0.2)));
  configurator.clock().advance(20ms);
  core::TaskState s;
  ASSERT_NE(state.read(s), core::FlowStatus::NoData);
  EXPECT_EQ(s.path.str(), "Initialized");
  KDL::Wrench w;
  ASSERT_NE(wrench.read(w), core::FlowStatus::NoData);
  EXPECT_NEAR(w.force.z(), 25.0, 1.0);
  KDL::Frame f;
  ASSERT_NE(hand.read(f), core::FlowStatus::NoData);
  EXPECT_NEAR(f.p.z(), 0.2, 0.005);
}

TEST(DriversPackage, ARealBackendIsOnePropertyAwayAndRefusesAMissingInterfaceByName) {
  deploy::Configurator configurator;
  script::LuaState lua;
  deploy::LuaDeployer deployer{configurator, lua};
  addBuiltinPackages(configurator.packages());
  deployer.run(
      "initConfigurator({ 'cobra_drivers' }, { { peer_name = 'FTSens', component_type = 'FTSensDriver' } })\n"
      "getReferences() FTSens.bus = 'socketcan:cobra_nocan0'\n"
      "setActivities({ { peer_name = 'FTSens', period = 0.001 } })",
      "real.lua");
  const std::string message = test_support::messageOf([&] { deployer.run("configureComponents({ 'FTSens' })", "c.lua"); });
  EXPECT_CONTAINS(message,
                  "component 'FTSens': property bus = 'socketcan:cobra_nocan0': CAN bus backend "
                  "'socketcan:cobra_nocan0': SocketCAN interface 'cobra_nocan0': no network interface has this name");
  core::Component& ftsens = configurator.getReferences().get("FTSens");
  ftsens.setProperty("bus", "can0");
  EXPECT_CONTAINS(ftsens.configure().message,
                  "property bus = 'can0': 'can0' is not a CAN bus backend name: expected <scheme>:<address>; backends "
                  "that exist: 'socketcan:<address>' (Linux SocketCAN: a raw CAN socket on the network interface "
                  "named, from package 'cobra_drivers')");
  EXPECT_CONTAINS(configurator.getReferences().get("FTSens").configure().message, "(a sim-world component registers");
}

}  // namespace
}  // namespace cobra::components
