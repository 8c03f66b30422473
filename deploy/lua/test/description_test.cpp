// The deployment description's round trip: describe(load(write(d))) == write(d), on the
// applications of the repo and on a seeded set of generated projects; and its Lua values.
#include "cobra/deploy/description.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <charconv>
#include <filesystem>
#include <fstream>
#include <random>
#include <set>

#include "cobra/components/builtin_packages.hpp"
#include "cobra/core/core.hpp"
#include <kdl/frames.hpp>
#include <kdl/jntarray.hpp>
#include "cobra/deploy/lua_deployer.hpp"
#include "cobra/test_support/test_support.hpp"

namespace cobra::deploy {
namespace {

using cobra::test_support::messageOf;

/// A grade of a package's own type: registered with the core, no Lua conversion (Lua sets it
/// from its text form, "grade 3").
struct Grade {
  int level = 0;
  friend bool operator==(const Grade&, const Grade&) = default;
};

}  // namespace
}  // namespace cobra::deploy

template <>
struct cobra::core::DataTypeTraits<cobra::deploy::Grade> {
  static constexpr std::string_view name = "test.Grade";
  static constexpr DataKind kind = DataKind::Pure;
  static constexpr std::string_view format = "grade N, e.g. grade 3";
  static std::string print(const cobra::deploy::Grade& g) { return "grade " + std::to_string(g.level); }
  static bool parse(std::string_view text, cobra::deploy::Grade& out) {
    if (text.substr(0, 6) != "grade " || text.size() == 6) return false;
    int level = 0;
    const auto [end, ec] = std::from_chars(text.data() + 6, text.data() + text.size(), level);
    if (ec != std::errc() || end != text.data() + text.size()) return false;
    out.level = level;
    return true;
  }
};

namespace cobra::deploy {
namespace {

/// A property of every type cobra's components hold (double, int, bool, string, vector<double>,
/// KDL.Vector, KDL.Frame, KDL.Wrench: grep Property< components/) and of the other registered
/// types a component may hold (KDL.Rotation, Twist, JntArray, Event, TaskState, a package's own).
class EveryType final : public core::Component {
 public:
  explicit EveryType(std::string name) : Component(std::move(name), core::Role::Calculation, "a property of each type") {
    for (core::PropertyBase* p : std::initializer_list<core::PropertyBase*>{
             &real_, &count_, &flag_, &text_, &list_, &vector_, &rotation_, &frame_, &twist_, &wrench_, &joints_,
             &event_, &state_, &grade_})
      addProperty(*p);
  }

 private:
  core::Property<double> real_{"real", 0.0, "m", "a number"};
  core::Property<int> count_{"count", 0, "1", "an integer"};
  core::Property<bool> flag_{"flag", false, "1", "a flag"};
  core::Property<std::string> text_{"text", "", "", "a text"};
  core::Property<std::vector<double>> list_{"list", {}, "m", "numbers"};
  core::Property<KDL::Vector> vector_{"vector", KDL::Vector::Zero(), "m", "a point"};
  core::Property<KDL::Rotation> rotation_{"rotation", KDL::Rotation::Identity(), "1", "an orientation"};
  core::Property<KDL::Frame> frame_{"frame", KDL::Frame::Identity(), "m", "a pose"};
  core::Property<KDL::Twist> twist_{"twist", KDL::Twist::Zero(), "m/s, rad/s", "a velocity"};
  core::Property<KDL::Wrench> wrench_{"wrench", KDL::Wrench::Zero(), "N, N m", "a wrench"};
  core::Property<KDL::JntArray> joints_{"joints", KDL::JntArray(), "rad", "joint values"};
  core::Property<core::Event> event_{"event", core::Event{}, "", "an event"};
  core::Property<core::TaskState> state_{"state", core::TaskState{}, "", "a state path"};
  core::Property<Grade> grade_{"grade", Grade{}, "", "a package's own type"};
};

void registerEveryType(PackageBuilder& package) { package.component<EveryType>("EveryType", "a property of each type"); }

/// A deployment file run in a Configurator on the simulation clock, never advanced.
struct Loaded {
  explicit Loaded(const std::string& path) {
    components::addBuiltinPackages(configurator.packages());
    configurator.packages().addBuiltin("test_every_type", registerEveryType);
    deployer.runFile(path);
  }
  Configurator configurator;
  script::LuaState lua;
  LuaDeployer deployer{configurator, lua};
};

std::filesystem::path scratch(const std::string& name) {
  const auto folder = ::cobra::test_support::scratchPath("cobra_description_test");
  std::filesystem::create_directories(folder);
  return folder / name;
}

std::string writeFile(const std::string& name, const std::string& text) {
  const auto path = scratch(name);
  std::ofstream(path) << text;
  return path.string();
}

/// Describes `path`, writes the description, loads that and describes it again: the same text.
std::string expectStable(const std::string& path, const std::string& name) {
  std::string first;
  {
    Loaded original(path);
    first = toLua(describe(original.configurator));
  }
  const std::string written = writeFile(name, first);
  Loaded again(written);
  EXPECT_EQ(toLua(describe(again.configurator)), first) << path << " -> " << written;
  return first;
}

TEST(Description, ExamplesRoundTrip) {
  const std::string examples = std::string(COBRA_SOURCE_DIR) + "/apps/examples/";
  const std::string signal = expectStable(examples + "signal_listing.lua", "signal.lua");
  EXPECT_NE(signal.find("{ peer_name = \"TrajGen\", period = 0.001, priority = 95, scheduler = \"ORO_SCHED_RT\" }"),
            std::string::npos) << signal;
  EXPECT_NE(signal.find("{ output = \"MotPlan.out\", input = \"TrajGen.in\", conn_policy = { type = \"data\" } }"),
            std::string::npos) << signal;
  const std::string listing = expectStable(examples + "configurator_listing.lua", "listing.lua");
  // Property values set by the file are written; defaults are not.
  EXPECT_NE(listing.find("TrajGen.arms_num = 2\n"), std::string::npos) << listing;
  EXPECT_EQ(listing.find("TrajGen.max_vel"), std::string::npos) << listing;  // set to its default, 0.05 m/s
  EXPECT_NE(listing.find("conn_policy = { type = \"buffer\", size = 16 }"), std::string::npos) << listing;
  expectStable(examples + "puma260_drivers.lua", "drivers.lua");
}

TEST(Description, PuncturingKeepsItsDeploymentsAndConfigurations) {
  const std::string text = expectStable(std::string(COBRA_SOURCE_DIR) + "/apps/puncturing/puncturing.lua", "puncturing.lua");
  Loaded original(std::string(COBRA_SOURCE_DIR) + "/apps/puncturing/puncturing.lua");
  const DeploymentDescription d = describe(original.configurator);
  EXPECT_EQ(d.apply, (std::vector<std::string>{"needle_autonomous_planning", "probe_autonomous_planning"}));
  EXPECT_EQ(d.deployments.size(), original.configurator.deploymentSet().deploymentNames().size());
  EXPECT_EQ(d.configurations.size(), original.configurator.deploymentSet().configurationNames().size());
  EXPECT_GT(d.deployments.size(), 2u);
  for (const DeploymentSpec& deployment : d.deployments)
    EXPECT_NE(text.find("defineDeployment(\"" + deployment.name + "\""), std::string::npos) << deployment.name;
  // Every connection the Configurator made is in the file: by connectPorts, or by an applied
  // deployment (components' own connections, e.g. a Reporter's to its peers' ports, are theirs).
  EXPECT_EQ(d.connections.size(), original.configurator.madeConnections().size());
  std::size_t live = 0, by_deployments = 0;
  for (const core::Component* c : original.configurator.getReferences().components())
    for (const core::PortBase* port : c->ports())
      if (port->direction() == core::PortDirection::Output) live += port->connections().size();
  for (const std::string& name : d.apply) by_deployments += original.configurator.deploymentSet().deployment(name).connections.size();
  EXPECT_GT(by_deployments, 0u);
  EXPECT_LE(d.connections.size() + by_deployments, live);
}

TEST(Description, LuaValuesOfEveryForm) {
  EXPECT_EQ(luaValue("double", "0.001"), "0.001");
  EXPECT_EQ(luaValue("double", "-inf"), "-math.huge");
  EXPECT_EQ(luaValue("int", "42"), "42");
  EXPECT_EQ(luaValue("bool", "true"), "true");
  EXPECT_EQ(luaValue("string", "a \"quoted\"\\ name\n"), "\"a \\\"quoted\\\"\\\\ name\\n\"");
  EXPECT_EQ(luaValue("KDL.Frame", "[0.1, 0, -2e-05, 0, 0, 0, 1]"), "{ 0.1, 0, -2e-05, 0, 0, 0, 1 }");
  EXPECT_EQ(luaValue("vector<double>", "[]"), "{}");
  EXPECT_EQ(luaValue("Event", "e_done"), "\"e_done\"");
  EXPECT_EQ(messageOf([] { (void)luaValue("double", "fast"); }), "expected a number for a double, got 'fast'");
  EXPECT_EQ(messageOf([] { (void)luaValue("KDL.Vector", "[1, x, 3]"); }),
            "expected a list of numbers for a KDL.Vector, got '[1, x, 3]'");
  EXPECT_EQ(luaPolicyTable(ConnPolicySpec("circular", 4)), "{ type = \"circular\", size = 4 }");
  ConnPolicySpec dds("buffer", 16);
  dds.transport = "dds";
  dds.topic = "needle/events";
  dds.qos = {{"reliability", "reliable"}, {"lease", "0.1"}};
  EXPECT_EQ(luaPolicyTable(dds), "{ type = \"buffer\", size = 16, transport = \"dds\", topic = \"needle/events\", "
                                 "qos = { reliability = \"reliable\", lease = \"0.1\" } }");
}

TEST(Description, EveryPropertyTypeRoundTrips) {
  // Values no fresh EveryType has, of every form: negative, exponents, inf, a half-turn
  // quaternion, a string with quotes and a newline, an event with a source and a stamp.
  const std::string file = writeFile("every_type.lua", R"(packages_list = { "test_every_type" }
initConfigurator(packages_list, { { peer_name = "T", component_type = "EveryType" } })
getReferences()
T.real = -math.huge
T.count = -7
T.flag = true
T.text = "say \"hi\"\nthen go"
T.list = { 1.5, -2e-05, 3 }
T.vector = { 0.1, -0.2, 0.3 }
T.rotation = { 0, 0, 1, 0 }
T.frame = { 0.5, 0, -0.25, 1, 0, 0, 0 }
T.twist = { 0.01, 0, 0, 0, 0, 0.5 }
T.wrench = { 0, 0, -9.81, 0.1, 0, 0 }
T.joints = { 0, 0.5, -1.25 }
T.event = { name = "e_done", source = "Planner", stamp = 1.5 }
T.state = "root.opening.turn"
T.grade = "grade 3"
)");
  const std::string text = expectStable(file, "every_type_written.lua");
  for (const char* line : {"T.real = -math.huge\n", "T.count = -7\n", "T.flag = true\n", "T.text = \"say \\\"hi\\\"\\nthen go\"\n",
                           "T.list = { 1.5, -2e-05, 3 }\n", "T.vector = { 0.1, -0.2, 0.3 }\n", "T.rotation = { 0, 0, 1, 0 }\n",
                           "T.frame = { 0.5, 0, -0.25, 1, 0, 0, 0 }\n", "T.twist = { 0.01, 0, 0, 0, 0, 0.5 }\n",
                           "T.wrench = { 0, 0, -9.81, 0.1, 0, 0 }\n", "T.joints = { 0, 0.5, -1.25 }\n",
                           "T.event = { name = \"e_done\", source = \"Planner\", stamp = 1.5 }\n",
                           "T.state = \"root.opening.turn\"\n", "T.grade = \"grade 3\"\n"})
    EXPECT_NE(text.find(line), std::string::npos) << line << " in\n" << text;
  // The values came back, not only the text: the loaded component holds them.
  Loaded again(scratch("every_type_written.lua").string());
  const core::Component& t = *again.configurator.getReferences().find("T");
  EXPECT_EQ(t.getProperty<core::Event>("event").source.view(), "Planner");
  EXPECT_EQ(t.getProperty<Grade>("grade").level, 3);
  EXPECT_EQ(t.getProperty<std::string>("text"), "say \"hi\"\nthen go");
}

TEST(Description, NotANumberRoundTrips) {
  const std::string file = writeFile("nan.lua", R"(packages_list = { "test_every_type" }
initConfigurator(packages_list, { { peer_name = "T", component_type = "EveryType" } })
getReferences()
T.real = math.abs(0/0)
T.list = { 1, -math.abs(0/0) }
)");
  const std::string text = expectStable(file, "nan_written.lua");
  EXPECT_NE(text.find("T.real = math.abs(0/0)\n"), std::string::npos) << text;
  EXPECT_NE(text.find("T.list = { 1, -math.abs(0/0) }\n"), std::string::npos) << text;
}

TEST(Description, APropertyThatCannotBeWrittenIsNamed) {
  DeploymentDescription d;
  d.components = {{"G", "Gain", {}}};
  d.properties = {{"G", "m", "Matrix", "[[1, 0], [0, 1]]"}};
  EXPECT_EQ(messageOf([&] { (void)toLua(d); }),
            "component 'G': property 'm': type 'Matrix' has no Lua form: no type of that name is registered "
            "(a type of a package that is not loaded?)");
  d.properties = {{"G", "pose", "KDL.Frame", "[0, 0, 1, 0, 0, 0]"}};
  EXPECT_EQ(messageOf([&] { (void)toLua(d); }),
            "component 'G': property 'pose': expected 7 numbers [x, y, z, qx, qy, qz, qw] (m, a unit quaternion) for a "
            "KDL.Frame, got 6: '[0, 0, 1, 0, 0, 0]'");
  d.properties = {{"G", "n", "int", "1.5"}};
  EXPECT_EQ(messageOf([&] { (void)toLua(d); }),
            "component 'G': property 'n': expected an integer for an int (-2147483648 to 2147483647), got '1.5'");
  d.properties = {{"G", "e", "Event", "e_done from"}};
  EXPECT_NE(messageOf([&] { (void)toLua(d); }).find("component 'G': property 'e': expected an event ("), std::string::npos);
}

TEST(Description, DefineConfigurationNamesTheLineOfABadValue) {
  const std::string path = writeFile("bad_configuration.lua",
                                     "packages_list = { \"cobra_signal\" }\n"
                                     "initConfigurator(packages_list, { { peer_name = \"G\", component_type = \"Gain\" } })\n"
                                     "defineConfiguration(\"slow\", {\n"
                                     "  G = { k = \"2\",\n"
                                     "        bad = function() end },\n"
                                     "})\n");
  Configurator configurator;
  components::addBuiltinPackages(configurator.packages());
  script::LuaState lua;
  LuaDeployer deployer(configurator, lua);
  EXPECT_EQ(messageOf([&] { deployer.runFile(path); }),
            path + ":5: G.bad must be a number, boolean, string or array of numbers, got function");
}

// ---- A seeded set of generated projects (signal components): written, loaded, described. ----

struct TypeInfoForTest {
  const char* type;
  bool has_in, has_out;
  std::vector<std::pair<const char*, const char*>> properties;  // name, type
};

const std::vector<TypeInfoForTest>& signalTypes() {
  static const std::vector<TypeInfoForTest> types = {
      {"SineGenerator", false, true, {{"amplitude", "double"}, {"frequency", "double"}, {"phase", "double"}, {"offset", "double"}}},
      {"Gain", true, true, {{"k", "double"}}},
      {"ThresholdDetector", true, false, {{"threshold", "double"}, {"hysteresis", "double"}}},
      {"Recorder", true, false, {{"capacity", "int"}}},
      {"Constant", false, true, {{"value", "double"}}},
  };
  return types;
}

/// A canonical description (what describe gives back for its own file): non-default values only,
/// deployments over components and connections of their own, one applied.
DeploymentDescription generate(std::mt19937& random) {
  const auto pick = [&](int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(random); };
  DeploymentDescription d;
  d.packages = {"cobra_signal"};
  const int n = pick(2, 7);
  std::vector<const TypeInfoForTest*> types;
  for (int i = 0; i < n; ++i) {
    const auto* t = &signalTypes()[static_cast<std::size_t>(pick(0, static_cast<int>(signalTypes().size()) - 1))];
    types.push_back(t);
    const std::string name = "C" + std::to_string(i);
    d.components.push_back({name, t->type, {}});
    for (const auto& [property, type] : t->properties) {
      if (pick(0, 2) == 0) continue;
      // Values no fresh component has (defaults are 0, 1 and 10000).
      const std::string value = std::string(type) == "int" ? std::to_string(pick(2, 9000))
                                                           : core::DataTypeTraits<double>::print(pick(2, 800) / 8.0 + 0.125);
      d.properties.push_back({name, property, type, value});
    }
  }
  // Components in the deployment (when there is one): the last ones.
  const bool with_deployment = n >= 3 && pick(0, 1) == 1;
  const int first_deployed = with_deployment ? n - pick(1, 2) : n;
  const auto policy = [&] {
    switch (pick(0, 2)) {
      case 0: return ConnPolicySpec("data", 1);
      case 1: return ConnPolicySpec("buffer", pick(1, 64));
      default: return ConnPolicySpec("circular", pick(1, 64));
    }
  };
  std::set<std::pair<int, int>> wired;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      if (i == j || !types[i]->has_out || !types[j]->has_in || pick(0, 2) != 0) continue;
      if ((i >= first_deployed) != (j >= first_deployed)) continue;
      wired.insert({i, j});
      ConnectionSpec c{"C" + std::to_string(i) + ".out", "C" + std::to_string(j) + ".in", policy(), {}};
      if (i >= first_deployed) {
        if (d.deployments.empty()) d.deployments.push_back({});
        d.deployments[0].connections.push_back(c);
      } else {
        d.connections.push_back(c);
      }
    }
  for (int i = 0; i < first_deployed; ++i) {
    const std::string name = "C" + std::to_string(i);
    if (pick(0, 1) == 1) {
      const bool rt = pick(0, 1) == 1;
      d.activities.push_back({name, pick(1, 4) * 0.0025, rt ? pick(1, 99) : 0, rt ? "ORO_SCHED_RT" : "ORO_SCHED_OTHER", {}});
    }
    if (i > 0 && pick(0, 3) == 0) d.peers.push_back({name, {"C0"}, {}});
    const int state = pick(0, 2);  // PreOperational, Stopped, Running
    if (state >= 1) d.configure.push_back(name);
    if (state == 2) d.start.push_back(name);
  }
  if (with_deployment) {
    if (d.deployments.empty()) d.deployments.push_back({});
    DeploymentSpec& deployment = d.deployments[0];
    deployment.name = "deployed_" + std::to_string(pick(0, 99));
    deployment.scope = pick(0, 1) ? "robot" : "";
    for (int i = first_deployed; i < n; ++i) {
      const std::string name = "C" + std::to_string(i);
      deployment.components.push_back({name, {}});
      d.configure.push_back(name);  // applyDeployment configures and starts it; describe lists it as configured
      deployment.activities.push_back({name, 0.005, 0, "ORO_SCHED_OTHER", {}});
    }
    d.apply = {deployment.name};
  }
  for (int k = pick(0, 2); k > 0; --k) {
    ConfigurationSpec configuration;
    configuration.name = "configuration_" + std::to_string(k);
    for (const PropertyValueDescription& p : d.properties)
      if (pick(0, 1) == 1) configuration.values.push_back({p.component, p.property, p.value + "0", {}});
    if (!configuration.values.empty()) d.configurations.push_back(configuration);
  }
  std::sort(d.configurations.begin(), d.configurations.end(),
            [](const ConfigurationSpec& a, const ConfigurationSpec& b) { return a.name < b.name; });
  return d;
}

TEST(Description, GeneratedProjectsRoundTrip) {
  constexpr int kProjects = 60;
  std::mt19937 random(20261125);
  for (int i = 0; i < kProjects; ++i) {
    const DeploymentDescription d = generate(random);
    const std::string text = toLua(d);
    ASSERT_EQ(toLua(canonical(d)), text) << "project " << i << " is generated canonical";
    const std::string path = writeFile("generated_" + std::to_string(i) + ".lua", text);
    Loaded loaded(path);
    ASSERT_EQ(toLua(describe(loaded.configurator)), text) << "project " << i << ": " << path;
  }
}

}  // namespace
}  // namespace cobra::deploy
