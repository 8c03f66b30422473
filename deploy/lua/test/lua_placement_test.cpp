// The entry file's `placement` table (placement.hpp) read by the Lua deployer when the process is
// one host of a split application: the global `host`, remote components whose properties take
// what the files set, and the file:line of a bad or missing placement.
#include "cobra/components/builtin_packages.hpp"
#include "cobra/deploy/lua_deployer.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "cobra/core/transport.hpp"
#include "cobra/test_support/test_support.hpp"

namespace cobra::deploy {
namespace {

using cobra::test_support::messageOf;

/// A transport that accepts every end and makes none (the placement's connections are counted).
class NullTransport final : public core::Transport {
 public:
  void check(const core::ConnPolicy&) const override {}
  void makeWriterEnd(core::OutputPortBase&, const core::ConnPolicy& policy, core::PortBase*) override {
    topics.push_back("writer " + policy.topic);
  }
  void makeReaderEnd(core::InputPortBase&, const core::ConnPolicy& policy, core::PortBase*) override {
    topics.push_back("reader " + policy.topic);
  }
  std::vector<std::string> topics;
};

struct Host {
  explicit Host(const std::string& name) : configurator(options(name)) {
    components::addBuiltinPackages(configurator.packages());
  }
  static ConfiguratorOptions options(const std::string& name) {
    ConfiguratorOptions o;
    o.host = name;
    return o;
  }
  Configurator configurator;
  script::LuaState lua;
  LuaDeployer deployer{configurator, lua};
};

/// Writes `text` as a deployment file of this test and returns its path.
std::string file(const std::string& name, const std::string& text) {
  const auto path = std::filesystem::temp_directory_path() / ("cobra_lua_placement_" + std::to_string(::getpid()) + "_" + name);
  std::ofstream(path) << text;
  return path.string();
}

const std::string kSplit = R"(placement = {
  hosts = {
    a = { "Sine", "A*" },
    b = { "B*" },
  },
  transport = "null_wire",
}
initConfigurator({ "cobra_signal" }, {
  { peer_name = "Sine", component_type = "SineGenerator" },
  { peer_name = "AGain", component_type = "Gain" },
  { peer_name = "BGain", component_type = "Gain" },
})
getReferences()
BGain.k = 4
AGain.k = 2
connectPorts({ { output = "Sine.out", input = "BGain.in" }, { output = "Sine.out", input = "AGain.in" } })
configureComponents({ "Sine", "AGain", "BGain" })
startComponents({ "Sine", "AGain", "BGain" })
)";

class LuaPlacement : public ::testing::Test {
 protected:
  void SetUp() override { core::TransportRegistry::add("null_wire", "test", "lua_placement_test", wire); }
  void TearDown() override { core::TransportRegistry::remove("null_wire"); }
  std::shared_ptr<NullTransport> wire = std::make_shared<NullTransport>();
};

TEST_F(LuaPlacement, TheEntryFilesPlacementSaysWhatRunsHere) {
  Host a("a");
  a.deployer.runFile(file("split.lua", kSplit));
  ASSERT_NE(a.configurator.placement(), nullptr);
  EXPECT_EQ(a.lua.evaluate("host"), "a");
  EXPECT_EQ(a.configurator.getReferences().get("AGain").state(), core::State::Running);
  EXPECT_TRUE(a.configurator.isRemote("BGain"));
  EXPECT_EQ(a.configurator.remoteComponents().get("BGain").state(), core::State::PreOperational);
  EXPECT_EQ(a.lua.evaluate("BGain.k"), "4.0") << "a remote shadow takes what the file sets, and nothing runs it";
  EXPECT_EQ(wire->topics, std::vector<std::string>{"writer Sine/out"});
  const auto& spec = a.configurator.placement()->spec();
  ASSERT_EQ(spec.hosts.size(), 2u);
  EXPECT_EQ(spec.hosts[0].where.line, 3) << "host a's line in the entry file";
  EXPECT_EQ(spec.hosts[1].where.line, 4);
  EXPECT_EQ(spec.where.line, 1);

  Host b("b");
  b.deployer.runFile(file("split.lua", kSplit));
  EXPECT_EQ(b.configurator.getReferences().get("BGain").state(), core::State::Running);
  EXPECT_EQ(b.configurator.getReferences().find("AGain"), nullptr);
}

TEST_F(LuaPlacement, WithoutAHostThePlacementIsIgnored) {
  Configurator single;
  components::addBuiltinPackages(single.packages());
  script::LuaState lua;
  LuaDeployer deployer(single, lua);
  deployer.runFile(file("single.lua", kSplit));
  EXPECT_EQ(single.placement(), nullptr);
  EXPECT_EQ(lua.evaluate("tostring(host)"), "nil");
  for (const char* name : {"Sine", "AGain", "BGain"})
    EXPECT_EQ(single.getReferences().get(name).state(), core::State::Running) << name;
  EXPECT_TRUE(wire->topics.empty()) << "every connection local";
}

TEST_F(LuaPlacement, AnUnplacedComponentOrNoPlacementIsAFileLineError) {
  Host a("a");
  std::string unplaced = kSplit;
  unplaced.replace(unplaced.find("\"BGain\", component_type"), 7, "\"Cryo\"");
  const std::string path = file("unplaced.lua", unplaced);
  const std::string unplaced_error = messageOf([&] { a.deployer.runFile(path); });
  EXPECT_CONTAINS(unplaced_error,
            path + ":11: component 'Cryo' is placed on no host of the placement (" + path +
                ":1): add it, or a pattern matching it, to one host's list or to everywhere");

  Host none("a");
  const std::string bare = file("bare.lua", kSplit.substr(kSplit.find("initConfigurator")));
  const std::string none_error = messageOf([&] { none.deployer.runFile(bare); });
  EXPECT_CONTAINS(none_error,
            bare + ":2: this process is host 'a' but no placement says which components live there; declare "
                   "placement = { hosts = { ... } } before the first initConfigurator (deploy/README.md, Placement)");

  Host typo("a");
  std::string key = kSplit;
  key.replace(key.find("transport ="), 9, "transprt");
  const std::string typo_path = file("typo.lua", key);
  const std::string typo_error = messageOf([&] { typo.deployer.runFile(typo_path); });
  EXPECT_CONTAINS(typo_error,
            typo_path + ":1: placement: unknown key 'transprt'; placement has hosts, everywhere, transport and qos");
}

}  // namespace
}  // namespace cobra::deploy
