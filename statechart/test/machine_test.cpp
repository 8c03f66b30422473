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

/// Records what the observer hears, as a supervisor publishing taskState would.
struct Recorder : Observer {
  std::vector<std::string> seen;
  void entered(std::string_view fqn) override { seen.push_back("entered " + std::string(fqn)); }
  void exited(std::string_view fqn) override { seen.push_back("exited " + std::string(fqn)); }
  void transitionTaken(const Chart::Transition& t) override { seen.push_back("taken " + t.text); }
  void eventsIgnored(const StepEvents& events) override {
    std::string names;
    for (std::size_t i = 0; i < events.size(); ++i) names += " " + std::string(events.name(i));
    seen.push_back("ignored" + names);
  }
};

TEST(Machine, TheObserverHearsEntriesExitsTransitionsAndDroppedEvents) {
  Traced t;
  for (const char* s : {"a", "b"}) t.state("root", s);
  t.state("root.b", "b1");
  t.trans("root", "initial", "a");
  t.trans("root.b", "initial", "b1");
  t.trans("root", "a", "b", {"e_go"});
  Running r(t);
  Recorder recorder;
  r.machine.setObserver(&recorder);
  r.machine.run();
  r.send({"e_nothing", "e_other"});
  r.send({"e_go"});
  EXPECT_EQ(recorder.seen, (std::vector<std::string>{"entered root", "taken root.initial -> root.a", "entered root.a",
                                                      "ignored e_done@root.a", "ignored e_nothing e_other",
                                                      "exited root.a", "taken root.a -> root.b.initial", "entered root.b",
                                                      "taken root.b.initial -> root.b.b1", "entered root.b.b1",
                                                      "ignored e_done@root.b.b1"}));
}

TEST(Machine, EachStepSaysWhatItDid) {
  Traced t;
  int doo_calls = 0;
  StateSpec working;
  working.doo = [&](bool) { return ++doo_calls < 2 ? DooStatus::Busy : DooStatus::Done; };
  t.builder.addState("root", "working", std::move(working));
  t.state("root", "done");
  t.trans("root", "initial", "working");
  t.trans("root", "working", "done", {"e_done"});
  Running r(t);
  EXPECT_EQ(r.machine.step(), StepResult::Entered);
  EXPECT_EQ(r.machine.raise("e_noise"), RaiseStatus::Queued);
  EXPECT_EQ(r.machine.step(), StepResult::EventsIgnored);
  EXPECT_EQ(r.machine.step(), StepResult::DooRan);  // busy
  EXPECT_EQ(r.machine.step(), StepResult::DooRan);  // done: its e_done is waiting
  EXPECT_EQ(r.machine.step(), StepResult::Transitioned);
  EXPECT_EQ(r.machine.step(), StepResult::EventsIgnored);  // e_done@root.done: nothing waits for it
  EXPECT_EQ(r.machine.step(), StepResult::Idle);
  EXPECT_EQ(r.machine.activeLeaf(), "root.done");

  Traced u;
  u.state("root", "a");
  TransitionSpec closed{"initial", "a", {}, 0, [](const StepEvents&) { return false; }, {}, {}};
  u.builder.addTransition("root", std::move(closed));
  Running blocked(u);
  EXPECT_EQ(blocked.machine.step(), StepResult::CannotEnter);
  EXPECT_FALSE(blocked.machine.run());
  EXPECT_FALSE(blocked.machine.entered());
}

TEST(Machine, TheFirstStepSeesEInitFsmAsRfsmsDoesAndResetStartsOver) {
  Traced t;
  for (const char* s : {"a", "b"}) t.state("root", s);
  std::vector<std::string> seen;
  TransitionSpec enter{"initial", "a", {"e_init_fsm"}, 0,
                       [&](const StepEvents& events) {
                         for (std::size_t i = 0; i < events.size(); ++i) seen.emplace_back(events.name(i));
                         return true;
                       },
                       {}, {}};
  t.builder.addTransition("root", std::move(enter));
  t.trans("root", "a", "b", {"e_go"});
  Running r(t);
  EXPECT_EQ(r.machine.queuedEvents(), 1U);
  r.machine.raise("e_early");
  EXPECT_TRUE(r.machine.run());
  EXPECT_EQ(r.machine.activeLeaf(), "root.a");
  EXPECT_EQ(seen, (std::vector<std::string>{"e_init_fsm", "e_early"}));
  EXPECT_EQ(r.send({"e_go"}), "root.b");
  t.take();
  r.machine.reset();  // as rfsm.reset: no exit functions, the next step enters again
  EXPECT_TRUE(t.take().empty());
  EXPECT_FALSE(r.machine.entered());
  EXPECT_EQ(r.machine.activeLeaf(), "");
  EXPECT_FALSE(r.machine.isActive("root"));
  EXPECT_TRUE(r.machine.run());
  EXPECT_EQ(r.machine.activeLeaf(), "root.a");
}

// rFSM's README: an error state whose initial connector dispatches on the event that entered it.
TEST(Machine, TransitionsFromInitialMayWaitForEventsOfTheEnteringStep) {
  Traced t;
  t.state("root", "ok");
  t.state("root", "err");
  t.state("root.err", "software");
  t.state("root.err", "hardware");
  t.trans("root", "initial", "ok");
  t.trans("root", "ok", "err", {"e_sw_err", "e_hw_err"});
  t.trans("root.err", "initial", "software", {"e_sw_err"});
  t.trans("root.err", "initial", "hardware", {"e_hw_err"});
  t.trans("root", "err", "ok", {"e_recovered"});
  Running r(t);
  r.machine.run();
  EXPECT_EQ(r.send({"e_hw_err"}), "root.err.hardware");
  EXPECT_EQ(r.send({"e_recovered"}), "root.ok");
  EXPECT_EQ(r.send({"e_sw_err"}), "root.err.software");
  EXPECT_EQ(r.send({"e_recovered"}), "root.ok");
  EXPECT_EQ(r.send({"e_recovered"}), "root.ok");
}

// rFSM's README: an initial transition to a relative path refines the default entry.
TEST(Machine, AnInitialTransitionToANestedStateEntersEveryAncestorAndSkipsTheirInitials) {
  Traced t;
  t.state("root", "operational");
  t.state("root.operational", "motors_on");
  t.state("root.operational.motors_on", "moving");
  t.state("root.operational.motors_on", "stopped");
  t.state("root", "off");
  t.trans("root.operational.motors_on", "initial", "stopped");
  t.trans("root.operational", "initial", "motors_on");
  t.trans("root", "initial", ".operational.motors_on.moving");
  t.trans("root", ".operational.motors_on.stopped", "off", {"e_off"});
  Running r(t);
  r.machine.run();
  EXPECT_EQ(r.machine.activeLeaf(), "root.operational.motors_on.moving");
  EXPECT_EQ(t.take(), (std::vector<std::string>{"effect initial->.operational.motors_on.moving", "entry root.operational",
                                                "entry root.operational.motors_on",
                                                "entry root.operational.motors_on.moving"}));
  EXPECT_EQ(r.send({"e_off"}), "root.operational.motors_on.moving");  // only from stopped
}

// The LCA of root.a -> root.a.y is root: a is exited and entered again, as in rFSM.
TEST(Machine, ATransitionFromACompositeToItsOwnChildLeavesAndReentersIt) {
  Traced t;
  t.state("root", "a");
  t.state("root.a", "x");
  t.state("root.a", "y");
  t.trans("root", "initial", "a");
  t.trans("root.a", "initial", "x");
  t.trans("root", "a", ".a.y", {"e_y"});
  Running r(t);
  r.machine.run();
  t.take();
  EXPECT_EQ(r.send({"e_y"}), "root.a.y");
  EXPECT_EQ(t.take(), (std::vector<std::string>{"exit root.a.x", "exit root.a", "effect a->.a.y", "entry root.a",
                                                "entry root.a.y"}));
}

TEST(Machine, EveryGuardOfASearchedStateIsAskedAndTheEffectSeesTheStepsEvents) {
  Traced t;
  for (const char* s : {"a", "high", "low"}) t.state("root", s);
  int low_guard_calls = 0;
  std::vector<std::string> effect_saw;
  t.trans("root", "initial", "a");
  TransitionSpec high{"a", "high", {"e_go"}, 5, {},
                      [&](const StepEvents& events) {
                        for (std::size_t i = 0; i < events.size(); ++i) effect_saw.emplace_back(events.name(i));
                      },
                      {}};
  TransitionSpec low{"a", "low", {"e_go"}, 1, [&](const StepEvents&) { return ++low_guard_calls > 0; }, {}, {}};
  t.builder.addTransition("root", std::move(high));
  t.builder.addTransition("root", std::move(low));
  Running r(t);
  r.machine.run();
  low_guard_calls = 0;  // the step that took e_done@root.a asked it too
  EXPECT_EQ(r.send({"e_go", "e_extra"}), "root.high");
  EXPECT_EQ(low_guard_calls, 1);  // asked, although a higher pn was enabled (rFSM collects every path)
  EXPECT_EQ(effect_saw, (std::vector<std::string>{"e_go", "e_extra"}));
}

TEST(Machine, AConnectorCycleIsNeverTakenAndDoesNotHang) {
  Traced t;
  t.state("root", "a");
  t.builder.addConnector("root", "c1");
  t.builder.addConnector("root", "c2");
  t.trans("root", "initial", "a");
  t.trans("root", "a", "c1", {"e_go"});
  t.trans("root", "c1", "c2");
  t.trans("root", "c2", "c1");
  Running r(t);
  r.machine.run();
  t.take();
  EXPECT_EQ(r.machine.raise("e_go"), RaiseStatus::Queued);
  EXPECT_EQ(r.machine.step(), StepResult::EventsIgnored);
  EXPECT_TRUE(t.take().empty());
}

TEST(Machine, ADooRestartsOnReentryAndAFailingDooEndsWithoutEDone) {
  Traced t;
  std::vector<bool> restarts;
  StateSpec working;
  working.doo = [&](bool restart) {
    restarts.push_back(restart);
    return DooStatus::Idle;
  };
  t.builder.addState("root", "working", std::move(working));
  t.state("root", "pause");
  StateSpec failing;
  failing.doo = [](bool) -> DooStatus { throw std::runtime_error("arm fault"); };
  t.builder.addState("root", "failing", std::move(failing));
  t.state("root", "after");
  t.trans("root", "initial", "working");
  t.trans("root", "working", "pause", {"e_pause"});
  t.trans("root", "pause", "working", {"e_resume"});
  t.trans("root", "working", "failing", {"e_fail"});
  t.trans("root", "failing", "after", {"e_done"});
  Running r(t);
  Failures failures;
  r.machine.setObserver(&failures);
  r.machine.run();
  r.machine.step();
  r.send({"e_pause"});
  r.send({"e_resume"});
  EXPECT_EQ(restarts, (std::vector<bool>{true, false, true}));
  EXPECT_EQ(r.send({"e_fail"}), "root.failing");
  EXPECT_TRUE(r.machine.run());
  EXPECT_EQ(r.machine.activeLeaf(), "root.failing");  // no e_done@root.failing
  EXPECT_EQ(failures.seen, std::vector<std::string>{"doo of root.failing: arm fault"});
}

TEST(Machine, EngineEventsAreNeverLostToAFullQueue) {
  Traced t;
  for (const char* s : {"a", "b", "c", "d"}) t.state("root", s);
  t.trans("root", "initial", "a");
  t.trans("root", "a", "b", {"e_go"});
  t.trans("root", "b", "c", {"e_done"});
  t.trans("root", "c", "d", {"e_after(1)"});
  const Chart chart = t.builder.build();
  std::chrono::nanoseconds now{0};
  Machine m(chart, [&] { return now; }, 2);
  m.run();
  EXPECT_EQ(m.raise("e_go"), RaiseStatus::Queued);
  EXPECT_EQ(m.step(), StepResult::Transitioned);  // to b: e_done@root.b is queued
  EXPECT_EQ(m.raise("e_noise1"), RaiseStatus::Queued);
  EXPECT_EQ(m.raise("e_noise2"), RaiseStatus::Queued);
  EXPECT_EQ(m.raise("e_noise3"), RaiseStatus::QueueFull);
  EXPECT_EQ(m.step(), StepResult::Transitioned);
  EXPECT_EQ(m.activeLeaf(), "root.c");
  m.run();
  now = std::chrono::seconds(2);
  EXPECT_EQ(m.raise("e_noise1"), RaiseStatus::Queued);
  EXPECT_EQ(m.raise("e_noise2"), RaiseStatus::Queued);
  EXPECT_EQ(m.step(), StepResult::Transitioned);  // the time event joined the full queue
  EXPECT_EQ(m.activeLeaf(), "root.d");
}

TEST(Machine, TimeEventsAreNamedAsRfsmNamesThemAndCanBeRaisedByName) {
  Traced t;
  for (const char* s : {"a", "b", "c", "d"}) t.state("root", s);
  t.trans("root", "initial", "a");
  t.trans("root", "a", "b", {"e_after(0.50)"});
  t.trans("root", "b", "c", {"e_after(2)"});
  t.trans("root", "c", "d", {"e_after(1e0)"});
  Running r(t);
  r.machine.run();
  for (const char* name : {"e_after(0.5)@root.a", "e_after(2)@root.b", "e_after(1.0)@root.c"})
    EXPECT_NE(r.chart.eventId(name), kUnknownEvent) << name;
  EXPECT_EQ(r.send({"e_after(0.5)@root.a"}), "root.b");  // rFSM: a time event is an event like any other
  EXPECT_EQ(r.send({"e_after(2)@root.b"}), "root.c");
}

TEST(Machine, EAtFiresOnceTheClockPassesAnAbsoluteTime) {
  Traced t;
  for (const char* s : {"a", "b"}) t.state("root", s);
  t.trans("root", "initial", "a");
  t.trans("root", "a", "b", {"e_at(100)"});
  Running r(t);
  t.now = 50s;
  r.machine.run();
  t.now = 100s;
  EXPECT_EQ(r.send({}), "root.a");
  t.now = 101s;
  EXPECT_EQ(r.send({}), "root.b");
}

TEST(Machine, AnOuterStatesTimerCountsFromItsOwnEntryAndWinsOverInnerTransitions) {
  Traced t;
  t.state("root", "task");
  t.state("root.task", "x");
  t.state("root.task", "y");
  t.state("root", "timeout");
  t.trans("root", "initial", "task");
  t.trans("root.task", "initial", "x");
  t.trans("root.task", "x", "y", {"e_after(1)"});
  t.trans("root.task", "y", "x", {"e_after(1)"});
  t.trans("root", "task", "timeout", {"e_after(2.5)"});
  Running r(t);
  r.machine.run();  // task entered at 0 s
  t.now = 1100ms;
  EXPECT_EQ(r.send({}), "root.task.y");
  t.now = 2200ms;
  EXPECT_EQ(r.send({}), "root.task.x");  // inner moves do not restart the outer timer
  t.now = 3300ms;                        // both x's (entered 2.2 s) and task's timers are due: outer wins
  EXPECT_EQ(r.send({}), "root.timeout");
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
