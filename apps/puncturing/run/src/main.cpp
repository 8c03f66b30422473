// cobra-puncturing: the puncturing task of the thesis (ch. 4) in simulation, on the lockstep clock.
//
//   cobra-puncturing [--scenario DIR] [--report DIR] [--time-limit S]
//
// Prints a line per task state and per deployment/configuration switch, then where the report is.
// Exit status 0 when the procedure completed.

#include <cstdio>
#include <cstring>
#include <string>

#include "cobra/puncturing/procedure.hpp"

int main(int argc, char** argv) {
  cobra::puncturing::ProcedureOptions options;
  options.deployment_file = std::string(COBRA_PUNCTURING_DIR) + "/puncturing.lua";
  options.scenario = std::string(COBRA_PUNCTURING_DIR) + "/scenarios/two_needles";
  options.report_folder = "/tmp/cobra-puncturing";
  for (int i = 1; i < argc; ++i) {
    const bool has_value = i + 1 < argc;
    if (std::strcmp(argv[i], "--scenario") == 0 && has_value) {
      options.scenario = argv[++i];
    } else if (std::strcmp(argv[i], "--report") == 0 && has_value) {
      options.report_folder = argv[++i];
    } else if (std::strcmp(argv[i], "--time-limit") == 0 && has_value) {
      options.time_limit = std::atof(argv[++i]);
    } else {
      std::fprintf(stderr, "usage: cobra-puncturing [--scenario DIR] [--report DIR] [--time-limit S]\n");
      return 2;
    }
  }
  options.progress = [](const std::string& line) { std::printf("  %s\n", line.c_str()); std::fflush(stdout); };
  std::printf("cobra puncturing: scenario %s, on the lockstep clock (simulated time)\n", options.scenario.c_str());
  try {
    const cobra::puncturing::ProcedureResult result = cobra::puncturing::runProcedure(options);
    for (const auto& p : result.placements)
      std::printf("needle %d: placement error %.2f mm\n", p.needle + 1, p.error_mm);
    for (const auto* robot : {&result.fidelity.needle, &result.fidelity.probe})
      std::printf("%s: worst tracking %.2f mm at %.3f s, %.2f deg at %.3f s (autonomous), %.3f s above 5 mm, %d joint "
                  "jump episodes\n",
                  robot->robot.c_str(), robot->position_mm.value, robot->position_mm.at, robot->orientation_deg.value,
                  robot->orientation_deg.at, robot->seconds_above_5mm, robot->joint_jumps);
    const cobra::puncturing::ClearanceFigures& c = result.fidelity.clearance;
    std::printf("worst clearance %.2f mm (threshold %.2f mm) at %.3f s (%s); %zu IK discontinuity events\n",
                1000.0 * c.worst, 1000.0 * c.threshold, c.worst_at, c.worst_pair.c_str(),
                result.fidelity.ik_discontinuities.size());
    if (result.safe_stop) std::printf("safe stop: %s\n", result.stop_reason.c_str());
    std::printf("report: %s\n", result.report.c_str());
    return result.completed ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "cobra-puncturing: %s\n", e.what());
    return 2;
  }
}
