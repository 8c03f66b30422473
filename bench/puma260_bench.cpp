// The Puma 260 task (apps/puma260, thesis §6.3-6.4) as `cobra run apps/puma260 --scenario ...`
// runs it, timed by the wall clock: realtime_factor = simulated s per wall s. Side by side in one
// run: the MuJoCo world with the surface (closed-form and KDL kinematics) and the analytic world
// without contact (the same controller and chart; the run ends at H without phases E-G). Three
// repetitions each: the median and the worst (the smallest factor, statistic "min").

#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <string>
#include <vector>

#include "cobra/run/runner.hpp"

namespace {

void BM_TaskSpeed(benchmark::State& state, const std::string& scenario) {
  double simulated = 0.0;
  double wall = 0.0;
  bool completed = true;
  for (auto _ : state) {
    cobra::run::RunOptions options;
    options.app = std::string(COBRA_SOURCE_DIR) + "/apps/puma260";
    options.scenario = std::string(COBRA_SOURCE_DIR) + "/apps/puma260/scenarios/" + scenario;
    options.time_limit = 120.0;  // s simulated; the task takes about 20 s
    const auto started = std::chrono::steady_clock::now();
    const cobra::run::RunResult result = cobra::run::runApp(options);
    wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    simulated = result.duration;
    completed = completed && result.completed();
    state.SetIterationTime(wall);
  }
  if (!completed) state.SkipWithError("the task did not complete");
  state.counters["simulated_s"] = simulated;
  state.counters["realtime_factor"] = wall > 0.0 ? simulated / wall : 0.0;
}
double minOf(const std::vector<double>& v) { return *std::min_element(v.begin(), v.end()); }

void taskSpeed(const char* scenario) {
  benchmark::RegisterBenchmark((std::string("Puma260TaskSpeed/") + scenario).c_str(), BM_TaskSpeed, std::string(scenario))
      ->Iterations(1)
      ->Repetitions(3)
      ->UseManualTime()
      ->ReportAggregatesOnly(true)
      ->ComputeStatistics("min", minOf)
      ->Unit(benchmark::kSecond);
}

}  // namespace

int main(int argc, char** argv) {
  for (const char* scenario : {"closed_form", "kdl", "no_contact"}) taskSpeed(scenario);
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
