// Cost of coordination: events through cobra's statechart engine, with C++ guards and
// with Lua guards (an rFSM file), against Boost.MSM in the same run, and a Supervisor component's
// step on the lockstep clock; and the cost of the Lua budget's count hook on a Lua loop.
//
// Every benchmark runs 10 repetitions and reports their median and worst case ("max"). The time
// column is per external event: one raise plus the steps that handle it, i.e. the step that
// takes its transition and the step that drops the e_done@<leaf> the entered leaf raised (rFSM
// semantics: a completion event is an event; MSM has none, so cobra does twice the steps).
// `transitions_per_s` is its inverse. Charts:
//  - Cobra3Level: root > work > {fast > {a, b}, slow}, where three events cycle
//    a -> b -> slow -> a (through fast's initial); each transition has a guard returning true: guard calls, exit/entry chains and an LCA per event;
//  - CobraFlat: the same three states flat with the same guards: the like-for-like peer of
//  - BoostMsm: three states cycling on three events with functor guards (statechart_msm_peer.cpp);
//  - CobraToggle: two states, one event each way, no guard: the engine's floor.
// PerEvent* time each single event (steady_clock around raise + 2 steps, resp. process_event) and
// report p50/p99/max_ns of one run as counters: the worst case a supervisor's update sees.
// Targets: >= 1,000,000 transitions/s with C++ guards, >= 100,000/s with Lua guards,
// supervisor step < 10 us median.

#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <vector>

#include "cobra/components/builtin_packages.hpp"
#include "cobra/components/coordination/supervisor.hpp"
#include "cobra/deploy/deploy.hpp"
#include "cobra/script/rfsm.hpp"
#include "cobra/statechart/machine.hpp"

#include <lua.hpp>
#include "statechart_msm_peer.hpp"
#include "median_and_worst.hpp"

namespace {

using namespace cobra;

constexpr int kRepetitions = 10;
constexpr double kMinTime = 0.05;  // s per repetition

using cobra::bench::maxOf;
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

void Cobra3Level(benchmark::State& state) {
  const statechart::Chart chart = threeLevelChart();
  statechart::Machine m(chart, {});
  runEvents(state, m);
}

statechart::Chart flatChart() {
  statechart::ChartBuilder b;
  for (const char* s : {"a", "b", "slow"}) b.addState("root", s);
  b.addTransition("root", guarded("initial", "a", {}));
  b.addTransition("root", guarded("a", "b", {"e_ab"}));
  b.addTransition("root", guarded("b", "slow", {"e_bslow"}));
  b.addTransition("root", guarded("slow", "a", {"e_slowa"}));
  return b.build();
}

void CobraFlat(benchmark::State& state) {
  const statechart::Chart chart = flatChart();
  statechart::Machine m(chart, {});
  runEvents(state, m);
}

void CobraToggle(benchmark::State& state) {
  statechart::ChartBuilder b;
  b.addState("root", "off");
  b.addState("root", "on");
  b.addTransition("root", {"initial", "off", {}, 0, {}, {}, {}});
  b.addTransition("root", {"off", "on", {"e_toggle"}, 0, {}, {}, {}});
  b.addTransition("root", {"on", "off", {"e_toggle"}, 0, {}, {}, {}});
  const statechart::Chart chart = b.build();
  statechart::Machine m(chart, {});
  m.run();
  for (auto _ : state) {
    m.raise("e_toggle");
    m.step();
    m.step();
  }
  state.counters["transitions_per_s"] = benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}

/// Times each call of `one_event(i)` and reports p50/p99/max in ns of this run.
template <class OneEvent>
void perEvent(benchmark::State& state, OneEvent one_event) {
  std::vector<double> ns;
  ns.reserve(1 << 20);
  std::size_t i = 0;
  for (auto _ : state) {
    const auto start = std::chrono::steady_clock::now();
    one_event(i++);
    const auto stop = std::chrono::steady_clock::now();
    if (ns.size() < ns.capacity()) ns.push_back(std::chrono::duration<double, std::nano>(stop - start).count());
  }
  std::sort(ns.begin(), ns.end());
  state.counters["p50_ns"] = ns[ns.size() / 2];
  state.counters["p99_ns"] = ns[ns.size() * 99 / 100];
  state.counters["max_ns"] = ns.back();
}

void PerEventCobraFlat(benchmark::State& state) {
  const statechart::Chart chart = flatChart();
  statechart::Machine m(chart, {});
  m.run();
  perEvent(state, [&m](std::size_t i) {
    m.raise(kEvents[i % 3]);
    m.step();
    m.step();
  });
}

void PerEventBoostMsm(benchmark::State& state) {
  MsmPeer* m = msmCreate();
  perEvent(state, [m](std::size_t i) { msmDispatch(m, static_cast<int>(i % 3)); });
  msmDestroy(m);
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
  components::addBuiltinPackages(configurator.packages());
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

// --- the Lua budget's count hook (LuaState, "Budget and interrupts") ---------------------------
// One call of a Lua function adding 100,000 numbers (about 400,000 instructions, so 40 hook calls)
// as one step: LuaNoHook without any hook (the peer: what the check costs is the difference),
// LuaHookNoBudget with the state's hook and no budget (each hook call returns at once),
// LuaHookBudget with a budget it never reaches (each hook call reads the thread's CPU clock).
void luaLoop(benchmark::State& state, int mode) {
  script::LuaState lua({4 << 20, "bench", ""});
  if (mode == 0) lua_sethook(lua.get(), nullptr, 0, 0);
  if (mode == 2) lua.setBudget(std::chrono::seconds(10));
  lua.run("function work() local x = 0 for i = 1, 100000 do x = x + i end return x end", "=bench");
  lua_State* L = lua.get();
  for (auto _ : state) {
    lua.startStep();
    lua_getglobal(L, "work");
    lua.call(0, 1);
    benchmark::DoNotOptimize(lua_tonumber(L, -1));
    lua_pop(L, 1);
  }
}
void LuaNoHook(benchmark::State& state) { luaLoop(state, 0); }
void LuaHookNoBudget(benchmark::State& state) { luaLoop(state, 1); }
void LuaHookBudget(benchmark::State& state) { luaLoop(state, 2); }

}  // namespace

BENCHMARK(Cobra3Level)->Apply(configure);
BENCHMARK(CobraFlat)->Apply(configure);
BENCHMARK(BoostMsm)->Apply(configure);
BENCHMARK(CobraToggle)->Apply(configure);
BENCHMARK(PerEventCobraFlat)->Apply(configure);
BENCHMARK(PerEventBoostMsm)->Apply(configure);
BENCHMARK(CobraLuaGuards)->Apply(configure);
BENCHMARK(SupervisorStep)->Apply(configure);
BENCHMARK(LuaNoHook)->Apply(configure);
BENCHMARK(LuaHookNoBudget)->Apply(configure);
BENCHMARK(LuaHookBudget)->Apply(configure);
BENCHMARK_MAIN();
