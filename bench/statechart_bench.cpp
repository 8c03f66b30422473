// Cost of coordination (issue 4): events through cobra's statechart engine, with C++ guards and
// with Lua guards (an rFSM file), against Boost.MSM in the same run, and a Supervisor component's
// step on the lockstep clock.
//
// Every benchmark runs 10 repetitions and reports their median and worst case ("max"). The time
// column is per event (one raise + the step that takes its transition); `transitions_per_s` is
// its inverse. Charts:
//  - cobra: a 3-level chart, root > work > {fast > {a, b}, slow}, where four events cycle
//    a -> b -> slow -> a (through fast's initial) and back; each transition has a guard returning
//    true, so every event costs a guard call, an exit/entry chain and an LCA.
//  - Boost.MSM: the same four states and events, flat (MSM's submachines change the cost model),
//    with functor guards: the peer for "dispatch one event to a state machine".
// Targets (issue 4): >= 1,000,000 transitions/s with C++ guards, >= 100,000/s with Lua guards,
// supervisor step < 10 us median.

#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <vector>

#include "cobra/components/coordination/package.hpp"
#include "cobra/components/coordination/supervisor.hpp"
#include "cobra/deploy/deploy.hpp"
#include "cobra/script/rfsm.hpp"
#include "cobra/statechart/machine.hpp"
#include "statechart_msm_peer.hpp"

namespace {

using namespace cobra;

constexpr int kRepetitions = 10;
constexpr double kMinTime = 0.05;  // s per repetition

double maxOf(const std::vector<double>& v) { return *std::max_element(v.begin(), v.end()); }
void configure(benchmark::internal::Benchmark* b) {
  b->Repetitions(kRepetitions)->ReportAggregatesOnly(true)->ComputeStatistics("max", maxOf)->MinTime(kMinTime);
}

const char* const kEvents[] = {"e_ab", "e_bslow", "e_slowa", "e_noise"};

statechart::TransitionSpec guarded(std::string src, std::string tgt, std::vector<std::string> events) {
  statechart::TransitionSpec t;
  t.src = std::move(src);
  t.tgt = std::move(tgt);
  t.events = std::move(events);
  t.guard = [](const statechart::StepEvents&) { return true; };
  return t;
}

statechart::Chart threeLevelChart() {
  statechart::ChartBuilder b;
  b.addState("root", "work");
  b.addState("root.work", "fast");
  b.addState("root.work.fast", "a");
  b.addState("root.work.fast", "b");
  b.addState("root.work", "slow");
  b.addTransition("root", guarded("initial", "work", {}));
  b.addTransition("root.work", guarded("initial", "fast", {}));
  b.addTransition("root.work.fast", guarded("initial", "a", {}));
  b.addTransition("root.work.fast", guarded("a", "b", {"e_ab"}));
  b.addTransition("root.work", guarded(".fast.b", "slow", {"e_bslow"}));
  b.addTransition("root.work", guarded("slow", "fast", {"e_slowa"}));
  return b.build();
}

void runEvents(benchmark::State& state, statechart::Machine& m) {
  m.run();
  std::size_t i = 0;
  for (auto _ : state) {
    m.raise(kEvents[i++ % 3]);
    m.step();  // the event's transition
    m.step();  // the e_done@<leaf> it raised: no transition waits for it (dropped)
  }
  state.counters["transitions_per_s"] = benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}

void CobraCppGuards(benchmark::State& state) {
  const statechart::Chart chart = threeLevelChart();
  statechart::Machine m(chart, {});
  runEvents(state, m);
}

void CobraLuaGuards(benchmark::State& state) {
  script::LuaState lua({4 << 20, "bench", ""});
  const auto chart = script::RfsmChart::loadString(lua, R"(
local yes = function() return true end
return rfsm.state {
  work = rfsm.state {
    fast = rfsm.state {
      a = rfsm.state {}, b = rfsm.state {},
      rfsm.trans { src = 'initial', tgt = 'a' },
      rfsm.trans { src = 'a', tgt = 'b', events = { 'e_ab' }, guard = yes },
    },
    slow = rfsm.state {},
    rfsm.trans { src = 'initial', tgt = 'fast' },
    rfsm.trans { src = '.fast.b', tgt = 'slow', events = { 'e_bslow' }, guard = yes },
    rfsm.trans { src = 'slow', tgt = 'fast', events = { 'e_slowa' }, guard = yes },
  },
  rfsm.trans { src = 'initial', tgt = 'work' },
})", "=bench");
  statechart::Machine m(chart->chart(), {});
  chart->bind(&m);
  runEvents(state, m);
}

// --- Boost.MSM peer (statechart_msm_peer.cpp: compiled as C++17, Boost 1.74's MSM predates C++20)
void BoostMsm(benchmark::State& state) {
  MsmPeer* m = msmCreate();
  int i = 0;
  for (auto _ : state) msmDispatch(m, i++ % 3);
  msmDestroy(m);
  state.counters["transitions_per_s"] = benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}

// --- a Supervisor component's step --------------------------------------------------------------
void SupervisorStep(benchmark::State& state) {
  deploy::Configurator configurator;
  configurator.packages().addBuiltin("cobra_coordination", components::registerCoordinationPackage);
  configurator.initConfigurator({{"cobra_coordination", {}}}, {{"Sup", "Supervisor", {}}});
  core::Component& sup = configurator.getReferences().get("Sup");
  sup.setProperty("fsm_path", std::string(COBRA_SOURCE_DIR) + "/script/test/charts/fig32.lua");
  core::OutputPort<core::Event> events{"events", "bench", ""};
  core::connectPorts(events, sup.port("inputEvents"), core::ConnPolicy::buffer(8));
  configurator.configureComponents({{"Sup", {}}});
  configurator.startComponents({{"Sup", {}}});
  const char* cycle[] = {"e_start", "e_stop"};
  std::size_t i = 0;
  for (auto _ : state) {
    core::Event e;
    e.name = cycle[i++ % 2];
    events.write(e);
    configurator.clock().advance(std::chrono::milliseconds(1));  // the supervisor steps on the event
  }
}

}  // namespace

BENCHMARK(CobraCppGuards)->Apply(configure);
BENCHMARK(CobraLuaGuards)->Apply(configure);
BENCHMARK(BoostMsm)->Apply(configure);
BENCHMARK(SupervisorStep)->Apply(configure);
BENCHMARK_MAIN();
