// The cobra_sim package (with the Decision components of cobra_monitoring) deployed by the Lua
// deployer as the puncturing application would: the six components by type name, wired by connections_list, on the Configurator's lockstep clock.
#include "cobra/components/sim/package.hpp"

#include "cobra/components/builtin_packages.hpp"

#include <gtest/gtest.h>

#include "cobra/deploy/deploy.hpp"
#include "cobra/deploy/lua_deployer.hpp"
#include "cobra/test_support/test_support.hpp"
#include "puncturing_world.hpp"

namespace cobra::components::test {
namespace {

constexpr const char* kDeployment = R"(
packages_list = { "cobra_sim", "cobra_monitoring" }
components_list = {
  { peer_name = "Isur", component_type = "SimulatedISURRobot" },
  { peer_name = "Ur5", component_type = "SimulatedUR5Robot" },
  { peer_name = "Patient", component_type = "PatientSimulator" },
  { peer_name = "Omni", component_type = "SimulatedOmniPhantom" },
  { peer_name = "NeedleMonitor", component_type = "NeedleInsertionMonitor" },
  { peer_name = "UsMonitor", component_type = "UltrasoundMonitor" },
}
names = { "Isur", "Ur5", "Patient", "Omni", "NeedleMonitor", "UsMonitor" }
activities_list = {}
for _, n in ipairs(names) do activities_list[#activities_list + 1] = { peer_name = n, period = 0.001 } end
connections_list = {
  { output = "Isur.trueCartPose", input = "Patient.needleTipPose" },
  { output = "Ur5.trueCartPose", input = "Patient.probePose" },
  { output = "Patient.needleWrench", input = "Isur.contactWrench" },
  { output = "Patient.probeWrench", input = "Ur5.contactWrench" },
  { output = "Isur.measWrench", input = "NeedleMonitor.measWrench" },
  { output = "Isur.measCartPose", input = "NeedleMonitor.measCartPose" },
  { output = "Patient.needlePlaneDistance", input = "UsMonitor.needlePlaneDistance" },
  { output = "Patient.needleInImage", input = "UsMonitor.needleInImage" },
  { output = "Patient.probeContactForce", input = "UsMonitor.probeContactForce" },
  { output = "Isur.measWrench", input = "Omni.desWrench" },
}
initConfigurator(packages_list, components_list, "")
setActivities(activities_list)
connectPorts(connections_list)
)";

TEST(CobraSimPackage, TheComponentsDeployByTypeNameAndRunTogether) {
  deploy::Configurator configurator;
  script::LuaState lua;
  deploy::LuaDeployer deployer{configurator, lua};
  addBuiltinPackages(configurator.packages());
  deployer.run(kDeployment, "puncturing_sim.lua");

  // The geometry of the test world: the phantom 5 mm ahead of the needle, the probe beside it.
  const PuncturingWorld geometry;
  core::ComponentRegistry& peers = configurator.getReferences();
  peers.get("Patient").setProperty("phantom_pose", geometry.phantom);
  peers.get("Ur5").setProperty("base_frame", geometry.ur5.getProperty<KDL::Frame>("base_frame"));
  EXPECT_EQ(peers.get("NeedleMonitor").role(), core::Role::Decision);
  EXPECT_EQ(peers.get("Patient").role(), core::Role::Bridge);

  core::OutputPort<KDL::Frame> needle{"needle", "", "m"};
  core::OutputPort<KDL::Frame> probe{"probe", "", "m"};
  core::InputPort<core::Event> events{"events", "", ""};
  core::connectPorts(needle, peers.get("Isur").port("desCartPose"));
  core::connectPorts(probe, peers.get("Ur5").port("desCartPose"));
  core::connectPorts(peers.get("NeedleMonitor").port("events"), events, core::ConnPolicy::buffer(32));
  core::connectPorts(peers.get("UsMonitor").port("events"), events, core::ConnPolicy::buffer(32));
  deployer.run("configureComponents(names) startComponents(names)", "start.lua");

  std::vector<std::string> seen;
  for (int ms = 0; ms < 2000; ++ms) {
    needle.write(geometry.needleAt(0.01 * ms * 1e-3));
    probe.write(geometry.probe);
    configurator.clock().advance(std::chrono::milliseconds(1));
    core::Event e;
    while (events.read(e) == core::FlowStatus::NewData) seen.push_back(e.name.str());
  }
  EXPECT_EQ(seen, (std::vector<std::string>{"e_probe_contact", "e_skin_touched", "e_skin_penetrated",
                                            "e_needle_visible"}));
}

}  // namespace
}  // namespace cobra::components::test
