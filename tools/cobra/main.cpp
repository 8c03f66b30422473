// The `cobra` command-line tool: run, check and draw Lua deployment files; write components.
//   cobra deploy FILE [--sim] [--run-for T] [--strict] [--host NAME]
//   cobra run APP [--scenario DIR] [--time-limit S] [--report DIR] [--faults FILE] [--realtime [--thread-per-component]] [--quiet] [--host NAME]
//                 [--studio [--studio-port N] [--studio-bind ADDR] [--studio-linger S]] [--pace X] [--interactive]
//   cobra studio RUN_DIR [--port N] [--bind ADDR]
//   cobra edit [FILE|APP] [--port N] [--bind ADDR]
//   cobra lint FILE
//   cobra graph FILE -o out.svg
//   cobra describe FILE [-o out.lua]
//   cobra console [FILE] [--sim] [--strict]
//   cobra fsm run FILE [--events "e1 e2 -"] | cobra fsm check FILE | cobra fsm graph FILE -o fsm.svg
//   cobra faults matrix [--tasks T,...] [--cells ID,...] [--jobs N] [--doc FILE] [--check-doc FILE]
//   cobra soak --duration S [--seed N] --report FILE [--tasks T,...]
//   cobra new component NAME --role R --package P [-o DIR] [--in n:T[:unit]] [--out ...] [--prop ...]

#include <CLI/CLI.hpp>

#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <thread>

#include "cobra/components/builtin_packages.hpp"
#include "cobra/core/core.hpp"
#include "cobra/deploy/deploy.hpp"
#include "cobra/deploy/graph.hpp"
#include "cobra/deploy/lua_deployer.hpp"
#include "cobra/script/rfsm.hpp"
#include "cobra/studio/component_generator.hpp"
#include "console.hpp"
#include "console_terminal.hpp"
#include "describe.hpp"
#include "edit_command.hpp"
#include "faults_command.hpp"
#include "fsm_command.hpp"
#include "run_command.hpp"
#include "cobra/types/register_type.hpp"

#include <cstdlib>
#include <iostream>
#include <filesystem>
#include <fstream>

using namespace cobra;

namespace {

std::atomic<bool> g_interrupted{false};

void onSignal(int) {
  g_interrupted.store(true);
  tools::Console::interrupt();
}

void printStates(const core::ComponentRegistry& registry) {
  for (const core::Component* c : registry.components())
    std::printf("  %-20s %-12s %-12s %s\n", c->name().c_str(), std::string(core::toString(c->role())).c_str(),
                std::string(core::toString(c->state())).c_str(), c->activity().describe().c_str());
}

/// Every connection of the deployment checked against the role rules (ARCHITECTURE §2).
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

deploy::ConfiguratorOptions optionsFor(bool sim, bool strict, const std::string& host = {}) {
  deploy::ConfiguratorOptions options;
  options.mode = sim ? deploy::ClockMode::Simulation : deploy::ClockMode::RealTime;
  options.strict_roles = strict;
  options.host = host;
  return options;
}

int runDeploy(const std::string& file, bool sim, double run_for, bool strict, const std::string& host) {
  deploy::Configurator configurator(optionsFor(sim, strict, host));
  components::addBuiltinPackages(configurator.packages());
  script::LuaState lua;
  deploy::LuaDeployer deployer(configurator, lua);
  deployer.runFile(file);
  for (const std::string& warning : configurator.warnings()) std::printf("warning: %s\n", warning.c_str());
  std::printf("deployed %s (%s):\n", file.c_str(), sim ? "lockstep simulation clock" : "real time");
  if (configurator.placement() != nullptr)
    std::printf("host '%s' of the placement: %zu component(s) here; %zu of other hosts, which run them\n", host.c_str(),
                configurator.getReferences().components().size(),
                configurator.remoteComponents().components().size());
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
  components::addBuiltinPackages(configurator.packages());
  script::LuaState lua;
  deploy::LuaDeployer deployer(configurator, lua);
  deployer.runFile(file);
  const auto violations = lintAll(configurator.getReferences());
  for (const auto& v : violations) std::printf("%s\n", v.message.c_str());
  std::printf("%s: %zu component(s), %zu role violation(s)\n", file.c_str(),
              configurator.getReferences().components().size(), violations.size());
  return violations.empty() ? 0 : 1;
}

/// Writes Graphviz `dot` as `output`: DOT, or SVG/PNG/PDF through Graphviz's `dot` according to
/// the output's extension.
void renderDot(const std::string& dot, const std::string& output) {
  const std::filesystem::path out(output);
  if (out.extension() == ".dot") {
    std::ofstream(out) << dot;
    return;
  }
  const std::string format = out.extension().string().substr(out.extension().empty() ? 0 : 1);
  if (format != "svg" && format != "png" && format != "pdf")
    throw std::runtime_error("output " + output + ": use .svg, .png, .pdf or .dot");
  const auto dot_file = std::filesystem::path(output + ".dot");
  std::ofstream(dot_file) << dot;
  const std::string command = "dot -T" + format + " '" + dot_file.string() + "' -o '" + output + "'";
  const int status = std::system(command.c_str());
  std::filesystem::remove(dot_file);
  if (status != 0) throw std::runtime_error("Graphviz failed (" + command + "); is graphviz installed?");
}

/// Deploys `file` on the simulation clock (nothing runs) and draws it.
int runGraph(const std::string& file, const std::string& output) {
  deploy::Configurator configurator;
  components::addBuiltinPackages(configurator.packages());
  script::LuaState lua;
  deploy::LuaDeployer deployer(configurator, lua);
  deployer.runFile(file);
  renderDot(deploy::graphvizDot(configurator.getReferences(), std::filesystem::path(file).filename().string()), output);
  std::printf("drew %zu component(s) of %s in %s\n", configurator.getReferences().components().size(), file.c_str(),
              output.c_str());
  return 0;
}

int runFsmGraph(const std::string& file, const std::string& output) {
  script::LuaState lua;
  const auto chart = script::RfsmChart::loadFile(lua, file);
  renderDot(tools::chartDot(chart->chart(), std::filesystem::path(file).filename().string()), output);
  std::printf("drew %zu state(s) of %s in %s\n", chart->chart().nodes().size(), file.c_str(), output.c_str());
  return 0;
}

int runDescribe(const std::string& file, const std::string& output) {
  deploy::Configurator configurator;
  components::addBuiltinPackages(configurator.packages());
  script::LuaState lua;
  deploy::LuaDeployer deployer(configurator, lua);
  deployer.runFile(file);
  const std::string text = tools::describeDeployment(configurator);
  if (output.empty()) {
    std::fputs(text.c_str(), stdout);
  } else {
    std::ofstream(output) << text;
    std::printf("described %zu component(s) of %s in %s\n", configurator.getReferences().components().size(),
                file.c_str(), output.c_str());
  }
  return 0;
}

int runConsole(const std::string& file, bool sim, bool strict) {
  deploy::Configurator configurator(optionsFor(sim, strict));
  components::addBuiltinPackages(configurator.packages());
  script::LuaState lua;
  deploy::LuaDeployer deployer(configurator, lua);
  tools::Console console(configurator, deployer, std::cout);
  // In the console Ctrl-C stops a trace and the session goes on: it must not cut the Lua code
  // that runs after it (the flag stays set).
  script::LuaState::watchInterrupt(nullptr);
  if (!file.empty()) console.execute("load " + file);
  return tools::runConsoleTerminal(console);
}

}  // namespace

int main(int argc, char** argv) {
  // cobra's own data types with their core, Lua and CSV capabilities (those above core,
  // TGL.MultiAxisPath, only here); their DDS wires come with the package cobra_dds when loaded.
  cobra::types::registerBuiltins();
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
  std::string deploy_host;
  deploy_cmd->add_option("--host", deploy_host, "this process's host in the file's placement: run only its components "
                                                 "(deploy/README.md, Placement)");
  deploy_cmd->footer("example: cobra deploy apps/examples/configurator_listing.lua --sim --run-for 1");

  run::RunOptions run_options;
  std::string run_app, run_scenario, run_report, run_faults;
  bool run_quiet = false;
  CLI::App* run_cmd = app.add_subcommand("run", "run an application until its task charts are done, with its report");
  run_cmd->add_option("APP", run_app, "application folder (holding <folder name>.lua) or entry file")->required();
  run_cmd->add_option("--scenario", run_scenario, "scenario folder, given to the entry file as `scenario` "
                                                  "(its faults.lua is played when present)");
  run_cmd->add_option("--time-limit", run_options.time_limit, "seconds after which the run stops unfinished (default 900)")
      ->check(CLI::PositiveNumber);
  run_cmd->add_option("--report", run_report, "folder for events.csv, signals.csv and report.html");
  run_cmd->add_option("--faults", run_faults, "faults file (faults.lua: on an event, a state or a time, call, write or set)");
  run_cmd->add_flag("--realtime", run_options.realtime,
                    "the wall clock instead of the lockstep clock: the deployment's schedule run every period by a "
                    "real-time executor (SCHED_FIFO, memory locked; setExecutor in the files)");
  run_cmd->add_flag("--thread-per-component", run_options.thread_per_component,
                    "with --realtime: every component on a thread of its own instead of the executor");
  run_cmd->add_flag("--quiet", run_quiet, "print no state, switch or progress line");
  run_cmd->add_option("--host", run_options.host, "this process's host in the application's placement: run only its "
                                                  "components, the others' in their own processes (run/README.md)");
  tools::StudioCommandOptions studio_options;
  studio_options.executable = argv[0];
  double pace = -1.0;
  run_cmd->add_flag("--studio", studio_options.live, "serve the run to cobra studio in the browser while it runs "
                                                    "(prints the URL; the lockstep clock is paced to real time)");
  run_cmd->add_option("--studio-port", studio_options.port, "studio's port (default 0: any free port)");
  run_cmd->add_option("--studio-bind", studio_options.bind, "address studio listens on (default 127.0.0.1; "
                                                            "beyond loopback: HTTPS only, with --studio-tls-cert/-key)");
  run_cmd->add_option("--studio-tls-cert", studio_options.tls_cert, "PEM certificate: studio serves HTTPS and WSS only");
  run_cmd->add_option("--studio-tls-key", studio_options.tls_key, "PEM private key of --studio-tls-cert");
  run_cmd->add_option("--studio-linger", studio_options.linger, "s studio stays after the run (default: until Ctrl-C)");
  run_cmd->add_option("--pace", pace, "simulated s per wall s on the lockstep clock (0 = as fast as possible; "
                                      "default 1 with --studio, else 0)")
      ->check(CLI::NonNegativeNumber);
  run_cmd->add_flag("--interactive", run_options.interactive,
                    "the entry file gets `interactive = true`: studio's buttons give the surgeon's inputs");
  run_cmd->footer("example: cobra run apps/puncturing --report build/demo-report\n"
                  "         cobra run apps/puncturing --studio --interactive\n"
                  "exit status 0 when the task charts reach their done states; 3 when a peer host was lost; else 1 and one "
                  "line saying why");

  const tools::FaultsCommands faults_commands(app);  // cobra faults matrix, cobra soak

  std::string studio_folder;
  tools::StudioCommandOptions replay_options;
  replay_options.executable = argv[0];
  CLI::App* studio_cmd = app.add_subcommand("studio", "replay a recorded run in the browser (cobra studio)");
  studio_cmd->add_option("RUN_DIR", studio_folder, "run folder written by cobra run APP --report RUN_DIR")->required();
  studio_cmd->add_option("--port", replay_options.port, "port (default 0: any free port)");
  studio_cmd->add_option("--bind", replay_options.bind, "address to listen on (default 127.0.0.1; beyond loopback: HTTPS only, "
                                                 "with --tls-cert and --tls-key)");
  studio_cmd->add_option("--tls-cert", replay_options.tls_cert, "PEM certificate: serve HTTPS and WSS only");
  studio_cmd->add_option("--tls-key", replay_options.tls_key, "PEM private key of --tls-cert");
  studio_cmd->footer("example: cobra run apps/puncturing --report build/demo-report && cobra studio build/demo-report\n"
                     "prints the URL to open; serves until Ctrl-C");

  std::string edit_path;
  tools::StudioCommandOptions edit_options;
  edit_options.executable = argv[0];
  CLI::App* edit_cmd = app.add_subcommand("edit", "edit deployments in the browser: cobra studio's deployment editor");
  edit_cmd->add_option("FILE", edit_path, "Lua deployment file or application folder to open (default: a new project)");
  edit_cmd->add_option("--port", edit_options.port, "port (default 0: any free port)");
  edit_cmd->add_option("--bind", edit_options.bind, "address to listen on (default 127.0.0.1; beyond loopback: HTTPS only, "
                                                 "with --tls-cert and --tls-key)");
  edit_cmd->add_option("--tls-cert", edit_options.tls_cert, "PEM certificate: serve HTTPS and WSS only");
  edit_cmd->add_option("--tls-key", edit_options.tls_key, "PEM private key of --tls-cert");
  edit_cmd->footer("example: cobra edit apps/puncturing\n"
                   "prints \"editor: http://127.0.0.1:PORT/editor.html?token=TOKEN\" to open; serves until Ctrl-C;\n"
                   "a file that does not load is still served (the page shows its error line and never saves over it)");

  std::string lint_file;
  CLI::App* lint_cmd = app.add_subcommand("lint", "check every connection of a deployment against the role rules");
  lint_cmd->add_option("FILE", lint_file, "Lua deployment file")->required()->check(CLI::ExistingFile);
  lint_cmd->footer("example: cobra lint apps/examples/configurator_listing.lua   (exit status 1 on violations)");

  std::string graph_file, graph_output;
  CLI::App* graph_cmd = app.add_subcommand("graph", "draw a deployment: components coloured by role, ports, connections");
  graph_cmd->add_option("FILE", graph_file, "Lua deployment file")->required()->check(CLI::ExistingFile);
  graph_cmd->add_option("-o,--output", graph_output, "output file: .svg, .png, .pdf (with Graphviz) or .dot")->required();
  graph_cmd->footer("example: cobra graph apps/examples/configurator_listing.lua -o deployment.svg");

  std::string describe_file, describe_output;
  CLI::App* describe_cmd = app.add_subcommand("describe", "write a deployment back as reusable Configurator tables (Lua)");
  describe_cmd->add_option("FILE", describe_file, "Lua deployment file")->required()->check(CLI::ExistingFile);
  describe_cmd->add_option("-o,--output", describe_output, "Lua file to write (default: standard output)");
  describe_cmd->footer("example: cobra describe apps/examples/configurator_listing.lua -o described.lua");

  std::string console_file;
  bool console_sim = false, console_strict = false;
  CLI::App* console_cmd = app.add_subcommand("console", "browse and drive a deployment interactively (like OROCOS' TaskBrowser)");
  console_cmd->add_option("FILE", console_file, "Lua deployment file to load first")->check(CLI::ExistingFile);
  console_cmd->add_flag("--sim", console_sim, "lockstep simulation clock: time advances only with step and trace");
  console_cmd->add_flag("--strict", console_strict, "refuse connections that break the role rules");
  console_cmd->footer("example: cobra console apps/examples/configurator_listing.lua --sim\n"
                      "         then: ls, cd TrajGen, set k 2, step 0.1, trace out 5, Reporter.count(), help");

  std::string fsm_file, fsm_events, fsm_output;
  double fsm_until = 0.0, fsm_step = 0.01;
  CLI::App* fsm_cmd = app.add_subcommand("fsm", "rFSM charts: run, check or draw one");
  fsm_cmd->require_subcommand(1);
  CLI::App* fsm_run = fsm_cmd->add_subcommand("run", "run a chart until idle, then once per event, printing the active state");
  fsm_run->add_option("FILE", fsm_file, "rFSM chart (return rfsm.state{ ... })")->required()->check(CLI::ExistingFile);
  fsm_run->add_option("--events", fsm_events,
                      "events, whitespace-separated; - sends none; with --until, NAME@SECONDS sends at that time");
  const CLI::Validator positive_seconds(
      [](std::string& text) -> std::string {
        char* end = nullptr;
        const double value = std::strtod(text.c_str(), &end);
        return end != text.c_str() && *end == '\0' && value > 0.0 ? "" : "expected a time > 0 s, got '" + text + "'";
      },
      "SECONDS > 0");
  CLI::Option* until_option =
      fsm_run->add_option("--until", fsm_until, "s: run a task chart on a simulated clock until then (e_after fires), "
                                                "with stand-in peers and emit, printing states, events and calls")
          ->check(positive_seconds);
  fsm_run->add_option("--step", fsm_step, "s: the simulated clock's step with --until (default 0.01)")
      ->check(positive_seconds)
      ->needs(until_option);
  fsm_run->footer("example: cobra fsm run script/test/charts/fig32.lua --events \"e_start e_error - e_error_fixed\"\n"
                  "prints one line with the active state's full path, then one per token\n"
                  "example: cobra fsm run apps/puncturing/charts/needle_insertion.lua --until 30 "
                  "--events \"e_deployed_needle_autonomous_planning@0.1 e_iceball_configured@1\"");
  CLI::App* fsm_check = fsm_cmd->add_subcommand("check", "validate a chart and list its states and transitions");
  fsm_check->add_option("FILE", fsm_file, "rFSM chart")->required()->check(CLI::ExistingFile);
  fsm_check->footer("example: cobra fsm check apps/door/door_task.lua   (exit status 2 on errors)");
  CLI::App* fsm_graph = fsm_cmd->add_subcommand("graph", "draw a chart (Graphviz; composite states as nested boxes)");
  fsm_graph->add_option("FILE", fsm_file, "rFSM chart")->required()->check(CLI::ExistingFile);
  fsm_graph->add_option("-o,--output", fsm_output, "output file: .svg, .png, .pdf or .dot")->required();
  fsm_graph->footer("example: cobra fsm graph apps/door/door_task.lua -o door_task.svg");

  studio::ComponentTemplate skeleton;
  std::string new_folder;
  std::vector<std::string> ins, event_ins, outs, props;
  CLI::App* new_cmd = app.add_subcommand("new", "write a component into a package folder built against an installed cobra");
  CLI::App* new_component_cmd = new_cmd->add_subcommand("component", "a component");
  new_cmd->require_subcommand(1);
  new_component_cmd->add_option("NAME", skeleton.name, "class name, CamelCase")->required();
  new_component_cmd->add_option("--role", skeleton.role, "calculation, supervision, decision or bridge")->required();
  new_component_cmd->add_option("--package", skeleton.package, "package (namespace and include folder)")->required();
  new_component_cmd->add_option("-o,--output", new_folder, "package folder (default: ./PACKAGE)");
  new_component_cmd->add_option("--in", ins, "input port name:Type[:unit]");
  new_component_cmd->add_option("--event-in", event_ins, "input port whose data triggers an update, name:Type[:unit]");
  new_component_cmd->add_option("--out", outs, "output port name:Type[:unit]");
  new_component_cmd->add_option("--prop", props, "property name:Type[:unit]");
  new_component_cmd->footer(
      "types: " + studio::generatorTypeNames() + "\n" +
      "example: cobra new component VariableAdmittance --role calculation --package my_control \\\n"
      "           --in des_pose:Frame --in meas_wrench:Wrench --out adm_pose:Frame --prop stiffness:double:N/m\n"
      "writes include/P/name.hpp, src/name.cpp, test/name_test.cpp (name: NAME in snake_case); creates or\n"
      "extends src/package.cpp and CMakeLists.txt (find_package(cobra) + cobra_add_package);\n"
      "build: cmake -S DIR -B build -DCMAKE_PREFIX_PATH=<cobra prefix>");

  CLI11_PARSE(app, argc, argv);
  std::signal(SIGINT, onSignal);
  std::signal(SIGTERM, onSignal);
  // Lua stuck in a loop notices the signal too (script::LuaState, "Budget and interrupts").
  script::LuaState::watchInterrupt(&g_interrupted);
  try {
    if (*deploy_cmd)
      return runDeploy(deploy_file, sim, deploy_cmd->count("--run-for") ? run_for : (sim ? 1.0 : 0.0), strict, deploy_host);
    if (*run_cmd) {
      run_options.app = run_app;
      run_options.scenario = run_scenario;
      run_options.report_folder = run_report;
      run_options.faults_file = run_faults;
      run_options.pace = pace >= 0.0 ? pace : (studio_options.live && !run_options.realtime ? 1.0 : 0.0);
      return tools::runApplication(run_options, run_quiet, studio_options, g_interrupted);
    }
    if (faults_commands.chosen()) return faults_commands.run();
    if (*studio_cmd) return tools::serveRecording(studio_folder, replay_options, g_interrupted);
    if (*edit_cmd) return tools::editDeployment(edit_path, edit_options, g_interrupted);
    if (*lint_cmd) return runLint(lint_file);
    if (*graph_cmd) return runGraph(graph_file, graph_output);
    if (*describe_cmd) return runDescribe(describe_file, describe_output);
    if (*console_cmd) return runConsole(console_file, console_sim, console_strict);
    if (*fsm_run)
      return fsm_until > 0.0 ? tools::runFsmUntil(fsm_file, fsm_until, fsm_step, fsm_events)
                             : tools::runFsm(fsm_file, fsm_events);
    if (*fsm_check) return tools::checkFsm(fsm_file);
    if (*fsm_graph) return runFsmGraph(fsm_file, fsm_output);
    if (*new_component_cmd) {
      for (const auto& text : ins) skeleton.inputs.push_back(studio::parseInterfaceItem(text, "--in"));
      for (const auto& text : event_ins) skeleton.event_inputs.push_back(studio::parseInterfaceItem(text, "--event-in"));
      for (const auto& text : outs) skeleton.outputs.push_back(studio::parseInterfaceItem(text, "--out"));
      for (const auto& text : props) skeleton.properties.push_back(studio::parseInterfaceItem(text, "--prop"));
      const auto folder = new_folder.empty() ? std::filesystem::path(skeleton.package) : std::filesystem::path(new_folder);
      for (const auto& path : studio::generateComponent(skeleton, folder)) std::printf("wrote %s\n", path.c_str());
      return 0;
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "cobra: %s\n", e.what());
    return 2;
  }
  return 0;
}
