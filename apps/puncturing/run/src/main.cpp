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
    std::printf("report: %s\n", result.report.c_str());
    return result.completed ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "cobra-puncturing: %s\n", e.what());
    return 2;
  }
}
