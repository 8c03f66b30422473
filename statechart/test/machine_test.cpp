// rFSM's semantics, rule by rule (chart.hpp and machine.hpp list them), on small charts.
#include "cobra/statechart/machine.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace cobra::statechart {
namespace {

using namespace std::chrono_literals;

/// Builds charts whose callbacks write to one trace: "entry root.a", "exit root.a", "effect a->b".
struct Traced {
  ChartBuilder builder;
  std::vector<std::string> trace;
  std::chrono::nanoseconds now{0};

  StateSpec spec(const std::string& fqn) {
    StateSpec s;
    s.entry = [this, fqn] { trace.push_back("entry " + fqn); };
    s.exit = [this, fqn] { trace.push_back("exit " + fqn); };
    return s;
  }
  void state(const std::string& parent, const std::string& name) { builder.addState(parent, name, spec(parent + "." + name)); }
  void trans(const std::string& scope, std::string src, std::string tgt, std::vector<std::string> events = {}, int pn = 0) {
    TransitionSpec t;
    const std::string label = "effect " + src + "->" + tgt;
    t.src = std::move(src);
    t.tgt = std::move(tgt);
    t.events = std::move(events);
    t.pn = pn;
    t.effect = [this, label](const StepEvents&) { trace.push_back(label); };
    builder.addTransition(scope, std::move(t));
  }
  std::vector<std::string> take() { return std::exchange(trace, {}); }
};

struct Running {
  Chart chart;
  Machine machine;
  explicit Running(Traced& t) : chart(t.builder.build()), machine(chart, [&t] { return t.now; }) {}
  std::string send(std::initializer_list<const char*> events) {
    for (const char* e : events) EXPECT_EQ(machine.raise(e), RaiseStatus::Queued);
    machine.run();
    return std::string(machine.activeLeaf());
  }
};

// Note: the step that enters the chart consumes the events queued before it, as rFSM's does.
TEST(Machine, EntersThroughInitialConnectorsDownToALeaf) {
  Traced t;
  t.state("root", "a");
  t.state("root.a", "b");
  t.trans("root", "initial", "a");
  t.trans("root.a", "initial", "b");
  Running r(t);
  EXPECT_EQ(r.machine.activeLeaf(), "");
  EXPECT_TRUE(r.machine.run());
  EXPECT_EQ(r.machine.activeLeaf(), "root.a.b");
  EXPECT_EQ(t.take(), (std::vector<std::string>{"effect initial->a", "entry root.a", "effect initial->b", "entry root.a.b"}));
  EXPECT_TRUE(r.machine.isActive("root.a"));
}

TEST(Machine, ExitsUpToTheCommonAncestorRunsTheEffectThenEntersDown) {
  Traced t;
  for (const char* s : {"a", "b"}) t.state("root", s);
  t.state("root.a", "a1");
  t.state("root.a.a1", "a11");
  t.state("root.b", "b1");
  t.trans("root", "initial", "a");
  t.trans("root.a", "initial", "a1");
  t.trans("root.a.a1", "initial", "a11");
  t.trans("root.b", "initial", "b1");
  t.trans("root", "root.a.a1.a11", "root.b", {"e_go"});
  Running r(t);
  r.machine.run();
  t.take();
  EXPECT_EQ(r.send({"e_go"}), "root.b.b1");
  EXPECT_EQ(t.take(), (std::vector<std::string>{"exit root.a.a1.a11", "exit root.a.a1", "exit root.a", "effect root.a.a1.a11->root.b",
                                                "entry root.b", "effect initial->b1", "entry root.b.b1"}));
}

TEST(Machine, OuterTransitionsWinOverInnerOnes) {
  Traced t;
  t.state("root", "outer");
  t.state("root", "elsewhere");
  t.state("root.outer", "inner");
  t.state("root.outer", "other");
  t.trans("root", "initial", "outer");
  t.trans("root.outer", "initial", "inner");
  t.trans("root.outer", "inner", "other", {"e_x"}, 100);  // inner, however high its pn
  t.trans("root", "outer", "elsewhere", {"e_x"});
  Running r(t);
  r.machine.run();
  EXPECT_EQ(r.send({"e_x"}), "root.elsewhere");
}

TEST(Machine, HigherPriorityNumbersGoFirstAndEqualOnesInTheOrderAdded) {
  Traced t;
  for (const char* s : {"a", "low", "high", "first", "second"}) t.state("root", s);
  t.trans("root", "initial", "a");
  t.trans("root", "a", "low", {"e_x"}, 1);
  t.trans("root", "a", "high", {"e_x"}, 5);
  t.trans("root", "a", "first", {"e_y"});
  t.trans("root", "a", "second", {"e_y"});
  {
    Running r(t);
    r.machine.run();
    EXPECT_EQ(r.send({"e_x"}), "root.high");
  }
  Traced u;
  for (const char* s : {"a", "first", "second"}) u.state("root", s);
  u.trans("root", "initial", "a");
  u.trans("root", "a", "first", {"e_y"});
  u.trans("root", "a", "second", {"e_y"});
  Running r(u);
  r.machine.run();
  EXPECT_EQ(r.send({"e_y"}), "root.first");
}

TEST(Machine, AnyListedEventTriggersAndNoEventsMeansAnyEvent) {
  Traced t;
  for (const char* s : {"a", "b", "c"}) t.state("root", s);
  t.trans("root", "initial", "a");
  t.trans("root", "a", "b", {"e_one", "e_two"});
  t.trans("root", "b", "c");  // any event
  Running r(t);
  r.machine.run();
  EXPECT_EQ(r.send({"e_two"}), "root.c");  // e_two -> b; then b's e_done@root.b is "any event" -> c
}

TEST(Machine, EventsOfAStepAreConsumedWhetherUsedOrNot) {
  Traced t;
  for (const char* s : {"a", "b", "c"}) t.state("root", s);
  t.trans("root", "initial", "a");
  t.trans("root", "a", "b", {"e_first"});
  t.trans("root", "b", "c", {"e_second"});
  Running r(t);
  r.machine.run();
  r.machine.raise("e_second");  // nothing waits for it in a: dropped with the step
  r.machine.raise("e_first");
  r.machine.run();
  EXPECT_EQ(r.machine.activeLeaf(), "root.b");  // e_second did not survive the step that took e_first
  EXPECT_EQ(r.machine.queuedEvents(), 0U);
}

TEST(Machine, EDoneIsRaisedPerStateAfterEntryOfALeafWithoutDoo) {
  Traced t;
  for (const char* s : {"a", "b", "c"}) t.state("root", s);
  t.trans("root", "initial", "a");
  t.trans("root", "a", "b", {"e_done"});  // means e_done@root.a
  t.trans("root", "b", "c", {"e_done@root.a"});  // b's own e_done@root.b does not match
  Running r(t);
  EXPECT_TRUE(r.machine.run());
  EXPECT_EQ(r.machine.activeLeaf(), "root.b");
  EXPECT_NE(r.chart.eventId("e_done@root.a"), kUnknownEvent);
}

TEST(Machine, DooIsResumedUntilDoneThenRaisesEDoneAndIdleStopsARun) {
  Traced t;
  int calls = 0, restarts = 0;
  StateSpec working;
  working.doo = [&](bool restart) {
    restarts += restart ? 1 : 0;
    return ++calls < 3 ? DooStatus::Busy : DooStatus::Done;
  };
  t.builder.addState("root", "working", std::move(working));
  int idle_calls = 0;
  StateSpec waiting;
  waiting.doo = [&](bool) {
    ++idle_calls;
    return DooStatus::Idle;
  };
  t.builder.addState("root", "waiting", std::move(waiting));
  t.trans("root", "initial", "working");
  t.trans("root", "working", "waiting", {"e_done"});
  Running r(t);
  EXPECT_TRUE(r.machine.run());
  EXPECT_EQ(calls, 3);
  EXPECT_EQ(restarts, 1);
  EXPECT_EQ(r.machine.activeLeaf(), "root.waiting");
  EXPECT_EQ(idle_calls, 1);  // idle: run returns
  EXPECT_EQ(r.machine.step(), StepResult::Idle);
  EXPECT_EQ(idle_calls, 2);  // each later step resumes it
}

TEST(Machine, ConnectorsChainSegmentsAndAPathNeedsEverySegmentEnabled) {
  Traced t;
  for (const char* s : {"a", "left", "right"}) t.state("root", s);
  t.builder.addConnector("root", "split");
  bool go_left = false;
  t.trans("root", "initial", "a");
  t.trans("root", "a", "split", {"e_go"});
  TransitionSpec left{"split", "left", {}, 0, [&](const StepEvents&) { return go_left; }, {}, {}};
  t.builder.addTransition("root", std::move(left));
  t.trans("root", "split", "right", {"e_right"});
  Running r(t);
  r.machine.run();
  EXPECT_EQ(r.send({"e_go"}), "root.a");  // no segment after the connector is enabled: not taken
  go_left = true;
  EXPECT_EQ(r.send({"e_go"}), "root.left");
}

TEST(Machine, RelativeLocalAndAbsolutePathsResolveAsInRfsm) {
  Traced t;
  t.state("root", "a");
  t.state("root.a", "x");
  t.state("root.a", "y");
  t.state("root", "b");
  t.trans("root", "initial", "a");
  t.trans("root.a", "initial", "x");
  t.trans("root.a", "x", "y", {"e_local"});      // names of the scope
  t.trans("root", ".a.y", "b", {"e_relative"});  // leading dot: below the scope
  t.trans("root.a", "root.b", "root.a.x", {"e_absolute"});
  Running r(t);
  r.machine.run();
  EXPECT_EQ(r.send({"e_local"}), "root.a.y");
  EXPECT_EQ(r.send({"e_relative"}), "root.b");
  EXPECT_EQ(r.send({"e_absolute"}), "root.a.x");
}

TEST(Machine, TimeEventsFireOnTheInjectedClockAfterEntryOfTheirSource) {
  Traced t;
  for (const char* s : {"a", "b"}) t.state("root", s);
  t.trans("root", "initial", "a");
  t.trans("root", "a", "b", {"e_after(0.5)"});
  t.trans("root", "b", "a", {"e_back"});
  Running r(t);
  t.now = 1s;
  r.machine.run();  // entered at t = 1 s
  t.now = 1s + 500ms;
  EXPECT_EQ(r.send({}), "root.a");  // not yet: strictly after 0.5 s
  t.now = 1s + 501ms;
  EXPECT_EQ(r.send({}), "root.b");
  EXPECT_EQ(r.send({"e_back"}), "root.a");  // re-entry restarts the timer
  t.now = 2s;
  EXPECT_EQ(r.send({}), "root.a");
  t.now = 3s;
  EXPECT_EQ(r.send({}), "root.b");
}

TEST(Machine, SelfTransitionsExitAndReenter) {
  Traced t;
  t.state("root", "a");
  t.trans("root", "initial", "a");
  t.trans("root", "a", "a", {"e_again"});
  Running r(t);
  r.machine.run();
  t.take();
  r.send({"e_again"});
  EXPECT_EQ(t.take(), (std::vector<std::string>{"exit root.a", "effect a->a", "entry root.a"}));
}

TEST(Machine, GuardsSeeTheStepsEventsAndAreAskedBeforeTheEvents) {
  Traced t;
  for (const char* s : {"a", "b"}) t.state("root", s);
  std::vector<std::string> seen;
  t.trans("root", "initial", "a");
  TransitionSpec guarded{"a", "b", {"e_go"}, 0,
                         [&](const StepEvents& events) {
                           for (std::size_t i = 0; i < events.size(); ++i) seen.emplace_back(events.name(i));
                           return events.contains("e_key");
                         },
                         {}, {}};
  t.builder.addTransition("root", std::move(guarded));
  Running r(t);
  r.machine.run();
  seen.clear();
  EXPECT_EQ(r.send({"e_unrelated"}), "root.a");
  EXPECT_EQ(seen, std::vector<std::string>{"e_unrelated"});  // the guard ran although e_go was not there
  EXPECT_EQ(r.send({"e_go"}), "root.a");
  EXPECT_EQ(r.send({"e_go", "e_key"}), "root.b");
}

/// Records callback failures.
struct Failures : Observer {
  std::vector<std::string> seen;
  void callbackFailed(std::string_view callback, std::string_view element, std::string_view what) override {
    seen.push_back(std::string(callback) + " of " + std::string(element) + ": " + std::string(what));
  }
};

TEST(Machine, AThrowingCallbackIsReportedAndTheStepGoesOn) {
  Traced t;
  StateSpec broken;
  broken.entry = [] { throw std::runtime_error("sensor offline"); };
  t.builder.addState("root", "a", std::move(broken));
  t.state("root", "b");
  t.trans("root", "initial", "a");
  t.trans("root", "a", "b", {"e_done"});
  Running r(t);
  Failures failures;
  r.machine.setObserver(&failures);
  EXPECT_TRUE(r.machine.run());
  EXPECT_EQ(r.machine.activeLeaf(), "root.b");
  EXPECT_EQ(failures.seen, std::vector<std::string>{"entry of root.a: sensor offline"});
}

TEST(Machine, RaiseRefusesOverlongNamesAndAFullQueue) {
  Traced t;
  t.state("root", "a");
  t.trans("root", "initial", "a");
  const Chart chart = t.builder.build();
  Machine m(chart, {}, 2);
  EXPECT_EQ(m.raise(std::string(Machine::kMaxEventName + 1, 'e')), RaiseStatus::NameTooLong);
  EXPECT_EQ(m.raise("e_1"), RaiseStatus::Queued);
  EXPECT_EQ(m.raise("e_2"), RaiseStatus::Queued);
  EXPECT_EQ(m.raise("e_3"), RaiseStatus::QueueFull);
}

}  // namespace
}  // namespace cobra::statechart
