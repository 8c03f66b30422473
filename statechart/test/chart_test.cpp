// Building charts: the thesis' Fig. 3.2 example, load-time errors and the no-allocation rule of
// a loaded chart's steps. The seeded random property test is property_test.cpp.
#include "cobra/statechart/chart.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "cobra/statechart/machine.hpp"
#include "cobra/test_support/counting_new.hpp"
#include "cobra/test_support/test_support.hpp"
#include "figure32.hpp"

namespace cobra::statechart {
namespace {

using test::figure32;
using test::trans;

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

TEST(Chart, LoadErrorsNameTheOriginThePathAndTheFix) {
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

/// Counts what the observer hears, without allocating.
struct Counter : Observer {
  int entered_count = 0, exited_count = 0, taken = 0, ignored = 0;
  void entered(std::string_view) override { ++entered_count; }
  void exited(std::string_view) override { ++exited_count; }
  void transitionTaken(const Chart::Transition&) override { ++taken; }
  void eventsIgnored(const StepEvents&) override { ++ignored; }
};

// Everything a step can do — guards, effects, connectors, doo, e_done, time events, the
// observer, unknown and dropped events, a full queue — allocates nothing once built.
TEST(ChartRealTime, EveryKindOfStepAllocatesNothing) {
  ChartBuilder b;
  int doo_calls = 0;
  StateSpec working;
  working.doo = [&doo_calls](bool restart) {
    doo_calls = restart ? 0 : doo_calls + 1;
    return doo_calls < 3 ? DooStatus::Busy : DooStatus::Done;
  };
  b.addState("root", "task");
  b.addState("root.task", "working", std::move(working));
  b.addState("root.task", "waiting");
  b.addState("root", "choose");
  b.addConnector("root", "split");
  b.addState("root", "left");
  b.addState("root", "right");
  b.addTransition("root", trans("initial", "task"));
  b.addTransition("root.task", trans("initial", "working"));
  b.addTransition("root.task", trans("working", "waiting", {"e_done"}));
  b.addTransition("root", trans("task", "choose", {"e_after(0.5)"}));
  TransitionSpec to_split = trans("choose", "split", {"e_go", "e_go2"});
  to_split.guard = [](const StepEvents& events) { return !events.contains("e_veto"); };
  to_split.effect = [&doo_calls](const StepEvents& events) { doo_calls += static_cast<int>(events.size()); };
  b.addTransition("root", std::move(to_split));
  b.addTransition("root", trans("split", "left", {"e_go"}));
  b.addTransition("root", trans("split", "right", {"e_go2"}));
  b.addTransition("root", trans("left", "task", {"e_back"}));
  b.addTransition("root", trans("right", "root.task.waiting", {"e_back"}));
  const Chart chart = b.build();
  std::chrono::nanoseconds now{0};
  Machine m(chart, [&now] { return now; }, 4);
  Counter counter;
  m.setObserver(&counter);
  // (events of one step, clock advance in ms, the leaf expected after run())
  struct Move {
    std::vector<const char*> events;
    int advance_ms;
    std::string_view leaf;
  };
  const std::vector<Move> script = {
      {{}, 0, "root.task.waiting"},                  // enter, doo busy twice then done, e_done
      {{}, 600, "root.choose"},                      // task's e_after(0.5)
      {{"e_go2", "e_veto"}, 0, "root.choose"},       // the guard says no: both dropped
      {{"e_go2"}, 0, "root.right"},                  // through the connector
      {{"e_back"}, 0, "root.task.waiting"},          // absolute target
      {{}, 600, "root.choose"},                      // the timer restarted on task's entry
      {{"e_go", "e_not_in_the_chart"}, 0, "root.left"},
      {{"e_back"}, 0, "root.task.waiting"},          // doo restarted
      {{"e_flood", "e_flood", "e_flood", "e_flood", "e_flood", "e_flood"}, 0, "root.task.waiting"},  // 2 refused
  };
  int wrong_leaves = 0;
  EXPECT_EQ(cobra::test_support::allocationsDuring([&] {
              for (int round = 0; round < 50; ++round) {
                for (const Move& move : script) {
                  for (const char* e : move.events) m.raise(e);
                  now += std::chrono::milliseconds(move.advance_ms);
                  m.run();
                  wrong_leaves += m.activeLeaf() == move.leaf ? 0 : 1;
                }
                m.reset();
              }
            }),
            0);
  EXPECT_EQ(wrong_leaves, 0);
  EXPECT_EQ(counter.taken, 50 * 13);  // segments a round: 11 transitions, two of them through the connector
  EXPECT_EQ(counter.exited_count, 50 * 10);
  EXPECT_GT(counter.ignored, 50 * 3);
}

}  // namespace
}  // namespace cobra::statechart
