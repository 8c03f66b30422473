// conn_policy in a deployment file: `transport = "dds", topic = ..., qos = {...}` connects two
// components through the dds transport; an unknown transport, a bad qos key or value, and a topic
// without a transport are refused with the file:line of the connection and what is allowed.
#include <gtest/gtest.h>

#include "cobra/components/signal/package.hpp"
#include "cobra/core/core.hpp"
#include "cobra/deploy/lua_deployer.hpp"
#include "cobra/test_support/test_support.hpp"
#include "dds_test_support.hpp"

namespace cobra::dds {
namespace {

using namespace std::chrono_literals;
using test_support::messageOf;

struct Fixture {
  explicit Fixture(int domain) : dds("dds", domain, "cobra") {
    configurator.packages().addBuiltin("cobra_signal", components::registerSignalPackage);
  }
  test::RegisteredTransport dds;
  deploy::Configurator configurator;
  script::LuaState lua;
  deploy::LuaDeployer deployer{configurator, lua};
};

constexpr const char* kComponents = R"(
initConfigurator({ "cobra_signal" }, {
  { peer_name = "Source", component_type = "Constant" },
  { peer_name = "Amp", component_type = "Gain" },
})
)";

TEST(DdsDeploy, AConnectionOfADeploymentFileGoesThroughDds) {
  Fixture f(124);
  f.deployer.run(kComponents, "components.lua");
  f.deployer.run(R"(
connectPorts({
  { output = "Source.out", input = "Amp.in",
    conn_policy = { type = "buffer", size = 8, transport = "dds", topic = "signal/source",
                    qos = { reliability = "reliable", depth = 8, lease = 0.5 } } },
})
)",
                 "connect.lua");
  core::ComponentRegistry& refs = f.configurator.getReferences();
  core::PortBase& out = refs.get("Source").port("out");
  core::PortBase& in = refs.get("Amp").port("in");
  ASSERT_TRUE(out.connectedTo(in));
  const core::ConnPolicy& policy = out.connections().front()->policy();
  EXPECT_EQ(policy.describe(), "buffer(8) over dds topic 'signal/source'");
  EXPECT_EQ(policy.options, (std::vector<std::pair<std::string, std::string>>{
                                {"depth", "8"}, {"lease", "0.5"}, {"reliability", "reliable"}}));
  ASSERT_TRUE(f.dds.transport->waitForMatch("signal/source", 5s));

  auto* source_out = dynamic_cast<core::OutputPort<double>*>(&out);
  ASSERT_NE(source_out, nullptr);
  source_out->write(2.5);
  auto* amp_in = dynamic_cast<core::InputPort<double>*>(&in);
  double got = 0;
  ASSERT_TRUE(test::pollUntil([&] { return amp_in->read(got) == core::FlowStatus::NewData; }));
  EXPECT_EQ(got, 2.5);
}

TEST(DdsDeploy, SwitchingToADeploymentWithoutTheConnectionRemovesBothEnds) {
  Fixture f(126);
  f.deployer.run(R"(
initConfigurator({ "cobra_signal" }, {
  { peer_name = "Source", component_type = "Constant" },
  { peer_name = "Amp", component_type = "Gain" },
})
defineDeployment("remote", {
  components = { "Source", "Amp" },
  connections = { { output = "Source.out", input = "Amp.in",
                    conn_policy = { transport = "dds", topic = "signal/remote" } } },
})
defineDeployment("alone", { components = { "Source" } })
applyDeployment("remote")
)",
                 "switch.lua");
  core::ComponentRegistry& refs = f.configurator.getReferences();
  core::PortBase& out = refs.get("Source").port("out");
  core::PortBase& in = refs.get("Amp").port("in");
  ASSERT_TRUE(out.connectedTo(in));
  ASSERT_TRUE(f.dds.transport->waitForMatch("signal/remote", 5s));
  f.deployer.run("applyDeployment('alone')", "switch2.lua");
  EXPECT_FALSE(out.connected());
  EXPECT_FALSE(in.connected());
  EXPECT_FALSE(f.dds.transport->waitForMatch("signal/remote", 50ms));  // no end left on the topic
}

TEST(DdsDeploy, BadTransportsAndQosAreRefusedWithTheFileAndLine) {
  Fixture f(125);
  f.deployer.run(kComponents, "components.lua");
  const auto connect = [&](const std::string& policy) {
    return messageOf([&] {
      f.deployer.run("connectPorts({\n  { output = \"Source.out\", input = \"Amp.in\", conn_policy = " + policy + " } })",
                     "conn.lua");
    });
  };
  EXPECT_EQ(connect(R"({ transport = "zmq", topic = "x" })"),
            "conn.lua:2: conn_policy: unknown transport 'zmq'; transports: 'dds' (Fast DDS, domain 125, from cobra_dds)");
  EXPECT_EQ(connect(R"({ transport = "dds", topic = "x", qos = { relability = "reliable" } })"),
            "conn.lua:2: conn_policy: unknown dds qos key 'relability'; allowed keys: reliability (\"reliable\" or "
            "\"best_effort\"), depth (an integer >= 1), lease (s, a number > 0), durability (\"volatile\" or "
            "\"transient_local\")");
  EXPECT_EQ(connect(R"({ transport = "dds", topic = "x", qos = { depth = 2.5 } })"),
            "conn.lua:2: conn_policy: dds qos.depth = \"2.5\": expected an integer >= 1 (samples)");
  EXPECT_EQ(connect(R"({ topic = "x" })"),
            "conn.lua:2: conn_policy.topic needs a transport: add transport = \"dds\" (or another registered transport)");
  EXPECT_EQ(connect(R"({ transport = "dds", topic = "x", qos = { lease = true } })"),
            "conn.lua:2: conn_policy.qos.lease must be a string or a number, got boolean");
  EXPECT_FALSE(f.configurator.getReferences().get("Source").port("out").connected());
}

}  // namespace
}  // namespace cobra::dds
