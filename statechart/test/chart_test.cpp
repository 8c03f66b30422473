// Building charts: the thesis' Fig. 3.2 example, load-time errors, a seeded random property test
// and the no-allocation rule of a loaded chart's steps.
#include "cobra/statechart/chart.hpp"

#include <gtest/gtest.h>

#include <random>
#include <string>
#include <vector>

#include "cobra/statechart/machine.hpp"
#include "cobra/test_support/counting_new.hpp"
#include "cobra/test_support/test_support.hpp"

namespace cobra::statechart {
namespace {

TransitionSpec trans(std::string src, std::string tgt, std::vector<std::string> events = {}, std::string origin = {}) {
  TransitionSpec t;
  t.src = std::move(src);
  t.tgt = std::move(tgt);
  t.events = std::move(events);
  t.origin = std::move(origin);
  return t;
}

/// Fig. 3.2 of the thesis, with its last transition's target spelt `tgt` (the listing has `tqt`).
Chart figure32() {
  ChartBuilder b;
  b.addState("root", "on");
  b.addState("root.on", "moving");
  b.addState("root.on", "waiting");
  b.addTransition("root.on", trans("initial", "waiting"));
  b.addTransition("root.on", trans("waiting", "moving", {"e_start"}));
  b.addTransition("root.on", trans("moving", "waiting", {"e_stop"}));
  b.addState("root", "error");
  b.addState("root", "fatal_error");
  b.addTransition("root", trans("initial", "on"));
  b.addTransition("root", trans("on", "error", {"e_error"}));
  b.addTransition("root", trans("error", "on", {"e_error_fixed"}));
  b.addTransition("root", trans("error", "fatal_error", {"e_fatal_error"}));
  b.addTransition("root", trans("fatal_error", "initial", {"e_reset"}));
  return b.build();
}

TEST(Chart, Figure32BehavesAsTheFigureSaysOnASequenceVisitingEveryTransition) {
  const Chart chart = figure32();
  Machine m(chart, {});
  ASSERT_TRUE(m.run());
  EXPECT_EQ(m.activeLeaf(), "root.on.waiting");
  const std::vector<std::pair<const char*, const char*>> sequence = {
      {"e_start", "root.on.moving"},   {"e_stop", "root.on.waiting"},   {"e_start", "root.on.moving"},
      {"e_error", "root.error"},       {"e_error_fixed", "root.on.waiting"}, {"e_error", "root.error"},
      {"e_fatal_error", "root.fatal_error"}, {"e_start", "root.fatal_error"}, {"e_reset", "root.on.waiting"},
  };
  for (const auto& [event, expected] : sequence) {
    ASSERT_EQ(m.raise(event), RaiseStatus::Queued);
    m.run();
    EXPECT_EQ(m.activeLeaf(), expected) << "after " << event;
  }
}

TEST(Chart, LoadErrorsNameTheOriginThePathAndWhatToDo) {
  ChartBuilder b;
  StateSpec composite_with_doo;
  composite_with_doo.doo = [](bool) { return DooStatus::Done; };
  composite_with_doo.origin = "task.lua:3";
  b.addState("root", "busy", std::move(composite_with_doo));
  b.addState("root.busy", "inner");
  b.addState("root", "plain");
  b.addState("root.plain", "child");  // composite, but nothing leads from its initial
  b.addConnector("root", "join", "task.lua:5");
  b.addTransition("root", trans("initial", "busy", {}, "task.lua:9"));
  b.addTransition("root", trans("busy", "nowhere", {"e_x"}, "task.lua:10"));
  b.addTransition("root", trans("busy", "plain", {"e_y"}, "task.lua:11"));
  b.addTransition("root.busy", trans("initial", "inner", {"e_z"}, "task.lua:12"));  // allowed, as in rFSM
  b.addTransition("root", trans("busy", "root.plain.child", {"e_after(soon)"}, "task.lua:13"));
  b.addTransition("root", trans("join", "busy", {"e_done"}, "task.lua:14"));
  b.addTransition("root", trans("join", "busy", {"e_after(2)"}, "task.lua:15"));
  b.addTransition("root", trans("root.plain.chld", "busy", {}, "task.lua:16"));
  b.addTransition("root", trans("busy", "join", {"e_after(1)", "e_at(4)"}, "task.lua:17"));
  b.addTransition("root", trans("busy", "", {}, "task.lua:18"));
  const std::string message = cobra::test_support::messageOf([&] { b.build(); });
  EXPECT_CONTAINS(message, "chart has 9 problem(s):");
  EXPECT_CONTAINS(message, "task.lua:3: state root.busy has a doo but is composite; doo is allowed in leaf states only");
  EXPECT_CONTAINS(message, "task.lua:10: transition busy -> nowhere in root: unknown target, no node 'root.nowhere'; "
                           "the nodes of root are root.busy, root.plain, root.join, root.initial");
  EXPECT_CONTAINS(message, "task.lua:11: transition busy -> plain in root: the target root.plain is composite but has "
                           "no initial connector; give it a transition from 'initial'");
  EXPECT_EQ(message.find("task.lua:12"), std::string::npos) << message;
  EXPECT_CONTAINS(message, "task.lua:13: transition busy -> root.plain.child in root: 'e_after(soon)' is not a time event");
  EXPECT_CONTAINS(message, "task.lua:14: transition join -> busy in root: e_done from a connector never happens (only "
                           "states complete); move the transition's e_done to the state that leads to the connector");
  EXPECT_CONTAINS(message, "task.lua:15: transition join -> busy in root: 'e_after(2)' from a connector never happens");
  EXPECT_CONTAINS(message, "task.lua:16: transition root.plain.chld -> busy in root: unknown source, no node "
                           "'root.plain.chld'; the nodes of root.plain are root.plain.child");
  EXPECT_CONTAINS(message, "task.lua:17: transition busy -> join in root: has two time events; keep one");
  EXPECT_CONTAINS(message, "task.lua:18: transition busy ->  in root: needs both src and tgt");
}

TEST(Chart, NamesAreCheckedAsTheyAreAdded) {
  ChartBuilder b;
  b.addState("root", "a");
  EXPECT_EQ(cobra::test_support::messageOf([&] { b.addState("root", "a", StateSpec{{}, {}, {}, "x.lua:4"}); }),
            "x.lua:4: chart: root.a is defined twice; give each node of root its own name");
  EXPECT_CONTAINS(cobra::test_support::messageOf([&] { b.addState("root", "a.b"); }), "names are non-empty, without dots");
  EXPECT_EQ(cobra::test_support::messageOf([&] { b.addState("root.zz", "c"); }), "chart: no state 'root.zz' to add to");
  EXPECT_EQ(cobra::test_support::messageOf([&] { b.addState("root", "initial", StateSpec{{}, {}, {}, "x.lua:7"}); }),
            "x.lua:7: chart: root.initial is a state, but 'initial' names the initial connector; rename the state");
  EXPECT_CONTAINS(cobra::test_support::messageOf([&] { b.addConnector("root", "", "x.lua:8"); }),
                  "x.lua:8: chart: a connector in root is named ''");
  b.addConnector("root", "c");
  EXPECT_EQ(cobra::test_support::messageOf([&] { b.addState("root.c", "inside"); }),
            "chart: root.c.inside: a connector cannot contain nodes");
  ChartBuilder empty;
  EXPECT_CONTAINS(cobra::test_support::messageOf([&] { empty.build(); }), "root has no initial connector");
}

// --- property test -------------------------------------------------------------------------

/// A random well-formed chart: `count` states under random composite parents, every composite
/// with an initial transition, and random event-triggered transitions between any two states.
Chart randomChart(std::mt19937& rng, int count, int events, std::vector<std::string>& trace) {
  ChartBuilder b;
  std::vector<std::string> states{"root"};
  std::vector<int> children(1, 0);
  for (int i = 0; i < count; ++i) {
    const auto parent = std::uniform_int_distribution<std::size_t>(0, states.size() - 1)(rng);
    const std::string name = "s" + std::to_string(i);
    const std::string fqn = states[parent] + "." + name;
    StateSpec spec;
    spec.entry = [&trace, fqn] { trace.push_back("+" + fqn); };
    spec.exit = [&trace, fqn] { trace.push_back("-" + fqn); };
    b.addState(states[parent], name, std::move(spec));
    if (children[parent]++ == 0) b.addTransition(states[parent], trans("initial", name));
    states.push_back(fqn);
    children.push_back(0);
  }
  std::uniform_int_distribution<std::size_t> any(1, states.size() - 1);
  for (int i = 0; i < 3 * count; ++i) {
    TransitionSpec t = trans(states[any(rng)], states[any(rng)], {"e" + std::to_string(rng() % events)});
    t.pn = static_cast<int>(rng() % 3);
    b.addTransition("root", std::move(t));
  }
  return b.build();
}

// 300 seeded random charts (5..24 states) with 50 random events each: never a crash, always one
// active leaf with every ancestor active, and the same trace when replayed.
TEST(ChartProperty, RandomChartsKeepALeafConfigurationAndReplayIdentically) {
  std::mt19937 rng(20261122);
  for (int round = 0; round < 300; ++round) {
    const int count = 5 + static_cast<int>(rng() % 20);
    std::vector<std::string> first, second;
    const auto seed = rng();
    std::mt19937 build_rng(static_cast<std::mt19937::result_type>(seed));
    const Chart chart = randomChart(build_rng, count, 6, first);
    std::mt19937 replay_build(static_cast<std::mt19937::result_type>(seed));
    const Chart again = randomChart(replay_build, count, 6, second);
    Machine a(chart, {}), b(again, {});
    a.run();
    b.run();
    std::mt19937 events(static_cast<std::mt19937::result_type>(seed + 1));
    for (int i = 0; i < 50; ++i) {
      const std::string e = "e" + std::to_string(events() % 6);
      a.raise(e);
      b.raise(e);
      a.run();
      b.run();
      const std::string_view leaf = a.activeLeaf();
      ASSERT_FALSE(leaf.empty()) << "round " << round;
      const int index = chart.find(leaf);
      ASSERT_GE(index, 0);
      EXPECT_FALSE(chart.node(index).composite) << leaf;
      for (int n = index; n != 0; n = chart.node(n).parent) EXPECT_TRUE(a.isActive(chart.node(n).fqn)) << leaf;
    }
    EXPECT_EQ(first, second) << "round " << round;
  }
}

TEST(ChartRealTime, StepsOfALoadedChartAllocateNothing) {
  const Chart chart = figure32();
  Machine m(chart, [] { return std::chrono::nanoseconds(0); });
  m.run();
  const char* events[] = {"e_start", "e_stop", "e_error", "e_error_fixed", "e_unknown", "e_error", "e_fatal_error",
                          "e_reset"};
  EXPECT_EQ(cobra::test_support::allocationsDuring([&] {
              for (int round = 0; round < 100; ++round)
                for (const char* e : events) {
                  m.raise(e);
                  m.run();
                }
            }),
            0);
  EXPECT_EQ(m.activeLeaf(), "root.on.waiting");
}

}  // namespace
}  // namespace cobra::statechart
