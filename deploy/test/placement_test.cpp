// One application split over hosts (placement.hpp): which components are local, remote or on
// every host, the transport ends the Configurator makes for the connections between hosts, and
// the errors of a bad placement (their text).
#include "cobra/deploy/placement.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "cobra/components/builtin_packages.hpp"
#include "cobra/core/transport.hpp"
#include "cobra/deploy/configurator.hpp"
#include "test_components.hpp"
#include "cobra/test_support/test_support.hpp"

using namespace cobra;
using namespace std::chrono_literals;
using deploy::ComponentSpec;
using deploy::ConnectionSpec;
using deploy::Configurator;
using deploy::NameEntry;
using deploy::Placement;
using deploy::PlacementSpec;
using deploy::SourceLocation;
using ::testing::ElementsAre;
using ::testing::HasSubstr;

namespace {

SourceLocation at(int line) { return {"app.lua", line}; }

/// A transport that records the ends asked of it (and attaches none): what the Configurator
/// makes for the connections between hosts, without a network.
class RecordingTransport final : public core::Transport {
 public:
  void check(const core::ConnPolicy& policy) const override {
    for (const auto& [key, value] : policy.options)
      if (key != "depth") throw core::Error("unknown option '" + key + "'; options: depth");
  }
  void makeWriterEnd(core::OutputPortBase& output, const core::ConnPolicy& policy, core::PortBase*) override {
    ends.push_back("writer " + output.fullName() + " on " + policy.topic + " " + policy.describe() + options(policy));
  }
  void makeReaderEnd(core::InputPortBase& input, const core::ConnPolicy& policy, core::PortBase*) override {
    ends.push_back("reader " + input.fullName() + " on " + policy.topic + " " + policy.describe() + options(policy));
  }
  std::vector<std::string> ends;

 private:
  static std::string options(const core::ConnPolicy& policy) {
    std::string text;
    for (const auto& [key, value] : policy.options) text += " " + key + "=" + value;
    return text;
  }
};

/// Two hosts: "a" runs Sine and A*, "b" runs B*, and Link (a Gain here) runs on both.
PlacementSpec twoHosts(const std::string& transport = "recording") {
  PlacementSpec spec;
  spec.hosts = {{"a", {"Sine", "A*"}, at(3)}, {"b", {"B*"}, at(4)}};
  spec.everywhere = {"Link"};
  spec.transport = transport;
  spec.qos = {{"depth", "4"}};
  spec.where = at(2);
  return spec;
}

std::vector<ComponentSpec> components() {
  return {{"Sine", "SineGenerator", at(10)}, {"AGain", "Gain", at(11)},     {"BGain", "Gain", at(12)},
          {"BRec", "Recorder", at(13)},      {"Link", "Gain", at(14)},      {"BSup", "TaskSupervisor", at(15)},
          {"ASup", "TaskSupervisor", at(16)}, {"AWatch", "PoseWatchingSupervisor", at(17)},
          {"BWatch", "PoseWatchingSupervisor", at(18)}};
}

struct Host {
  explicit Host(const std::string& name, bool strict_roles = false) : configurator(options(name, strict_roles)) {
    components::addBuiltinPackages(configurator.packages());
    configurator.packages().addBuiltin("deploy_test_parts", deploy::test::registerTestParts);
    configurator.setPlacement(twoHosts());
    configurator.initConfigurator({{"cobra_signal", at(8)}, {"deploy_test_parts", at(9)}}, components());
  }
  static deploy::ConfiguratorOptions options(const std::string& host, bool strict_roles) {
    deploy::ConfiguratorOptions o;
    o.host = host;
    o.strict_roles = strict_roles;
    return o;
  }
  Configurator configurator;
};

class PlacementTest : public ::testing::Test {
 protected:
  void SetUp() override {
    transport = std::make_shared<RecordingTransport>();
    core::TransportRegistry::add("recording", "records ends", "placement_test", transport);
  }
  void TearDown() override { core::TransportRegistry::remove("recording"); }
  std::shared_ptr<RecordingTransport> transport;
};

}  // namespace

TEST(PlacementPatterns, NameOrPrefixStar) {
  EXPECT_TRUE(deploy::matchesPlacementPattern("Needle*", "NeedleTaskSup"));
  EXPECT_TRUE(deploy::matchesPlacementPattern("Needle*", "Needle"));
  EXPECT_FALSE(deploy::matchesPlacementPattern("Needle*", "needleX"));
  EXPECT_TRUE(deploy::matchesPlacementPattern("ISUR", "ISUR"));
  EXPECT_FALSE(deploy::matchesPlacementPattern("ISUR", "ISUR2"));
}

TEST(PlacementPatterns, SitesAndErrors) {
  const Placement a(twoHosts(), "a");
  EXPECT_EQ(a.siteOf("AGain", at(20)), Placement::Site::Local);
  EXPECT_EQ(a.siteOf("BGain", at(20)), Placement::Site::Remote);
  EXPECT_EQ(a.siteOf("Link", at(20)), Placement::Site::Everywhere);
  EXPECT_EQ(a.hostOf("BGain", at(20)), "b");
  EXPECT_EQ(test_support::messageOf([&] { (void)a.hostOf("Cryo", at(21)); }),
            "app.lua:21: component 'Cryo' is placed on no host of the placement (app.lua:2): add it, or a pattern "
            "matching it, to one host's list or to everywhere");
  PlacementSpec twice = twoHosts();
  twice.hosts[1].patterns.push_back("AGain");
  const Placement b(twice, "b");
  EXPECT_EQ(test_support::messageOf([&] { (void)b.hostOf("AGain", at(22)); }),
            "app.lua:22: component 'AGain' is placed on 2 sites: host 'a' (app.lua:3) and host 'b' (app.lua:4); "
            "place each component once");
  EXPECT_THAT(test_support::messageOf([] { Placement(twoHosts(), "c"); }),
              HasSubstr("app.lua:2: this process's host 'c' is not a host of the placement (a, b)"));
  PlacementSpec star = twoHosts();
  star.hosts[0].patterns.push_back("A*B");
  EXPECT_THAT(test_support::messageOf([&] { Placement(star, "a"); }),
              HasSubstr("app.lua:3: placement host 'a': pattern 'A*B' must be a component name or a prefix followed by '*'"));
  const core::ConnPolicy policy = a.crossHostPolicy(core::ConnPolicy::buffer(8), "AGain.out");
  EXPECT_EQ(policy.describe(), "buffer(8) over recording topic 'AGain/out'");
  EXPECT_THAT(policy.options, ElementsAre(std::pair<std::string, std::string>{"depth", "4"}));
}

TEST_F(PlacementTest, RemoteComponentsAreShadowsThatNeverRun) {
  Host a("a");
  Configurator& c = a.configurator;
  EXPECT_NE(c.getReferences().find("AGain"), nullptr);
  EXPECT_NE(c.getReferences().find("Link"), nullptr) << "everywhere: local on every host";
  EXPECT_EQ(c.getReferences().find("BGain"), nullptr) << "remote: not among this process's components";
  ASSERT_NE(c.remoteComponents().find("BGain"), nullptr) << "but its shadow knows its ports";
  EXPECT_TRUE(c.isRemote("BGain"));
  EXPECT_FALSE(c.isRemote("Link"));
  EXPECT_EQ(c.componentTypeOf("BRec"), "Recorder");

  const std::vector<NameEntry> all{{"Sine", at(30)}, {"AGain", at(31)}, {"BGain", at(32)}, {"BRec", at(33)}};
  c.setActivities({{"Sine", 0.001, 0, "other", at(25)}, {"BGain", 0.001, 0, "other", at(26)}});
  c.configureComponents(all);
  c.startComponents(all);
  EXPECT_TRUE(c.getReferences().get("AGain").isRunning());
  EXPECT_EQ(c.remoteComponents().get("BGain").state(), core::State::PreOperational) << "its host configures it";
  EXPECT_EQ(c.activityOf("BGain"), nullptr);
  c.clock().advance(5ms);
  EXPECT_EQ(c.remoteComponents().get("BGain").updateCount(), 0u);
  EXPECT_EQ(c.getReferences().get("Sine").updateCount(), 5u);
  c.stopComponents(all);
  c.cleanupComponents(all);
  // Unknown names stay errors, remote or not.
  EXPECT_THAT(test_support::messageOf([&] { c.configureComponents({{"BGian", at(40)}}); }),
              HasSubstr("app.lua:40: no component named 'BGian'"));
}

TEST_F(PlacementTest, ConnectionsBetweenHostsBecomeTransportEnds) {
  Host a("a");
  Configurator& c = a.configurator;
  c.connectPorts({{"Sine.out", "AGain.in", {"data", 1}, at(50)},
                  {"Sine.out", "BGain.in", {"buffer", 8}, at(51)},
                  {"Sine.out", "BRec.in", {"buffer", 8}, at(52)},
                  {"BGain.out", "AGain.in", {"data", 1}, at(53)},
                  {"BGain.out", "BRec.in", {"data", 1}, at(54)},
                  {"Link.out", "BRec.in", {"data", 1}, at(55)},
                  {"BSup.outputEvents", "ASup.inputEvents", {"buffer", 64}, at(56)}});
  EXPECT_TRUE(c.getReferences().get("Sine").findPort("out")->connectedTo(*c.getReferences().get("AGain").findPort("in")));
  EXPECT_THAT(transport->ends,
              ElementsAre("writer Sine.out on Sine/out buffer(8) over recording topic 'Sine/out' depth=4",
                          "reader AGain.in on BGain/out data over recording topic 'BGain/out' depth=4",
                          "reader ASup.inputEvents on BSup/outputEvents buffer(64) over recording topic "
                          "'BSup/outputEvents' depth=4"))
      << "one writer end for Sine.out read by two remote inputs; remote -> remote and Link -> remote: nothing";
  EXPECT_THAT(c.writerTopics(), ElementsAre("Sine/out"));
  EXPECT_THAT(c.readerTopics(), ElementsAre("BGain/out", "BSup/outputEvents"));

  // The remote side's ports are checked: names and types.
  EXPECT_THAT(test_support::messageOf([&] { c.connectPorts({{"Sine.out", "BGain.inn", {}, at(60)}}); }),
              HasSubstr("app.lua:60: component 'BGain' has no port 'inn'"));
  EXPECT_THAT(test_support::messageOf([&] { c.connectPorts({{"BSup.outputEvents", "AGain.in", {}, at(61)}}); }),
              HasSubstr("app.lua:61: "));
  EXPECT_THAT(test_support::messageOf([&] { c.connectPorts({{"BSup.outputEvents", "AGain.in", {}, at(61)}}); }), HasSubstr("types differ"));
}

TEST_F(PlacementTest, TheOtherHostMakesTheMirrorEnds) {
  Host b("b");
  b.configurator.connectPorts({{"Sine.out", "BGain.in", {"buffer", 8}, at(51)},
                               {"Sine.out", "BRec.in", {"buffer", 8}, at(52)},
                               {"BGain.out", "AGain.in", {"data", 1}, at(53)},
                               {"Link.out", "BRec.in", {"data", 1}, at(55)}});
  EXPECT_THAT(transport->ends,
              ElementsAre("reader BGain.in on Sine/out buffer(8) over recording topic 'Sine/out' depth=4",
                          "reader BRec.in on Sine/out buffer(8) over recording topic 'Sine/out' depth=4",
                          "writer BGain.out on BGain/out data over recording topic 'BGain/out' depth=4"));
  EXPECT_TRUE(b.configurator.getReferences().get("Link").findPort("out")->connectedTo(
      *b.configurator.getReferences().get("BRec").findPort("in")))
      << "Link runs on every host: its connections to this host's components are local";
}

// The role rules do not change with where a component runs: a connection to another host's
// component is linted with its shadow (its ports and role) and warned of, or refused in strict
// mode, as a local one is, the message naming both hosts. Each host lints the connections it
// makes an end of.
TEST_F(PlacementTest, ConnectionsBetweenHostsAreRoleLinted) {
  const std::string rule = "(Calculation) -> BWatch.level (Supervision): a Supervision component may read only logic "
                           "data, but double is pure data";
  const std::string crossing = "app.lua:80: AGain.out " + rule + " (the connection crosses hosts: host 'a' -> host 'b')";
  for (const std::string host : {"a", "b"}) {
    Host h(host);
    const auto violations = h.configurator.connectPorts({{"AGain.out", "BWatch.level", {"data", 1}, at(80)}});
    ASSERT_EQ(violations.size(), 1u) << "host " << host;
    EXPECT_EQ(violations[0].message, crossing) << "host " << host;
    EXPECT_EQ(h.configurator.warnings().back(), "role rule: " + crossing) << "host " << host;
  }
  EXPECT_THAT(transport->ends, ElementsAre("writer AGain.out on AGain/out data over recording topic 'AGain/out' depth=4",
                                           "reader BWatch.level on AGain/out data over recording topic 'AGain/out' "
                                           "depth=4"))
      << "warned of, and made";

  Host b("b");
  const auto local = b.configurator.connectPorts({{"BGain.out", "BWatch.level", {"data", 1}, at(81)}});
  ASSERT_EQ(local.size(), 1u);
  EXPECT_EQ(local[0].message, "app.lua:81: BGain.out " + rule) << "the same rule between two components of one host";
  Host a("a");
  EXPECT_TRUE(a.configurator.connectPorts({{"BGain.out", "BWatch.level", {"data", 1}, at(81)}}).empty())
      << "host b's connection, linted there";

  transport->ends.clear();
  Host strict("a", true);
  EXPECT_EQ(test_support::messageOf([&] {
              strict.configurator.connectPorts({{"AGain.out", "BWatch.level", {"data", 1}, at(80)}});
            }),
            "connectPorts: nothing was connected: 1 role rule violation (strict mode refuses them):\n" + crossing);
  EXPECT_TRUE(transport->ends.empty()) << "refused: no transport end";
}

TEST_F(PlacementTest, PeersDoNotCrossHosts) {
  Host a("a");
  EXPECT_EQ(test_support::messageOf([&] { a.configurator.addPeers({{"ASup", {"AGain", "BGain"}, at(70)}}); }),
            "app.lua:70: 'BGain' (host 'b') cannot be a peer of 'ASup' (host 'a'): operations do not cross hosts; "
            "place both on one host, or exchange events through ports");
  EXPECT_TRUE(a.configurator.peersOf("ASup").empty()) << "a bad entry adds nothing";
  a.configurator.addPeers({{"ASup", {"AGain", "Link"}, at(71)}, {"BSup", {"BGain", "AGain"}, at(72)}});
  EXPECT_THAT(a.configurator.peersOf("ASup"), ElementsAre("AGain", "Link"));
  EXPECT_TRUE(a.configurator.peersOf("BSup").empty()) << "host b adds its own peers";
}

TEST_F(PlacementTest, DeploymentsBelongToOneHost) {
  Host a("a");
  Configurator& c = a.configurator;
  deploy::DeploymentSpec b_only{"b_run", at(79), {{"BGain", at(80)}, {"BRec", at(81)}}, {}, {}, "b"};
  deploy::DeploymentSpec mixed{"mixed", at(82), {{"AGain", at(83)}, {"BGain", at(84)}, {"Link", at(85)}}, {}, {}, ""};
  deploy::DeploymentSpec crossing{"crossing", at(86), {{"AGain", at(87)}}, {}, {{"BGain.out", "AGain.in", {}, at(88)}}, "x"};
  c.deploymentSet().addDeployment(b_only);
  c.deploymentSet().addDeployment(mixed);
  c.deploymentSet().addDeployment(crossing);
  EXPECT_TRUE(c.applyDeployment("b_run").empty());
  EXPECT_EQ(c.currentDeployment("b"), "") << "another host's deployment is not this process's";
  EXPECT_EQ(c.remoteComponents().get("BGain").state(), core::State::PreOperational);
  EXPECT_EQ(test_support::messageOf([&] { c.applyDeployment("mixed"); }),
            "deployment 'mixed' (app.lua:82) not applied: app.lua:82: it runs components of 2 hosts (host 'a': AGain; "
            "host 'b': BGain); a deployment is switched by one process, so it runs one host's components: split it per "
            "host; nothing was changed");
  EXPECT_THAT(test_support::messageOf([&] { c.applyDeployment("crossing"); }),
              HasSubstr("app.lua:88: BGain.out -> AGain.in names 'BGain' of host 'b'; a deployment switches the "
                        "connections of its own host: make connections between hosts with connectPorts"));
}

TEST_F(PlacementTest, ABadPlacementOrNoneIsRefused) {
  deploy::ConfiguratorOptions options;
  options.host = "a";
  Configurator without(options);
  components::addBuiltinPackages(without.packages());
  EXPECT_EQ(test_support::messageOf([&] { without.initConfigurator({{"cobra_signal", at(1)}}, {{"Sine", "SineGenerator", at(2)}}); }),
            "app.lua:2: this process is host 'a' but no placement says which components live there; declare "
            "placement = { hosts = { ... } } before the first initConfigurator (deploy/README.md, Placement)");

  Configurator unplaced(options);
  components::addBuiltinPackages(unplaced.packages());
  unplaced.setPlacement(twoHosts());
  EXPECT_THAT(test_support::messageOf([&] {
                unplaced.initConfigurator({{"cobra_signal", at(1)}},
                                          {{"Sine", "SineGenerator", at(2)}, {"Cryo", "Gain", at(3)}});
              }),
              HasSubstr("app.lua:3: component 'Cryo' is placed on no host of the placement (app.lua:2)"));
  EXPECT_TRUE(unplaced.getReferences().components().empty()) << "nothing created";
  EXPECT_THAT(test_support::messageOf([&] { unplaced.setPlacement(twoHosts()); }), HasSubstr("a placement is in force already"));

  Configurator late2(options);
  components::addBuiltinPackages(late2.packages());
  late2.getReferences().add(std::make_unique<deploy::test::Faulty>("Early"));
  EXPECT_THAT(test_support::messageOf([&] { late2.setPlacement(twoHosts()); }),
              HasSubstr("app.lua:2: the placement comes after components were created ('Early')"));

  // The placement's transport and QoS are checked when a connection between hosts is made.
  Configurator typo(options);
  components::addBuiltinPackages(typo.packages());
  PlacementSpec spec = twoHosts("no_such_transport");
  typo.setPlacement(spec);
  typo.initConfigurator({{"cobra_signal", at(1)}}, {{"Sine", "SineGenerator", at(2)}, {"BGain", "Gain", at(3)}});
  EXPECT_THAT(test_support::messageOf([&] { typo.connectPorts({{"Sine.out", "BGain.in", {}, at(4)}}); }),
              HasSubstr("app.lua:4: Sine.out -> BGain.in crosses hosts (a -> b): cannot connect Sine.out (double) to "
                        "no_such_transport topic 'Sine/out': unknown transport 'no_such_transport'"));
}

namespace {

/// A link that keeps the clocks in step (here: counts the meetings).
class CountingSync final : public core::Component, public core::ClockSync {
 public:
  explicit CountingSync(std::string name) : Component(std::move(name), core::Role::Bridge, "test sync") {}
  void reached(std::chrono::nanoseconds) noexcept override { ++meetings; }
  void setDone(bool) noexcept override {}
  bool peersDone() const noexcept override { return true; }
  std::vector<std::string> lostPeers() const override { return {}; }
  int meetings = 0;
};

void registerSync(deploy::PackageBuilder& package) { package.component<CountingSync>("CountingSync", "test sync"); }

}  // namespace

TEST_F(PlacementTest, TheLocalLinkKeepsTheLockstepClockInStep) {
  deploy::ConfiguratorOptions options;
  options.host = "b";
  Configurator c(options);
  components::addBuiltinPackages(c.packages());
  c.packages().addBuiltin("sync_parts", registerSync);
  c.setPlacement(twoHosts());
  c.initConfigurator({{"cobra_signal", at(1)}, {"sync_parts", at(2)}},
                     {{"BGain", "Gain", at(3)}, {"Link", "CountingSync", at(4)}});
  ASSERT_EQ(c.clockSync(), dynamic_cast<core::ClockSync*>(&c.getReferences().get("Link")));
  EXPECT_EQ(c.clock().clockSync(), c.clockSync());
  c.clock().advance(1ms);
  c.clock().advance(1ms);
  EXPECT_EQ(dynamic_cast<CountingSync&>(c.getReferences().get("Link")).meetings, 2);

  Configurator single;  // no host: one process, nothing to meet
  components::addBuiltinPackages(single.packages());
  single.packages().addBuiltin("sync_parts", registerSync);
  single.initConfigurator({{"sync_parts", at(2)}}, {{"Link", "CountingSync", at(4)}});
  EXPECT_EQ(single.clockSync(), nullptr);
  EXPECT_EQ(single.clock().clockSync(), nullptr);
}

TEST(PlacementIgnored, WithoutAHostEverythingRunsHere) {
  Configurator c;
  components::addBuiltinPackages(c.packages());
  c.setPlacement(twoHosts());
  EXPECT_EQ(c.placement(), nullptr);
  c.initConfigurator({{"cobra_signal", at(1)}}, {{"Sine", "SineGenerator", at(2)}, {"BGain", "Gain", at(3)},
                                                 {"Unplaced", "Gain", at(4)}});
  c.connectPorts({{"Sine.out", "BGain.in", {}, at(5)}});
  EXPECT_NE(c.getReferences().find("BGain"), nullptr);
  EXPECT_FALSE(c.isRemote("BGain"));
  EXPECT_TRUE(c.remoteComponents().components().empty());
  EXPECT_TRUE(c.getReferences().get("Sine").findPort("out")->connectedTo(*c.getReferences().get("BGain").findPort("in")));
}
