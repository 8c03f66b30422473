// Simulation stays out of production interfaces (ARCHITECTURE §3): the production code
// of fieldbus/, components/drivers/ and bridges/ includes no cobra/sim/ header (the bridges'
// simulated far ends live in bridges/sim/, library cobra_bridges_sim, which is not scanned), and
// no port, property or operation of a driver or bridge component exists only for simulation (none
// is named sim...); and the deployer includes no component package.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "cobra/components/builtin_packages.hpp"
#include "cobra/core/operation.hpp"
#include "cobra/deploy/package_registry.hpp"

namespace cobra::components {
namespace {

namespace fs = std::filesystem;

const fs::path kSource = COBRA_SOURCE_DIR;

const std::regex kSimInclude(R"(#\s*include\s*[<"]cobra/sim/)");

std::string read(const fs::path& file) {
  std::ifstream in(file);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

TEST(ProductionInterfaces, FieldbusDriversAndBridgesIncludeNoSimulationHeader) {
  // Every production directory of the three modules; tests and bridges/sim/ are not production.
  std::vector<std::string> offenders;
  int files = 0;
  for (const char* dir : {"fieldbus/include", "fieldbus/src", "components/drivers/include", "components/drivers/src",
                          "bridges/include", "bridges/src", "bridges/components", "bridges/tools"}) {
    ASSERT_TRUE(fs::is_directory(kSource / dir)) << dir;
    for (const auto& entry : fs::recursive_directory_iterator(kSource / dir)) {
      if (!entry.is_regular_file()) continue;
      ++files;
      if (std::regex_search(read(entry.path()), kSimInclude))
        offenders.push_back(fs::relative(entry.path(), kSource).string());
    }
  }
  EXPECT_GT(files, 30);  // the directories hold the modules' sources
  EXPECT_EQ(offenders, std::vector<std::string>{}) << "production code including cobra/sim/ headers";
}

TEST(ProductionInterfaces, TheCheckRecognisesASimulationInclude) {
  for (const char* line : {"#include \"cobra/sim/haptic.hpp\"", "#  include <cobra/sim/servo.hpp>"})
    EXPECT_TRUE(std::regex_search(std::string(line), kSimInclude)) << line;
  for (const char* line : {"#include \"cobra/bridges/sim/omni_server.hpp\"", "#include \"cobra/simulation.hpp\""})
    EXPECT_FALSE(std::regex_search(std::string(line), kSimInclude)) << line;
}

TEST(ProductionInterfaces, NoDriverOrBridgeHasASimulationOnlyPortPropertyOrOperation) {
  deploy::PackageRegistry packages;
  addBuiltinPackages(packages);
  packages.load("cobra_drivers");
  packages.load("cobra_bridges");
  const std::regex sim_name("^sim([A-Z_].*)?$");
  std::vector<std::string> offenders;
  int checked = 0;
  for (const std::string& type : packages.typeNames()) {
    auto component = packages.create(type, "Probe");
    for (const core::PortBase* p : component->ports())
      if (std::regex_match(p->name(), sim_name)) offenders.push_back(type + " port " + p->name());
    for (const core::PropertyBase* p : component->properties())
      if (std::regex_match(p->name(), sim_name)) offenders.push_back(type + " property " + p->name());
    for (const core::OperationBase* o : component->operations())
      if (std::regex_match(o->name(), sim_name)) offenders.push_back(type + " operation " + o->name());
    ++checked;
  }
  EXPECT_GE(checked, 5);  // three drivers, two bridges
  EXPECT_EQ(offenders, std::vector<std::string>{});
}

TEST(ProductionInterfaces, TheDeployerIncludesNoComponentPackage) {
  // components/builtin_packages registers cobra's packages; the deployer stays generic.
  const std::regex component_include(R"(#\s*include\s*[<"]cobra/components/)");
  std::vector<std::string> offenders;
  for (const char* dir : {"deploy/include", "deploy/src", "deploy/lua/include", "deploy/lua/src"})
    for (const auto& entry : fs::recursive_directory_iterator(kSource / dir))
      if (entry.is_regular_file() && std::regex_search(read(entry.path()), component_include))
        offenders.push_back(fs::relative(entry.path(), kSource).string());
  EXPECT_EQ(offenders, std::vector<std::string>{});
}

TEST(ProductionInterfaces, TheCheckRecognisesASimulationOnlyName) {
  const std::regex sim_name("^sim([A-Z_].*)?$");
  for (const char* name : {"simTrueWrench", "sim_seed", "simInjectFault", "sim"}) EXPECT_TRUE(std::regex_match(name, sim_name)) << name;
  for (const char* name : {"similarity", "measWrench", "simulated_time"}) EXPECT_FALSE(std::regex_match(name, sim_name)) << name;
}

}  // namespace
}  // namespace cobra::components
