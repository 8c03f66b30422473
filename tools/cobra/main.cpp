// The `cobra` command-line tool: run and check Lua deployment files.
//   cobra deploy FILE [--sim] [--run-for T] [--strict]
//   cobra lint FILE

#include <CLI/CLI.hpp>

#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <thread>

#include "cobra/core/core.hpp"
#include "cobra/deploy/deploy.hpp"
#include "cobra/deploy/lua_deployer.hpp"

using namespace cobra;

namespace {

std::atomic<bool> g_interrupted{false};

void onSignal(int) { g_interrupted.store(true); }

void printStates(const core::ComponentRegistry& registry) {
  for (const core::Component* c : registry.components())
    std::printf("  %-20s %-12s %-12s %s\n", c->name().c_str(), std::string(core::toString(c->role())).c_str(),
                std::string(core::toString(c->state())).c_str(), c->activity().describe().c_str());
}

/// Every connection of the deployment checked against the role rules (DESIGN §2).
std::vector<deploy::LintViolation> lintAll(const core::ComponentRegistry& registry) {
  std::vector<deploy::LintViolation> all;
  for (const core::Component* c : registry.components())
    for (const core::PortBase* port : c->ports()) {
      if (port->direction() != core::PortDirection::Output) continue;
      for (const auto& channel : port->connections()) {
        auto found = deploy::lintConnection(*port, channel->reader());
        all.insert(all.end(), found.begin(), found.end());
      }
    }
  return all;
}

int runDeploy(const std::string& file, bool sim, double run_for, bool strict) {
  deploy::ConfiguratorOptions options;
  options.mode = sim ? deploy::ClockMode::Simulation : deploy::ClockMode::RealTime;
  options.strict_roles = strict;
  deploy::Configurator configurator(options);
  script::LuaState lua;
  deploy::LuaDeployer deployer(configurator, lua);
  deployer.runFile(file);
  for (const std::string& warning : configurator.warnings()) std::printf("warning: %s\n", warning.c_str());
  std::printf("deployed %s (%s):\n", file.c_str(), sim ? "lockstep simulation clock" : "real time");
  printStates(configurator.getReferences());

  const auto duration = std::chrono::duration<double>(run_for);
  if (sim) {
    // Simulated time runs as fast as the CPU allows, in 10 ms slices so Ctrl-C is noticed.
    const auto end = configurator.clock().now() + std::chrono::duration_cast<std::chrono::nanoseconds>(duration);
    while (!g_interrupted.load() && configurator.clock().now() < end)
      configurator.clock().advance(std::min<std::chrono::nanoseconds>(std::chrono::milliseconds(10),
                                                                      end - configurator.clock().now()));
    std::printf("ran %.3f s of simulated time\n", std::chrono::duration<double>(configurator.clock().now()).count());
  } else {
    const auto start = std::chrono::steady_clock::now();
    while (!g_interrupted.load() && (run_for <= 0 || std::chrono::steady_clock::now() - start < duration))
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    std::printf("ran %.3f s of real time\n",
                std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  printStates(configurator.getReferences());
  return 0;
}

int runLint(const std::string& file) {
  deploy::ConfiguratorOptions options;  // simulation: nothing runs, the clock never advances
  deploy::Configurator configurator(options);
  script::LuaState lua;
  deploy::LuaDeployer deployer(configurator, lua);
  deployer.runFile(file);
  const auto violations = lintAll(configurator.getReferences());
  for (const auto& v : violations) std::printf("%s\n", v.message.c_str());
  std::printf("%s: %zu component(s), %zu role violation(s)\n", file.c_str(),
              configurator.getReferences().components().size(), violations.size());
  return violations.empty() ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"cobra: run and check component deployments (Lua deployment files, thesis §3.2.2)"};
  app.require_subcommand(1);

  std::string deploy_file;
  bool sim = false;
  bool strict = false;
  double run_for = 0.0;
  CLI::App* deploy_cmd = app.add_subcommand("deploy", "run a deployment file");
  deploy_cmd->add_option("FILE", deploy_file, "Lua deployment file")->required()->check(CLI::ExistingFile);
  deploy_cmd->add_flag("--sim", sim, "run on the lockstep simulation clock (deterministic, faster than real time)");
  deploy_cmd->add_option("--run-for", run_for, "seconds to run (simulated with --sim); 0 = until Ctrl-C (real time)")
      ->check(CLI::NonNegativeNumber);
  deploy_cmd->add_flag("--strict", strict, "refuse connections that break the role rules instead of warning");
  deploy_cmd->footer("example: cobra deploy apps/examples/configurator_listing.lua --sim --run-for 1");

  std::string lint_file;
  CLI::App* lint_cmd = app.add_subcommand("lint", "check every connection of a deployment against the role rules");
  lint_cmd->add_option("FILE", lint_file, "Lua deployment file")->required()->check(CLI::ExistingFile);
  lint_cmd->footer("example: cobra lint apps/examples/configurator_listing.lua   (exit status 1 on violations)");

  CLI11_PARSE(app, argc, argv);
  std::signal(SIGINT, onSignal);
  std::signal(SIGTERM, onSignal);
  try {
    if (*deploy_cmd) return runDeploy(deploy_file, sim, deploy_cmd->count("--run-for") ? run_for : (sim ? 1.0 : 0.0), strict);
    if (*lint_cmd) return runLint(lint_file);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "cobra: %s\n", e.what());
    return 2;
  }
  return 0;
}
