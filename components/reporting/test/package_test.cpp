// The cobra_reporting package: "Reporter" deployed by type name from a Lua deployment file records
// the output ports of its peers (as OCL's FileReporting), and says what is missing otherwise.
#include "cobra/components/reporting/package.hpp"

#include <gtest/gtest.h>

#include "cobra/components/builtin_packages.hpp"
#include "cobra/deploy/deploy.hpp"
#include "cobra/deploy/lua_deployer.hpp"
#include "cobra/test_support/test_support.hpp"
#include "test_files.hpp"

namespace cobra::components {
namespace {

using namespace std::chrono_literals;

struct Deployment {
  deploy::Configurator configurator;
  script::LuaState lua;
  deploy::LuaDeployer deployer{configurator, lua};
  test::ScratchDir dir;
  Deployment() { addBuiltinPackages(configurator.packages()); }
};

constexpr const char* kComponents = R"(
initConfigurator({ "cobra_signal", "cobra_reporting" }, {
  { peer_name = "Sine", component_type = "SineGenerator" },
  { peer_name = "Amp", component_type = "Gain" },
  { peer_name = "Reporter", component_type = "Reporter" },
})
setActivities({ { peer_name = "Sine", period = 0.01 }, { peer_name = "Amp", period = 0.01 },
                { peer_name = "Reporter", period = 0.01 } })
connectPorts({ { output = "Sine.out", input = "Amp.in" } })
getReferences()
)";

TEST(ReportingPackage, AReporterDeployedByTypeNameRecordsThePortsOfItsPeers) {
  Deployment d;
  d.deployer.run(kComponents, "deploy.lua");
  d.deployer.run("addPeers({ { peer_name = \"Reporter\", peers_to_add = { \"Amp\", \"Sine\" } } })\n"
                 "Reporter.file_path = [[" + d.dir.file("run.csv") + "]]\n"
                 "configureComponents({ \"Sine\", \"Amp\", \"Reporter\" })\n"
                 "startComponents({ \"Sine\", \"Amp\", \"Reporter\" })\n",
                 "deploy.lua");
  d.configurator.clock().advance(100ms);
  ASSERT_TRUE(d.configurator.getReferences().get("Reporter").stop());
  const auto lines = test::readLines(d.dir.file("run.csv"));
  ASSERT_GE(lines.size(), 10u);
  EXPECT_EQ(lines[0], "time [s],Amp.out [1],Sine.out [1]");  // the peers' outputs, in the peers' order
  // A second configure (after cleanup) reports the same ports again, once.
  auto& reporter = d.configurator.getReferences().get("Reporter");
  ASSERT_TRUE(reporter.configure());
  EXPECT_EQ(test::readLines(d.dir.file("run.csv")).front(), lines[0]);
}

TEST(ReportingPackage, AReporterWithoutPeersRefusesToConfigureSayingHowToGiveIt) {
  Deployment d;
  d.deployer.run(kComponents, "deploy.lua");
  const core::Result r = d.configurator.getReferences().get("Reporter").configure();
  EXPECT_FALSE(r);
  EXPECT_CONTAINS(r.message, "component 'Reporter': no ports to report: add the components to record as its peers "
                             "(peers_list = { { peer_name = \"Reporter\", peers_to_add = { ... } } })");
}

}  // namespace
}  // namespace cobra::components
