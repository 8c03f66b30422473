#include "run_command.hpp"

#include <chrono>
#include <cstdio>
#include <memory>
#include <thread>

#include "cobra/studio/bridge.hpp"
#include "cobra/studio/editor.hpp"
#include "cobra/studio/replay.hpp"
#include "cobra/studio/server.hpp"

namespace cobra::tools {
namespace {

void printResult(const run::RunResult& result) {
  for (const run::SummaryValue& value : result.summary) std::printf("%s: %s\n", value.name.c_str(), value.text.c_str());
  for (const run::TrackingFigures& t : result.tracking)
    std::printf("%s: worst tracking %.2f mm at %.3f s, %.2f deg at %.3f s (counted samples), %.3f s above 5 mm, "
                "%d joint jump episodes, largest command step %.3f mm\n",
                t.robot.c_str(), t.position_mm.value, t.position_mm.at, t.orientation_deg.value, t.orientation_deg.at,
                t.seconds_above_5mm, t.joint_jumps, 1000.0 * t.max_command_step);
  if (result.clearance.seconds_sampled > 0.0)
    std::printf("worst clearance %.2f mm (threshold %.2f mm) at %.3f s; %.3f s at or under it; %d unmeasurable\n",
                1000.0 * result.clearance.worst, 1000.0 * result.clearance.threshold, result.clearance.worst_at,
                result.clearance.seconds_below, result.clearance.unreachable);
  if (!result.clearance.pairs.empty()) {
    std::printf("clearance per pair:");
    for (std::size_t k = 0; k < result.clearance.pairs.size(); ++k)
      std::printf("%s %s %.2f mm", k == 0 ? "" : ",", result.clearance.pairs[k].name.c_str(),
                  1000.0 * result.clearance.pairs[k].worst);
    std::printf("\n");
  }
  if (result.executor.ran) std::printf("%s\n", run::executorLine(result.executor).c_str());
  if (!result.report.empty()) std::printf("report: %s\n", result.report.c_str());
}

// `fallback_web`: the page to serve when no built front end is found (a run folder's copy).
std::unique_ptr<studio::Server> startServer(studio::StudioSource& source, const StudioCommandOptions& options,
                                            const std::filesystem::path& fallback_web = {},
                                            studio::Editor* editor = nullptr) {
  studio::ServerOptions server;
  server.editor = editor;
  server.bind = options.bind;
  server.port = options.port;
  server.tls_cert = options.tls_cert;
  server.tls_key = options.tls_key;
  server.web_folder = studio::findWebFolder(options.executable);
  if (server.web_folder.empty() && std::filesystem::is_regular_file(fallback_web / "index.html")) server.web_folder = fallback_web;
  auto started = std::make_unique<studio::Server>(source, server);
  if (!studio::isLoopback(options.bind))
    std::printf("studio: warning: listening on %s (TLS): whoever reaches it with the token can see and drive the run\n",
                options.bind.c_str());
  if (server.web_folder.empty())
    std::printf("studio: warning: no web front end found (studio/web/dist, or set COBRA_STUDIO_WEB); /api and /ws work\n");
  std::printf("studio: %s\n", started->url().c_str());
  if (editor != nullptr) std::printf("editor: %s\n", studio::editorUrl(*started).c_str());
  std::fflush(stdout);
  return started;
}

// Keeps the server up until Ctrl-C or `linger` s.
void serveOn(const StudioCommandOptions& options, const std::atomic<bool>& interrupted) {
  std::printf("studio: serving %s\n", options.linger < 0 ? "until Ctrl-C" : "a little longer");
  std::fflush(stdout);
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(options.linger < 0 ? 1e9 : options.linger);
  while (!interrupted.load() && std::chrono::steady_clock::now() < end) std::this_thread::sleep_for(std::chrono::milliseconds(20));
}

}  // namespace

int runApplication(run::RunOptions options, bool quiet, const StudioCommandOptions& studio,
                   const std::atomic<bool>& interrupted) {
  if (!quiet) options.progress = [](const std::string& line) {
    std::printf("  %s\n", line.c_str());
    std::fflush(stdout);
  };
  run::entryFile(options.app);  // a missing entry file is the only line printed
  options.interrupt = &interrupted;
  studio::BridgeOptions bridge_options;
  bridge_options.interactive = options.interactive;  // the console offers the charts' choices only then
  bridge_options.web_folder = studio::findWebFolder(studio.executable);
  studio::VisualizerBridge bridge(bridge_options);
  // The editor (GET /api/editor/running: this run described) comes with the live studio; its
  // palette is built on a thread of its own, never the run's.
  studio::RunningDeployment running(&bridge);
  std::unique_ptr<studio::Editor> editor;
  std::unique_ptr<studio::Server> server;
  if (studio.live) {
    editor = std::make_unique<studio::Editor>();
    editor->setRunning(&running);
    server = startServer(bridge, studio, {}, editor.get());
  }
  if (studio.live) options.observer = &running;
  else if (!options.report_folder.empty()) options.observer = &bridge;
  if (!quiet)
    std::printf("cobra run %s%s%s on the %s\n", options.app.c_str(),
                options.scenario.empty() ? "" : (", scenario " + options.scenario.string()).c_str(),
                options.host.empty() ? "" : (", host " + options.host).c_str(),
                options.realtime ? "wall clock (real time)" : "lockstep clock (simulated time)");
  run::RunResult result;
  try {
    result = run::runApp(options);
  } catch (const std::exception& e) {
    if (!server) throw;
    bridge.fail(e.what());
    std::fprintf(stderr, "cobra: %s\n", e.what());
    serveOn(studio, interrupted);
    return 2;
  }
  printResult(result);
  const int status = run::exitStatus(result);
  if (result.completed()) {
    std::printf("%s\n", run::endLine(result).c_str());
  } else {
    std::fflush(stdout);
    std::fprintf(stderr, "%s\n", run::endLine(result).c_str());
  }
  if (server) serveOn(studio, interrupted);
  return status;
}

int serveRecording(const std::filesystem::path& folder, const StudioCommandOptions& studio,
                   const std::atomic<bool>& interrupted) {
  studio::Replay replay(folder);  // a folder that is not a run folder: one line, exit status 2
  const auto server = startServer(replay, studio, folder / "studio");
  serveOn(studio, interrupted);
  return 0;
}

}  // namespace cobra::tools
