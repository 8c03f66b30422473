#pragma once
// An application's whole task as `cobra run APP --scenario DIR` runs it (the runner's observers
// attached, no step observer), timed by the wall clock, shared by the application benchmarks
// (puncturing_bench, puma260_bench). Counters: simulated_s; realtime_factor = simulated s per wall
// s; cpu_realtime_factor = simulated s per CPU s of the process (the same figure without the time a
// loaded machine gives to other processes). Three repetitions of one iteration each: the median,
// and min = the worst repetition (the smallest factor).

#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <ctime>
#include <string>
#include <vector>

#include "cobra/run/runner.hpp"

namespace cobra::bench {

/// CPU time of this process [s] (every thread; a lockstep run has one).
inline double processCpuSeconds() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

inline double minOf(const std::vector<double>& v) { return *std::min_element(v.begin(), v.end()); }

/// Which task: `app` and `scenario` relative to the source tree; `time_limit` in simulated s.
struct AppTask {
  std::string app;
  std::string scenario;
  double time_limit = 900.0;
};

inline void BM_AppSpeed(benchmark::State& state, const AppTask& task) {
  double simulated = 0.0;
  double wall = 0.0;
  double cpu = 0.0;
  bool completed = true;
  for (auto _ : state) {
    run::RunOptions options;
    options.app = std::string(COBRA_SOURCE_DIR) + "/" + task.app;
    options.scenario = std::string(COBRA_SOURCE_DIR) + "/" + task.scenario;
    options.time_limit = task.time_limit;
    const double cpu_started = processCpuSeconds();
    const auto started = std::chrono::steady_clock::now();
    const run::RunResult result = run::runApp(options);
    wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    cpu = processCpuSeconds() - cpu_started;
    simulated = result.duration;
    completed = completed && result.completed();
    state.SetIterationTime(wall);
  }
  if (!completed) state.SkipWithError("the task did not complete");
  state.counters["simulated_s"] = simulated;
  state.counters["realtime_factor"] = wall > 0.0 ? simulated / wall : 0.0;
  state.counters["cpu_realtime_factor"] = cpu > 0.0 ? simulated / cpu : 0.0;
}

/// Registers the benchmark `name` running `task` (3 repetitions, median and min).
inline void registerAppSpeed(const std::string& name, const AppTask& task) {
  benchmark::RegisterBenchmark(name.c_str(), BM_AppSpeed, task)
      ->Iterations(1)
      ->Repetitions(3)
      ->UseManualTime()
      ->ReportAggregatesOnly(true)
      ->ComputeStatistics("min", minOf)
      ->Unit(benchmark::kSecond);
}

}  // namespace cobra::bench
