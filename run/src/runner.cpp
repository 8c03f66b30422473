#include "cobra/run/runner.hpp"

#include <cstdio>
#include <stdexcept>

#include "session.hpp"

namespace cobra::run {

const char* toString(Outcome outcome) {
  switch (outcome) {
    case Outcome::Completed: return "completed";
    case Outcome::TimeLimit: return "time limit";
    case Outcome::ComponentError: return "component error";
    case Outcome::UnhandledFault: return "fault unhandled";
    case Outcome::SafeStop: return "safe stop";
    case Outcome::Interrupted: return "interrupted";
    case Outcome::PeerLost: return "peer lost";
  }
  return "?";
}

const SummaryValue& RunResult::value(const std::string& name) const {
  for (const SummaryValue& v : summary)
    if (v.name == name) return v;
  throw std::out_of_range("no summary value '" + name + "'");
}

int exitStatus(const RunResult& result) {
  if (result.completed()) return 0;
  return result.outcome == Outcome::PeerLost ? 3 : 1;
}

std::string endLine(const RunResult& result) {
  if (result.completed()) {
    char line[64];
    std::snprintf(line, sizeof line, "completed in %.3f s", result.duration);
    return line;
  }
  return std::string("cobra run: ") + toString(result.outcome) + ": " + result.reason;
}

std::string executorLine(const ExecutorFigures& e) {
  if (!e.ran) return "";
  char line[400];
  std::snprintf(line, sizeof line,
                "executor: %llu ticks of %.3f ms, %s; %llu deadline misses (longest run %llu); wake-up latency median "
                "%.1f us, p99 %.1f us, p99.9 %.1f us, worst %.1f us; compute per tick median %.1f us, worst %.1f us",
                static_cast<unsigned long long>(e.ticks), e.period * 1e3, e.scheduler.c_str(),
                static_cast<unsigned long long>(e.deadline_misses), static_cast<unsigned long long>(e.worst_consecutive_misses),
                e.wake_latency.median * 1e6, e.wake_latency.p99 * 1e6, e.wake_latency.p999 * 1e6, e.wake_latency.worst * 1e6,
                e.tick_compute.median * 1e6, e.tick_compute.worst * 1e6);
  std::string text = line;
  for (const core::HandoverFigures& h : e.handovers) {
    char own[160];
    std::snprintf(own, sizeof own, "; %s (own pace) hand-over at most %.1f ms old (max_age %.0f ms, %llu stale)",
                  h.component.c_str(), h.worst_age * 1e3, h.max_age * 1e3, static_cast<unsigned long long>(h.stale));
    text += own;
  }
  return text;
}

std::filesystem::path entryFile(const std::filesystem::path& app) {
  if (std::filesystem::is_regular_file(app)) return app;
  if (!std::filesystem::is_directory(app)) throw std::runtime_error(app.string() + ": no such file or folder");
  std::filesystem::path folder = app;
  if (folder.filename().empty()) folder = folder.parent_path();  // "apps/x/"
  const std::filesystem::path entry = folder / (folder.filename().string() + ".lua");
  if (!std::filesystem::is_regular_file(entry))
    throw std::runtime_error(folder.string() + ": no entry file " + entry.string() +
                             " (an application folder holds <name>.lua)");
  return entry;
}

RunResult runApp(const RunOptions& options) { return Session(options, entryFile(options.app)).run(); }

}  // namespace cobra::run
