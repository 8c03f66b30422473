// Supervisors asking the Configurator for switches from their steps (thesis §2.2.3, Fig. 2.6).

#include <gtest/gtest.h>

#include <mutex>
#include <random>
#include <thread>

#include "cobra/components/builtin_packages.hpp"
#include "cobra/deploy/deploy.hpp"
#include "cobra/test_support/counting_new.hpp"
#include "cobra/test_support/test_support.hpp"

using namespace cobra;
using namespace std::chrono_literals;
using deploy::Configurator;
using deploy::SwitchRequest;

namespace {

/// Turns "e_deploy_NAME" / "e_configure_NAME" events into switch requests and keeps the answers.
class SwitchingSupervisor : public core::Component, public deploy::ConfiguratorClient {
 public:
  explicit SwitchingSupervisor(std::string name)
      : Component(std::move(name), core::Role::Supervision, "asks for deployments and configurations") {
    addEventPort(input_events_);
  }
  std::vector<std::string> answers() const {
    const std::lock_guard lock(mutex_);
    return answers_;
  }
  int refused = 0;  // requests requestSwitch did not queue

 protected:
  void updateHook() override {
    core::Event event;
    while (input_events_.read(event) == core::FlowStatus::NewData) {
      const std::string_view name = event.name;
      bool queued = true;
      if (name.starts_with("e_deploy_")) queued = requestSwitch(SwitchRequest::Kind::Deployment, name.substr(9));
      if (name.starts_with("e_configure_")) queued = requestSwitch(SwitchRequest::Kind::Configuration, name.substr(12));
      if (!queued) ++refused;
    }
  }
  void onRequestDone(const SwitchRequest& request, bool ok, std::string_view message) override {
    const std::lock_guard lock(mutex_);
    answers_.push_back(std::string(ok ? "done " : "failed ") + request.name.str() + (ok ? "" : ": " + std::string(message)));
  }

 private:
  core::InputPort<core::Event> input_events_{"inputEvents", "requests, as events", ""};
  mutable std::mutex mutex_;
  std::vector<std::string> answers_;
};

void registerParts(deploy::PackageBuilder& package) {
  package.component<SwitchingSupervisor>("SwitchingSupervisor", "asks for switches");
}

struct ClientFixture {
  explicit ClientFixture(deploy::ClockMode mode) : configurator({mode, false, {}, {}}) {
    components::addBuiltinPackages(configurator.packages());
    configurator.packages().addBuiltin("client_test", registerParts);
    configurator.initConfigurator({{"cobra_signal", {"app.lua", 1}}, {"client_test", {"app.lua", 2}}},
                                  {{"Sine", "SineGenerator", {"app.lua", 3}},
                                   {"Amp", "Gain", {"app.lua", 4}},
                                   {"DepSup", "SwitchingSupervisor", {"app.lua", 5}}});
    configurator.deploymentSet().addDeployment({"amplify", {"d.lua", 1}, {{"Sine", {}}, {"Amp", {}}}, {}, {{"Sine.out", "Amp.in", {"data", 1}, {}}}});
    configurator.deploymentSet().addConfiguration({"loud", {"loud.cfg", 1}, {{"Amp", "k", "5", {"loud.cfg", 2}}}});
    configurator.deploymentSet().addConfiguration({"broken", {"broken.cfg", 1}, {{"Amp", "k", "very", {"broken.cfg", 2}}}});
    configurator.configureComponents({{"DepSup", {}}});
    configurator.startComponents({{"DepSup", {}}});
    auto& input = supervisor().port("inputEvents");
    requests = static_cast<core::InputPortBase&>(input).makeWriter("requests", "test requests");
    requests->connectTo(input, core::ConnPolicy::buffer(16));
  }
  SwitchingSupervisor& supervisor() { return static_cast<SwitchingSupervisor&>(configurator.getReferences().get("DepSup")); }
  core::Component& component(const char* name) { return configurator.getReferences().get(name); }
  void send(const std::string& event) { ASSERT_EQ(requests->writeText(event), core::WriteStatus::Written); }

  Configurator configurator;
  std::unique_ptr<core::OutputPortBase> requests;
};

TEST(ConfiguratorClient, ASupervisorsRequestIsCarriedOutBetweenInstantsAndAnswered) {
  ClientFixture f(deploy::ClockMode::Simulation);
  EXPECT_TRUE(f.supervisor().attached());
  f.send("e_deploy_amplify");
  EXPECT_EQ(f.component("Amp").state(), core::State::PreOperational);  // nothing happens outside the clock
  f.configurator.clock().advance(1ms);
  EXPECT_EQ(f.component("Amp").state(), core::State::Running);
  EXPECT_EQ(f.configurator.currentDeployment(), "amplify");
  EXPECT_EQ(f.supervisor().answers(), std::vector<std::string>{"done amplify"});

  f.send("e_configure_loud");
  f.configurator.clock().advance(1ms);
  EXPECT_EQ(f.component("Amp").getProperty<double>("k"), 5.0);
  EXPECT_EQ(f.supervisor().answers().back(), "done loud");
}

// The between-instants hook services only when a request came since its last service: over 60
// instants with requests in a seeded random third of them (and direct serviceRequests calls in
// between), each request is carried out in the instant it is made, none is left waiting.
TEST(ConfiguratorClient, EveryRequestIsCarriedOutInTheInstantItIsMade) {
  ClientFixture f(deploy::ClockMode::Simulation);
  f.configurator.deploymentSet().addConfiguration({"quiet", {"quiet.cfg", 1}, {{"Amp", "k", "0.5", {"quiet.cfg", 2}}}});
  f.send("e_deploy_amplify");
  f.configurator.clock().advance(1ms);
  std::mt19937 rng(5);
  std::size_t answered = f.supervisor().answers().size();
  double expected_k = f.component("Amp").getProperty<double>("k");
  for (int instant = 0; instant < 60; ++instant) {
    const bool request = rng() % 3 == 0;
    if (request) {
      const bool loud = rng() % 2 == 0;
      f.send(loud ? "e_configure_loud" : "e_configure_quiet");
      expected_k = loud ? 5.0 : 0.5;
    }
    if (rng() % 5 == 0) {
      EXPECT_FALSE(f.configurator.serviceRequests());  // nothing queued outside a step
    }
    f.configurator.clock().advance(1ms);
    EXPECT_EQ(f.component("Amp").getProperty<double>("k"), expected_k) << "instant " << instant;
    EXPECT_EQ(f.supervisor().answers().size(), answered + (request ? 1 : 0)) << "instant " << instant;
    answered = f.supervisor().answers().size();
  }
}

TEST(ConfiguratorClient, AFailedSwitchChangesNothingAndTheAnswerSaysWhy) {
  ClientFixture f(deploy::ClockMode::Simulation);
  f.send("e_configure_broken");
  f.send("e_deploy_nowhere");
  f.configurator.clock().advance(1ms);
  const auto answers = f.supervisor().answers();
  ASSERT_EQ(answers.size(), 2U);
  EXPECT_CONTAINS(answers[0], "failed broken: DepSup asked for configuration 'broken': ");
  EXPECT_CONTAINS(answers[0], "broken.cfg:2");
  EXPECT_CONTAINS(answers[1], "failed nowhere: DepSup asked for deployment 'nowhere': no deployment named 'nowhere'");
  EXPECT_EQ(f.component("Amp").getProperty<double>("k"), 1.0);
  EXPECT_EQ(f.configurator.currentDeployment(), "");
  EXPECT_CONTAINS(f.configurator.warnings().back(), "nowhere");
  EXPECT_EQ(f.configurator.switchCount(), 0U);  // nothing applied: observers see no change
}

// switchCount counts what was applied: observers (the runner's switch and tracking lanes) look
// the deployments and configuration up again only when it changed.
TEST(ConfiguratorClient, TheSwitchCountGrowsWithEachAppliedSwitchOnly) {
  ClientFixture f(deploy::ClockMode::Simulation);
  EXPECT_EQ(f.configurator.switchCount(), 0U);
  f.send("e_deploy_amplify");
  f.configurator.clock().advance(1ms);
  EXPECT_EQ(f.configurator.switchCount(), 1U);
  f.send("e_configure_loud");
  f.send("e_configure_broken");
  f.configurator.clock().advance(1ms);
  EXPECT_EQ(f.configurator.switchCount(), 2U);
  f.configurator.applyDeployment("amplify");  // again, the same: applied, so counted
  EXPECT_EQ(f.configurator.switchCount(), 3U);
}

TEST(ConfiguratorClient, RequestsAreRefusedWhenTheQueueIsFullOrTheNameTooLong) {
  ClientFixture f(deploy::ClockMode::Simulation);
  SwitchingSupervisor& sup = f.supervisor();
  for (std::size_t i = 0; i < deploy::ConfiguratorClient::kQueueCapacity; ++i)
    EXPECT_TRUE(sup.requestSwitch(SwitchRequest::Kind::Configuration, "loud"));
  EXPECT_FALSE(sup.requestSwitch(SwitchRequest::Kind::Configuration, "loud"));
  EXPECT_FALSE(sup.requestSwitch(SwitchRequest::Kind::Deployment, std::string(64, 'x')));
  EXPECT_TRUE(f.configurator.serviceRequests());
  EXPECT_EQ(sup.answers().size(), deploy::ConfiguratorClient::kQueueCapacity);
  EXPECT_FALSE(f.configurator.serviceRequests());
}

TEST(ConfiguratorClient, RequestingAllocatesNothing) {
  ClientFixture f(deploy::ClockMode::Simulation);
  SwitchingSupervisor& sup = f.supervisor();
  EXPECT_EQ(cobra::test_support::allocationsDuring([&] { (void)sup.requestSwitch(SwitchRequest::Kind::Configuration, "loud"); }), 0);
}

TEST(ConfiguratorClient, OnlyItsOwnSupervisorsCanBeAttached) {
  ClientFixture f(deploy::ClockMode::Simulation);
  EXPECT_CONTAINS(cobra::test_support::messageOf([&] { f.configurator.attachClient(f.component("Amp")); }),
                  "component 'Amp' cannot ask this configurator for switches: it must be one of its components and a "
                  "ConfiguratorClient (a supervisor)");
  SwitchingSupervisor stranger("Stranger");
  EXPECT_FALSE(stranger.requestSwitch(SwitchRequest::Kind::Deployment, "amplify"));
  EXPECT_CONTAINS(cobra::test_support::messageOf([&] { f.configurator.attachClient(stranger); }), "'Stranger'");
}

TEST(ConfiguratorClient, InRealTimeTheServiceThreadCarriesRequestsOut) {
  ClientFixture f(deploy::ClockMode::RealTime);
  f.send("e_deploy_amplify");
  ASSERT_TRUE(cobra::test_support::waitUntil([&] { return f.supervisor().answers().size() == 1; }));
  EXPECT_EQ(f.supervisor().answers()[0], "done amplify");
  EXPECT_EQ(f.component("Amp").state(), core::State::Running);
  f.send("e_configure_loud");
  ASSERT_TRUE(cobra::test_support::waitUntil([&] { return f.supervisor().answers().size() == 2; }));
  EXPECT_EQ(f.component("Amp").getProperty<double>("k"), 5.0);
}

}  // namespace
