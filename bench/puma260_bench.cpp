// The Puma 260 task (apps/puma260, thesis §6.3-6.4) as `cobra run apps/puma260 --scenario ...`
// runs it, timed by the wall clock: realtime_factor = simulated s per wall s. Side by side in one
// run: the MuJoCo world with the surface (closed-form and KDL kinematics) and the analytic world
// without contact (the same controller and chart; the run ends at H without phases E-G). Three
// repetitions each: the median and the worst (the smallest factor, statistic "min"); see
// app_speed.hpp.

#include <string>

#include "app_speed.hpp"

int main(int argc, char** argv) {
  for (const char* scenario : {"closed_form", "kdl", "no_contact"}) {
    // 120 s simulated at most; the task takes about 50 s.
    cobra::bench::registerAppSpeed(std::string("Puma260TaskSpeed/") + scenario,
                                   {"apps/puma260", std::string("apps/puma260/scenarios/") + scenario, 120.0});
  }
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
