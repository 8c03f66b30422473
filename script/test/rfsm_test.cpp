// rFSM files and rFSM's Lua API on cobra's statechart engine.
#include "cobra/script/rfsm.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include <lua.hpp>

#include "cobra/test_support/test_support.hpp"

namespace cobra::script {
namespace {

using statechart::Machine;
using statechart::RaiseStatus;

const std::string kCharts = std::string(COBRA_SOURCE_DIR) + "/script/test/charts/";

/// Keeps the failures the machine reports.
struct Failures : statechart::Observer {
  std::vector<std::string> seen;
  void callbackFailed(std::string_view callback, std::string_view element, std::string_view what) override {
    seen.push_back(std::string(callback) + " of " + std::string(element) + ": " + std::string(what));
  }
};

TEST(Rfsm, TheThesisFigure32ListingAsPrintedIsRefusedAtItsTypo) {
  LuaState lua;
  const std::string message = cobra::test_support::messageOf([&] { RfsmChart::loadFile(lua, kCharts + "fig32_as_printed.lua"); });
  EXPECT_CONTAINS(message, "fig32_as_printed.lua:18: transition from 'fatal_error' in root has no tgt (its fields: "
                           "events, src, tqt)");
}

TEST(Rfsm, TheThesisFigure32ChartLoadsAndBehavesAsTheFigureSays) {
  LuaState lua;
  const auto chart = RfsmChart::loadFile(lua, kCharts + "fig32.lua");
  Machine m(chart->chart(), {});
  chart->bind(&m);
  ASSERT_TRUE(m.run());
  EXPECT_EQ(m.activeLeaf(), "root.on.waiting");
  const std::vector<std::pair<const char*, const char*>> sequence = {
      {"e_start", "root.on.moving"}, {"e_stop", "root.on.waiting"}, {"e_start", "root.on.moving"},
      {"e_error", "root.error"}, {"e_error_fixed", "root.on.waiting"}, {"e_error", "root.error"},
      {"e_fatal_error", "root.fatal_error"}, {"e_reset", "root.on.waiting"}};
  for (const auto& [event, expected] : sequence) {
    ASSERT_EQ(m.raise(event), RaiseStatus::Queued);
    m.run();
    EXPECT_EQ(m.activeLeaf(), expected) << "after " << event;
  }
}

TEST(Rfsm, CallbacksGetRfsmsArgumentsAndDooIsACoroutine) {
  LuaState lua;
  const auto chart = RfsmChart::loadFile(lua, kCharts + "callbacks.lua");
  Machine m(chart->chart(), {});
  chart->bind(&m);
  m.run();
  m.raise("e_go");
  m.run();
  EXPECT_EQ(m.activeLeaf(), "root.idle");  // the guard wants two events
  m.raise("e_go");
  m.raise("e_other");
  m.run();
  // working's doo ran three slices, finished (e_done), waiting's entry sent e_self to its own fsm.
  EXPECT_EQ(m.activeLeaf(), "root.done");
  EXPECT_EQ(lua.evaluate("table.concat(log, '; ')"),
            "entry idle; guard e_done@root.idle; guard e_go; guard e_go,e_other; exit idle; effect e_go; doo 1; "
            "doo 2; doo 3");  // rFSM asks the guard first, so also in the step of idle's e_done
}

TEST(Rfsm, AFailingLuaCallbackIsReportedWithItsFileAndLine) {
  LuaState lua;
  const auto chart = RfsmChart::loadString(lua, R"(return rfsm.state {
  a = rfsm.state { entry = function() error("no sensor") end },
  rfsm.trans { src = 'initial', tgt = 'a' },
})", "@broken.lua");
  Machine m(chart->chart(), {});
  Failures failures;
  m.setObserver(&failures);
  m.run();
  ASSERT_EQ(failures.seen.size(), 1U);
  EXPECT_EQ(failures.seen[0], "entry of root.a: broken.lua:2: no sensor");
  EXPECT_EQ(m.activeLeaf(), "root.a");
}

TEST(Rfsm, AFailingDooIsReportedAndTheLuaStackStaysWhole) {
  // The doo's error is on its coroutine's stack; taking it from the main thread's stack popped a
  // value that was not there, and the next call into Lua hit Lua's panic handler (abort).
  LuaState lua;
  const auto chart = RfsmChart::loadString(lua, R"(return rfsm.state {
  a = rfsm.state { doo = function() undefined_function() end },
  b = rfsm.state { entry = function() entered_b = true end },
  rfsm.trans { src = 'initial', tgt = 'a' },
  rfsm.trans { src = 'a', tgt = 'b', events = { 'e_go' } },
})", "@doo.lua");
  Machine m(chart->chart(), {});
  Failures failures;
  m.setObserver(&failures);
  const int top = lua_gettop(lua.get());
  m.run();
  ASSERT_GE(failures.seen.size(), 1U);
  EXPECT_EQ(failures.seen[0], "doo of root.a: doo.lua:2: attempt to call a nil value (global 'undefined_function')");
  EXPECT_EQ(lua_gettop(lua.get()), top);
  ASSERT_EQ(m.raise("e_go"), RaiseStatus::Queued);
  m.run();
  EXPECT_EQ(m.activeLeaf(), "root.b");
  EXPECT_EQ(lua.evaluate("entered_b"), "true");
  EXPECT_EQ(lua_gettop(lua.get()), top);
}

TEST(Rfsm, ModelErrorsNameFileLineAndPath) {
  LuaState lua;
  const std::string message = cobra::test_support::messageOf([&] { RfsmChart::loadFile(lua, kCharts + "bad.lua"); });
  EXPECT_CONTAINS(message, "bad.lua:9: transition in root has an 'event' field; rFSM reads 'events' (a list)");
  EXPECT_CONTAINS(message, "bad.lua:10: transition in root: event function");
  EXPECT_CONTAINS(message, "(function events are not supported: use a guard)");
  const std::string engine = cobra::test_support::messageOf([&] {
    RfsmChart::loadString(lua, R"(return rfsm.state {
  busy = rfsm.state { inner = rfsm.state {}, doo = function() end, rfsm.trans { src = 'initial', tgt = 'inner' } },
  rfsm.trans { src = 'initial', tgt = 'busy' },
  rfsm.trans { src = 'busy', tgt = 'nowhere', events = { 'e_x' } },
})", "@engine.lua");
  });
  EXPECT_CONTAINS(engine, "engine.lua:2: state root.busy has a doo but is composite");
  EXPECT_CONTAINS(engine, "engine.lua:4: transition busy -> nowhere in root: unknown target, no node 'root.nowhere'");
  EXPECT_CONTAINS(cobra::test_support::messageOf([&] { RfsmChart::loadString(lua, "return 42", "@number.lua"); }),
                  "number.lua: the chart must return an rfsm.state");
  EXPECT_CONTAINS(cobra::test_support::messageOf([&] { RfsmChart::loadString(lua, "return rfsm.state {", "@syntax.lua"); }),
                  "syntax.lua:1:");
}

TEST(Rfsm, ScriptsWrittenForRfsmRunUnchanged) {
  LuaState lua;
  installRfsm(lua);
  lua.run("package.path = '" + kCharts + "?.lua;' .. package.path\n" + R"(
local rfsm = require("rfsm")
local fsm = rfsm.init(rfsm.load(")" + kCharts + R"(fig32.lua"))
trace = {}
rfsm.post_step_hook_add(fsm, function(f) trace[#trace + 1] = rfsm.get_actleaf_fqn(f) or "-" end)
rfsm.run(fsm)
first = rfsm.get_actleaf_fqn(fsm)
rfsm.send_events(fsm, 'e_start')
rfsm.run(fsm)
second = rfsm.get_actleaf_fqn(fsm)
conf = table.concat(rfsm.get_active_conf(fsm), " ")
rfsm.send_events(fsm, 'e_error', 'e_fatal_error')
idle = rfsm.step(fsm, 1)
third = rfsm.get_actleaf_fqn(fsm)
)", "=driver");
  EXPECT_EQ(lua.evaluate("first"), "root.on.waiting");
  EXPECT_EQ(lua.evaluate("second"), "root.on.moving");
  EXPECT_EQ(lua.evaluate("conf"), "root root.on root.on.moving");
  EXPECT_EQ(lua.evaluate("third"), "root.error");  // one step, both events: e_error is taken, e_fatal_error dropped
  EXPECT_EQ(lua.evaluate("trace[1]"), "root.on.waiting");
  EXPECT_CONTAINS(cobra::test_support::messageOf([&] { lua.run("rfsm.step(rfsm.load('" + kCharts + "fig32.lua'))", "=x"); }),
                  "this fsm was not initialised: call rfsm.init(model) first");
}

TEST(Rfsm, TimeEventsUseTheGettimeHookOfRfsmTimeevent) {
  LuaState lua;
  installRfsm(lua);
  lua.run(R"(
local rfsm = require("rfsm")
local te = require("rfsm_timeevent")
now = 0
te.set_gettime_hook(function() return now end)
fsm = rfsm.init(rfsm.state {
  a = rfsm.state {}, b = rfsm.state {},
  rfsm.trans { src = 'initial', tgt = 'a' },
  rfsm.trans { src = 'a', tgt = 'b', events = { 'e_after(0.5)' } },
})
rfsm.run(fsm)
now = 4e8  rfsm.run(fsm)  early = rfsm.get_actleaf_fqn(fsm)
now = 6e8  rfsm.run(fsm)  late = rfsm.get_actleaf_fqn(fsm)
)", "=timed");
  EXPECT_EQ(lua.evaluate("early"), "root.a");
  EXPECT_EQ(lua.evaluate("late"), "root.b");
}

}  // namespace
}  // namespace cobra::script
