// Coordination cost during a whole puncturing procedure (thesis ch. 4, apps/puncturing): the
// default two-needle scenario on the lockstep clock, both robots' task, deployment and
// configuration supervisors at 1 kHz alongside their 1 kHz control loops. Every component step is
// timed by the wall clock (core::LockstepClock::setStepObserver) and reported per kind of
// component, side by side from the same runs:
//  - supervisor: the six Supervisor components (rFSM charts in Lua; target: worst < 100 µs);
//  - control: the admittance, equivalent-wrench and trajectory-generator steps of both robots, the
//    real-time loop the supervisors run beside;
//  - world: the simulated robots, patient, monitors and the planners (for scale).
//
// The procedure runs through the runner library (cobra::run: the app's files, as `cobra run`
// runs them). It is deterministic (seeded, lockstep), so the n-th supervisor step does the same
// work in every run. The benchmark runs it kRuns times and reports, besides the raw figures over
// all runs (median, p99, p99.9, worst: what a loop on this machine sees, OS and hypervisor
// preemptions included), the worst over steps of each step's fastest run (`*_code_worst_us`): the
// code's own worst step, since a preemption rarely hits the same step in every run. The
// difference (`*_noise_worst_us`, the most a run added to a step) is this machine's share.
// The slowest steps by that measure are printed with their component and chart state.
// The benchmark time is the wall time of one procedure (about 161 s simulated).
// ProcedureSpeed/<scenario>: each scenario's whole procedure as `cobra run` runs it (app_speed.hpp:
// realtime_factor = simulated s per wall s, cpu_realtime_factor = per CPU s; median and worst).

#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <map>
#include <numeric>
#include <string>
#include <vector>

#include "cobra/components/coordination/supervisor.hpp"
#include "cobra/core/component.hpp"
#include "cobra/run/runner.hpp"

#include "app_speed.hpp"

namespace {

constexpr int kRuns = 3;
constexpr double kSlowStepUs = 30.0;  // steps above this keep their chart state for the listing

/// One kind of component's steps in one run, in step order.
struct Steps {
  std::vector<double> us;                  // wall-clock step time
  std::vector<std::uint8_t> component;     // index into Kind::names
  std::map<std::size_t, std::string> slow;  // step -> chart state, for steps above kSlowStepUs
};

struct Kind {
  const char* label;
  std::vector<Steps> runs;
  std::vector<std::string> names;

  void record(const cobra::core::Component& c, double us) {
    Steps& steps = runs.back();
    auto it = std::find(names.begin(), names.end(), c.name());
    if (it == names.end()) it = names.insert(names.end(), c.name());
    steps.us.push_back(us);
    steps.component.push_back(static_cast<std::uint8_t>(it - names.begin()));
    if (us > kSlowStepUs) {
      const auto* supervisor = dynamic_cast<const cobra::components::Supervisor*>(&c);
      steps.slow.emplace(steps.us.size() - 1, supervisor ? std::string(supervisor->activeState()) : std::string());
    }
  }
};

bool endsWith(const std::string& s, const char* suffix) {
  const std::string tail(suffix);
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

double quantile(const std::vector<double>& sorted, double q) {
  return sorted[static_cast<std::size_t>(q * static_cast<double>(sorted.size() - 1))];
}

/// Same steps, same components, in the same order in every run (the procedure is deterministic).
bool sameSequence(const Kind& kind) {
  for (const Steps& run : kind.runs)
    if (run.component != kind.runs.front().component) return false;
  return true;
}

void report(benchmark::State& state, const Kind& kind, bool list_slowest) {
  const std::string prefix(kind.label);
  std::vector<double> all;
  for (const Steps& run : kind.runs) all.insert(all.end(), run.us.begin(), run.us.end());
  if (all.empty()) return;
  std::sort(all.begin(), all.end());
  state.counters[prefix + "_median_us"] = quantile(all, 0.5);
  state.counters[prefix + "_p99_us"] = quantile(all, 0.99);
  state.counters[prefix + "_p999_us"] = quantile(all, 0.999);
  state.counters[prefix + "_worst_us"] = all.back();
  state.counters[prefix + "_steps"] = static_cast<double>(kind.runs.front().us.size());
  if (!sameSequence(kind)) {
    std::fprintf(stderr, "%s: the runs' step sequences differ; no per-step minimum\n", kind.label);
    return;
  }
  const std::size_t n = kind.runs.front().us.size();
  std::vector<double> fastest(n), added(n, 0.0);
  for (std::size_t i = 0; i < n; ++i) {
    fastest[i] = kind.runs.front().us[i];
    for (const Steps& run : kind.runs) fastest[i] = std::min(fastest[i], run.us[i]);
    for (const Steps& run : kind.runs) added[i] = std::max(added[i], run.us[i] - fastest[i]);
  }
  state.counters[prefix + "_code_worst_us"] = *std::max_element(fastest.begin(), fastest.end());
  state.counters[prefix + "_noise_worst_us"] = *std::max_element(added.begin(), added.end());
  if (!list_slowest) return;
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), std::size_t{0});
  const std::size_t shown = std::min<std::size_t>(15, n);
  std::partial_sort(order.begin(), order.begin() + static_cast<std::ptrdiff_t>(shown), order.end(),
                    [&](std::size_t a, std::size_t b) { return fastest[a] > fastest[b]; });
  std::fprintf(stderr, "%s: the %zu slowest steps (fastest of %d runs; chart state after the step)\n", kind.label,
               shown, kRuns);
  for (std::size_t k = 0; k < shown; ++k) {
    const std::size_t i = order[k];
    const auto state_after = kind.runs.front().slow.find(i);
    std::fprintf(stderr, "  step %zu %s: %.1f us (runs:", i, kind.names[kind.runs.front().component[i]].c_str(),
                 fastest[i]);
    for (const Steps& run : kind.runs) std::fprintf(stderr, " %.1f", run.us[i]);
    std::fprintf(stderr, ") %s\n", state_after == kind.runs.front().slow.end() ? "" : state_after->second.c_str());
  }
}

void BM_SupervisorsDuringAProcedure(benchmark::State& state) {
  Kind supervisors{"supervisor", {}, {}}, control{"control", {}, {}}, world{"world", {}, {}};
  bool completed = true;
  for (auto _ : state) {
    for (Kind* kind : {&supervisors, &control, &world}) {
      kind->runs.emplace_back();
      kind->runs.back().us.reserve(1200000);  // no reallocation during the run
      kind->runs.back().component.reserve(1200000);
    }
    cobra::run::RunOptions options;  // what `cobra run apps/puncturing` runs, through the runner's API
    options.app = std::string(COBRA_SOURCE_DIR) + "/apps/puncturing";
    options.scenario = std::string(COBRA_SOURCE_DIR) + "/apps/puncturing/scenarios/two_needles";
    options.step_observer = [&](const cobra::core::Component& c, std::chrono::nanoseconds wall, std::chrono::nanoseconds) {
      const double us = static_cast<double>(wall.count()) * 1e-3;
      const std::string& name = c.name();
      if (endsWith(name, "Sup")) {
        supervisors.record(c, us);
      } else if (endsWith(name, "Admittance") || endsWith(name, "Wrench") || endsWith(name, "TrajGen")) {
        control.record(c, us);
      } else {
        world.record(c, us);
      }
    };
    completed = cobra::run::runApp(options).completed() && completed;
  }
  if (!completed) state.SkipWithError("the procedure did not complete");
  report(state, supervisors, true);
  report(state, control, true);
  report(state, world, false);
}
BENCHMARK(BM_SupervisorsDuringAProcedure)->Iterations(kRuns)->Unit(benchmark::kSecond);

/// The whole procedure of each scenario (target: realtime_factor >= 100); see app_speed.hpp.
const bool kProcedureSpeedRegistered = [] {
  for (const char* scenario : {"two_needles", "three_needles", "vertical_needle"})
    cobra::bench::registerAppSpeed(std::string("ProcedureSpeed/") + scenario,
                                   {"apps/puncturing", std::string("apps/puncturing/scenarios/") + scenario});
  return true;
}();

}  // namespace

BENCHMARK_MAIN();
