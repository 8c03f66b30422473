// The whole-procedure check of the puncturing task (apps/puncturing/README.md, "Verified whole"):
// the wall time of the NeedlePlanner step that answers verifyProcedure (every motion state of both
// charts walked with the planning library before the first motion), per scenario, with its
// nominal registration. The procedure runs through the runner library as `cobra run` runs it, for
// the first 3 s simulated (the check comes at about 1-2 s); the step is timed by the lockstep
// clock's step observer. Reported: the step's time per repetition (manual time: median and worst
// over the repetitions) and its validity checks (the planner's unit of work, the same in every
// run: the walk is deterministic).

#include <benchmark/benchmark.h>

#include <chrono>
#include <string>

#include "cobra/core/component.hpp"
#include "cobra/run/runner.hpp"

#include "median_and_worst.hpp"

namespace {

void BM_WholeProcedureCheck(benchmark::State& state, const std::string& scenario) {
  std::string verification;
  for (auto _ : state) {
    double check_s = -1.0;
    cobra::run::RunOptions options;
    options.app = std::string(COBRA_SOURCE_DIR) + "/apps/puncturing";
    options.scenario = std::string(COBRA_SOURCE_DIR) + "/apps/puncturing/scenarios/" + scenario;
    options.time_limit = 3.0;  // s simulated
    options.step_observer = [&](const cobra::core::Component& c, std::chrono::nanoseconds wall,
                                std::chrono::nanoseconds) {
      if (check_s >= 0.0 || c.name() != "NeedlePlanner") return;
      // The step after which lastVerification() says something is the check's.
      auto& planner = const_cast<cobra::core::Component&>(c);
      const std::string said = planner.call<std::string>("lastVerification");
      if (said.empty()) return;
      check_s = static_cast<double>(wall.count()) * 1e-9;
      verification = said;
    };
    cobra::run::runApp(options);
    if (check_s < 0.0) {
      state.SkipWithError("the procedure was not verified within 3 s simulated");
      return;
    }
    state.SetIterationTime(check_s);
  }
  state.SetLabel(verification);
}

const bool kRegistered = [] {
  for (const char* scenario : {"vertical_needle", "two_needles", "three_needles"})
    benchmark::RegisterBenchmark((std::string("WholeProcedureCheck/") + scenario).c_str(), BM_WholeProcedureCheck,
                                 std::string(scenario))
        ->UseManualTime()
        ->Iterations(1)
        ->Repetitions(5)
        ->ComputeStatistics("max", cobra::bench::maxOf)
        ->Unit(benchmark::kMillisecond);
  return true;
}();

}  // namespace

BENCHMARK_MAIN();
