// Coordination cost during a whole puncturing procedure (thesis ch. 4, apps/puncturing): the
// default two-needle scenario on the lockstep clock, both robots' task, deployment and
// configuration supervisors at 1 kHz alongside their 1 kHz control loops. Every component step is
// timed (core::LockstepClock::setStepObserver) and the step times are reported per kind of
// component, side by side from the same run:
//  - supervisors: the six Supervisor components (rFSM charts in Lua; target: worst < 100 µs);
//  - control: the admittance, equivalent-wrench and trajectory-generator steps of both robots, the
//    real-time loop the supervisors run beside;
//  - world: the simulated robots, patient and monitors (for scale);
//  - floor: as many timed empty steps (the same two clock reads around nothing), right after the
//    procedure: the worst case this machine adds to any step (preemption, interrupts).
// Counters: median, p99, p99.9 and worst step time in µs, and the number of steps; cpu_time:0
// times the steps by the wall clock (what a real-time loop sees, OS preemptions included),
// cpu_time:1 by the thread's CPU time (the code's own cost). One iteration = one
// procedure (about 105 s simulated); the benchmark time is its wall time. Timings are wall-clock
// on a shared machine: the worst case includes the OS's preemptions.

#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <ctime>
#include <string>
#include <vector>

#include "cobra/core/component.hpp"
#include "cobra/puncturing/procedure.hpp"

namespace {

struct StepTimes {
  std::vector<double> supervisors, control, world;  // µs
  void reserve(std::size_t n) {
    supervisors.reserve(n);
    control.reserve(n);
    world.reserve(n);
  }
};

std::chrono::nanoseconds threadCpuTime() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return std::chrono::seconds(ts.tv_sec) + std::chrono::nanoseconds(ts.tv_nsec);
}

bool endsWith(const std::string& s, const char* suffix) {
  const std::string tail(suffix);
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

void report(benchmark::State& state, const char* prefix, std::vector<double>& times) {
  if (times.empty()) return;
  std::sort(times.begin(), times.end());
  const auto at = [&](double q) { return times[static_cast<std::size_t>(q * static_cast<double>(times.size() - 1))]; };
  state.counters[std::string(prefix) + "_median_us"] = at(0.5);
  state.counters[std::string(prefix) + "_p99_us"] = at(0.99);
  state.counters[std::string(prefix) + "_p999_us"] = at(0.999);
  state.counters[std::string(prefix) + "_worst_us"] = times.back();
  state.counters[std::string(prefix) + "_steps"] = static_cast<double>(times.size());
}

/// state.range(0): 0 = wall-clock step times, 1 = the thread's CPU time (without preemption).
void BM_SupervisorsDuringAProcedure(benchmark::State& state) {
  const bool use_cpu_time = state.range(0) == 1;
  StepTimes times;
  bool completed = true;
  for (auto _ : state) {
    times = {};
    times.reserve(1200000);  // ~105 s x 1 kHz x up to 10 components per kind: no reallocation in the run
    cobra::puncturing::ProcedureOptions options;
    options.deployment_file = std::string(COBRA_SOURCE_DIR) + "/apps/puncturing/puncturing.lua";
    options.scenario = std::string(COBRA_SOURCE_DIR) + "/apps/puncturing/scenarios/two_needles";
    options.step_observer = [&](const cobra::core::Component& c, std::chrono::nanoseconds wall,
                                std::chrono::nanoseconds cpu) {
      const double us = static_cast<double>((use_cpu_time ? cpu : wall).count()) * 1e-3;
      const std::string& name = c.name();
      if (endsWith(name, "Sup")) {
        times.supervisors.push_back(us);
      } else if (endsWith(name, "Admittance") || endsWith(name, "Wrench") || endsWith(name, "TrajGen")) {
        times.control.push_back(us);
      } else {
        times.world.push_back(us);
      }
    };
    completed = cobra::puncturing::runProcedure(options).completed && completed;
  }
  if (!completed) state.SkipWithError("the procedure did not complete");
  std::vector<double> floor;
  floor.reserve(times.supervisors.size());
  for (std::size_t i = 0; i < times.supervisors.size(); ++i) {
    const auto cpu_started = threadCpuTime();
    const auto started = std::chrono::steady_clock::now();
    benchmark::ClobberMemory();
    const auto wall = std::chrono::steady_clock::now() - started;
    const auto cpu = threadCpuTime() - cpu_started;
    floor.push_back(static_cast<double>((use_cpu_time ? cpu : wall).count()) * 1e-3);
  }
  report(state, "supervisor", times.supervisors);
  report(state, "control", times.control);
  report(state, "world", times.world);
  report(state, "floor", floor);
}
BENCHMARK(BM_SupervisorsDuringAProcedure)->ArgName("cpu_time")->Arg(0)->Arg(1)->Iterations(1)->Unit(benchmark::kSecond);

}  // namespace

BENCHMARK_MAIN();
