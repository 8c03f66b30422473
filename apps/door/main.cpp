// The door example (thesis §2.2, Figs. 2.5-2.6): a task chart opens a simulated door through a
// deployment supervisor and a configuration supervisor, on the lockstep clock.
//
//   cobra-door [door.lua] [plot.svg]
//
// It prints every task state with its simulated time, the deployments and configurations the
// supervisors applied, and draws the arm, handle and door over time (default /tmp/cobra-door.svg).
// Exit status 0 when the task reached root.done.

#include <cstdio>
#include <string>

#include "cobra/components/builtin_packages.hpp"
#include "cobra/components/coordination/supervisor.hpp"
#include "cobra/deploy/deploy.hpp"
#include "cobra/deploy/lua_deployer.hpp"
#include "cobra/plot/svg_plot.hpp"
#include "door_sim.hpp"

using namespace cobra;
using namespace std::chrono_literals;

int main(int argc, char** argv) {
  const std::string file = argc > 1 ? argv[1] : std::string(COBRA_DOOR_DIR) + "/door.lua";
  const std::string plot_file = argc > 2 ? argv[2] : "/tmp/cobra-door.svg";
  deploy::Configurator configurator;  // lockstep simulation clock
  components::addBuiltinPackages(configurator.packages());
  configurator.packages().addBuiltin("door_example", [](deploy::PackageBuilder& package) {
    package.component<examples::DoorSim>("DoorSim", "simulated arm, handle and door");
  });
  script::LuaState lua;
  deploy::LuaDeployer deployer(configurator, lua);
  try {
    deployer.runFile(file);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "cobra-door: %s\n", e.what());
    return 2;
  }
  core::ComponentRegistry& refs = configurator.getReferences();
  const auto& task = static_cast<components::Supervisor&>(refs.get("TaskSup"));

  // Watch the world as a scope would.
  const char* signals[] = {"armPosition", "handleAngle", "doorAngle"};
  std::vector<std::unique_ptr<core::InputPortBase>> probes;
  for (const char* s : signals) {
    auto& out = static_cast<core::OutputPortBase&>(refs.get("Door").port(s));
    probes.push_back(out.makeReader(s, "probe"));
    out.connectTo(*probes.back(), core::ConnPolicy::data());
  }
  plot::Figure figure{"The door task on the lockstep clock (thesis Fig. 2.5)",
                      {{"arm and door", "t [s]", "position [m], angle [rad]", {}}}};
  for (const char* s : signals) figure.panels[0].series.push_back({s, {}, {}});

  std::printf("cobra door example: %s\n", file.c_str());
  std::string last_state, last_deployment, last_configuration;
  const auto limit = 30s;
  while (configurator.clock().now() < limit && task.activeState() != "root.done" && task.activeState() != "root.failed") {
    configurator.clock().advance(10ms);
    const double t = std::chrono::duration<double>(configurator.clock().now()).count();
    if (std::string(task.activeState()) != last_state) {
      last_state = task.activeState();
      std::printf("  t = %6.2f s  task state %s\n", t, last_state.c_str());
    }
    if (configurator.currentDeployment() != last_deployment) {
      last_deployment = configurator.currentDeployment();
      std::printf("  t = %6.2f s    deployment %s\n", t, last_deployment.c_str());
    }
    if (configurator.currentConfiguration() != last_configuration) {
      last_configuration = configurator.currentConfiguration();
      std::printf("  t = %6.2f s    configuration %s\n", t, last_configuration.c_str());
    }
    for (std::size_t i = 0; i < probes.size(); ++i) {
      std::string text;
      if (probes[i]->readText(text) == core::FlowStatus::NoData) continue;
      figure.panels[0].series[i].x.push_back(t);
      figure.panels[0].series[i].y.push_back(std::stod(text));
    }
  }
  plot::writeSvg(figure, plot_file);
  std::printf("drew the run in %s\n", plot_file.c_str());
  const bool done = task.activeState() == "root.done";
  if (done)
    std::printf("door task done at t = %.2f s\n", std::chrono::duration<double>(configurator.clock().now()).count());
  else
    std::printf("door task NOT done (state %s)\n", std::string(task.activeState()).c_str());
  return done ? 0 : 1;
}
