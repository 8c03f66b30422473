#include "run_command.hpp"

#include <cstdio>

namespace cobra::tools {

int runApplication(run::RunOptions options, bool quiet) {
  if (!quiet) options.progress = [](const std::string& line) {
    std::printf("  %s\n", line.c_str());
    std::fflush(stdout);
  };
  run::entryFile(options.app);  // a missing entry file is the only line printed
  if (!quiet)
    std::printf("cobra run %s%s on the %s\n", options.app.c_str(),
                options.scenario.empty() ? "" : (", scenario " + options.scenario.string()).c_str(),
                options.realtime ? "wall clock (real time)" : "lockstep clock (simulated time)");
  const run::RunResult result = run::runApp(options);
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
  if (!result.report.empty()) std::printf("report: %s\n", result.report.c_str());
  if (result.completed()) {
    std::printf("completed in %.3f s\n", result.duration);
    return 0;
  }
  std::fflush(stdout);
  std::fprintf(stderr, "cobra run: %s: %s\n", run::toString(result.outcome), result.reason.c_str());
  return 1;
}

}  // namespace cobra::tools
