#pragma once
// An application's whole task as `cobra run APP --scenario DIR` runs it (the runner's observers
// attached, no step observer), timed by the wall clock, shared by the application benchmarks
// (puncturing_bench, puma260_bench, suturing_bench), and the planning requests such a task makes
// (planning_bench, suturing_bench). Counters: simulated_s; realtime_factor = simulated s per wall
// s; cpu_realtime_factor = simulated s per CPU s of the process (the same figure without the time a
// loaded machine gives to other processes). Three repetitions of one iteration each: the median,
// and min = the worst repetition (the smallest factor).

#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "cobra/core/core.hpp"
#include "cobra/run/runner.hpp"
#include "median_and_worst.hpp"

namespace cobra::bench {

/// CPU time of this process [s] (every thread; a lockstep run has one).
inline double processCpuSeconds() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

inline double minOf(const std::vector<double>& v) { return *std::min_element(v.begin(), v.end()); }

/// The value at fraction `q` of the sorted `values` (NaN when empty).
inline double quantile(std::vector<double> values, double q) {
  if (values.empty()) return std::nan("");
  std::sort(values.begin(), values.end());
  return values[static_cast<std::size_t>(q * double(values.size() - 1))];
}

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

/// The planning requests of an application's task, measured where the task makes them: the whole
/// task runs `runs` times as `cobra run` runs it (lockstep, seeded, the planners' work limits: every
/// run makes the same requests), and every step of a component whose name ends in "Planner" in
/// which it served a request (it emitted e_plan_done or e_plan_failed) is timed, wall clock and
/// the stepping thread's CPU. Counters: queries (per run), median_ms, p95_ms, max_ms, cpu_median_ms,
/// cpu_max_ms, success_rate; the count is checked against the runs' logs.
inline void BM_AppPlanningRequests(benchmark::State& state, const AppTask& task, int runs) {
  std::vector<double> times_ms, cpu_ms;
  int requests = 0, solved = 0, logged = 0;
  double slowest_ms = 0.0;
  std::string slowest;
  for (auto _ : state) {
    for (int run = 0; run < runs; ++run) {
      // A tap on each planner's events, connected the first time it steps (before it is asked:
      // its first steps measure the clearance of the first measured poses).
      std::map<const cobra::core::Component*, std::unique_ptr<cobra::core::InputPort<cobra::core::Event>>> taps;
      cobra::run::RunOptions options;
      options.app = std::string(COBRA_SOURCE_DIR) + "/" + task.app;
      options.scenario = std::string(COBRA_SOURCE_DIR) + "/" + task.scenario;
      options.time_limit = task.time_limit;
      options.step_observer = [&](const cobra::core::Component& c, std::chrono::nanoseconds wall,
                                  std::chrono::nanoseconds cpu) {
        if (c.name().size() < 7 || c.name().compare(c.name().size() - 7, 7, "Planner") != 0) return;
        auto& tap = taps[&c];
        if (!tap) {
          tap = std::make_unique<cobra::core::InputPort<cobra::core::Event>>("plannerEvents", "", "");
          cobra::core::connectPorts(const_cast<cobra::core::Component&>(c).events(), *tap,
                                    cobra::core::ConnPolicy::buffer(64));
          return;
        }
        cobra::core::Event e;
        while (tap->read(e) == cobra::core::FlowStatus::NewData) {
          const bool done = e.name == std::string_view("e_plan_done");
          if (!done && !(e.name == std::string_view("e_plan_failed"))) continue;
          const double ms = 1e-6 * static_cast<double>(wall.count());
          times_ms.push_back(ms);
          cpu_ms.push_back(1e-6 * static_cast<double>(cpu.count()));
          ++requests;
          solved += done ? 1 : 0;
          if (ms > slowest_ms) {
            slowest_ms = ms;
            slowest = c.name() + " at " + std::to_string(std::chrono::duration<double>(c.now()).count()) +
                      " s simulated";
          }
        }
      };
      const cobra::run::RunResult result = cobra::run::runApp(options);
      if (!result.completed()) state.SkipWithError(("the procedure did not complete: " + result.reason).c_str());
      for (const std::string& line : result.log)
        if (line.find("Planner: e_plan_done") != std::string::npos ||
            line.find("Planner: e_plan_failed") != std::string::npos)
          ++logged;
    }
  }
  if (logged != requests)
    state.SkipWithError(("timed " + std::to_string(requests) + " requests, the runs' logs have " +
                         std::to_string(logged)).c_str());
  if (requests == 0) return;
  std::fprintf(stderr, "%s: slowest request %.1f ms, %s\n", task.scenario.c_str(), slowest_ms, slowest.c_str());
  state.counters["queries"] = static_cast<double>(requests) / runs;
  state.counters["median_ms"] = quantile(times_ms, 0.5);
  state.counters["p95_ms"] = quantile(times_ms, 0.95);
  state.counters["max_ms"] = maxOf(times_ms);
  state.counters["cpu_median_ms"] = quantile(cpu_ms, 0.5);
  state.counters["cpu_max_ms"] = maxOf(cpu_ms);
  state.counters["success_rate"] = static_cast<double>(solved) / requests;
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
