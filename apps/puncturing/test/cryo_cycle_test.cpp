// The cryoablation cycle of the puncturing world as deployment/world.lua deploys it: a request
// on the console's inputEvents (what the needle chart emits in WaitCryoCycle) freezes the patient
// through the wiring of world.lua and is answered with e_cryo_done when the iceball has thawed, at
// the time world.lua's comments give (5 s of freezing to ~9.5 mm, ~14.7 s of thawing to 1.5 mm).
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <string>

#include "cobra/components/builtin_packages.hpp"
#include "cobra/deploy/deploy.hpp"
#include "cobra/deploy/lua_deployer.hpp"

namespace cobra::puncturing {
namespace {

using namespace std::chrono_literals;

const std::string kApp = std::string(COBRA_SOURCE_DIR) + "/apps/puncturing/";

TEST(PuncturingWorld, TheConsoleFreezesThePatientOnRequestAndReportsTheThaw) {
  deploy::Configurator configurator;
  components::addBuiltinPackages(configurator.packages());
  script::LuaState lua;
  deploy::LuaDeployer deployer(configurator, lua);
  // What puncturing.lua gives world.lua: the scenario and the needle's tool frame (z along the needle).
  deployer.run("scenario = [[" + kApp + "scenarios/two_needles]]\n"
               "needle_tool_frame = { 0, 0, 0, 0, math.sin(math.pi / 4), 0, math.cos(math.pi / 4) }",
               "=test");
  deployer.runFile(kApp + "deployment/world.lua");
  core::ComponentRegistry& refs = configurator.getReferences();

  core::OutputPort<core::Event> chart{"chart", "the needle chart's outputEvents", ""};
  core::InputPort<core::Event> answers{"answers", "the console's events", ""};
  core::InputPort<double> radius{"radius", "the patient's iceball", "m"};
  core::connectPorts(chart, refs.get("Cryo").port("inputEvents"), core::ConnPolicy::buffer(8));
  core::connectPorts(refs.get("Cryo").port("events"), answers, core::ConnPolicy::buffer(8));
  core::connectPorts(refs.get("Patient").port("iceballRadius"), radius);
  configurator.clock().advance(100ms);

  core::Event request;
  request.name = "e_cryo_start";
  request.source = "NeedleTaskSup";
  chart.write(request);
  const auto asked = configurator.clock().now();
  double biggest = 0.0, r = 0.0, done_after = -1.0;
  while (configurator.clock().now() - asked < 30s && done_after < 0.0) {
    configurator.clock().advance(1ms);
    if (radius.read(r) != core::FlowStatus::NoData) biggest = std::max(biggest, r);
    for (core::Event e; answers.read(e) == core::FlowStatus::NewData;)
      if (e.name == "e_cryo_done") done_after = std::chrono::duration<double>(configurator.clock().now() - asked).count();
  }
  // world.lua: Patient.freeze_time_constant 5 s, thaw 8 s, 15 mm plateau; Cryo 5 s, 1.5 mm.
  EXPECT_NEAR(biggest, 0.015 * (1.0 - std::exp(-1.0)), 1e-4);
  EXPECT_NEAR(done_after, 5.0 + 8.0 * std::log(0.015 * (1.0 - std::exp(-1.0)) / 0.0015), 0.02);
  EXPECT_LE(r, 0.0015);
  EXPECT_LT(r, refs.get("Patient").getProperty<double>("release_radius"));  // the needle is free then
}

}  // namespace
}  // namespace cobra::puncturing
