// Unit tests of the threaded activities (activity.hpp). Only behaviour is asserted, never
// timing: waits are bounded polls on step counters.

#include <gtest/gtest.h>

#include "cobra/test_support/counting_new.hpp"
#include "cobra/test_support/test_support.hpp"

#include <atomic>
#include <chrono>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <thread>

#include "cobra/core/activity.hpp"
#include "cobra/core/component.hpp"

namespace cobra::core {
namespace {

using cobra::test_support::messageOf;
using cobra::test_support::waitUntil;

using namespace std::chrono_literals;

/// Counts updates and checks, from inside, facts only the activity thread can see.
class Probe : public Component {
 public:
  explicit Probe(std::string name = "Probe") : Component(std::move(name), Role::Calculation, "activity probe") {
    addEventPort(in);
  }
  InputPort<double> in{"in", "trigger data", "1"};
  std::atomic<bool> inside_update{false};
  std::atomic<int> not_activity_thread{0};
  std::atomic<bool> update_during_stop_hook{false};
  std::atomic<bool> throw_next{false};
  std::atomic<std::thread::id> last_thread{};
  std::atomic<bool> hold{false};  ///< while set, a step waits inside updateHook (a long search)

 protected:
  void updateHook() override {
    last_thread = std::this_thread::get_id();
    inside_update = true;
    while (hold.load()) std::this_thread::sleep_for(100us);
    if (!activity().isActivityThread()) ++not_activity_thread;
    double v = 0.0;
    (void)in.read(v);
    inside_update = false;
    if (throw_next.exchange(false)) throw std::runtime_error("sensor unplugged");
  }
  void stopHook() override {
    if (inside_update.load()) update_during_stop_hook = true;
  }
};

// --- PeriodicActivity -------------------------------------------------------------------------

TEST(PeriodicActivity, StepsTheComponentUntilStopped) {
  Probe p;
  p.setActivity(std::make_unique<PeriodicActivity>(1ms, 0, Scheduler::Other));
  auto& activity = dynamic_cast<PeriodicActivity&>(p.activity());
  EXPECT_FALSE(activity.hasRunningThread());
  ASSERT_TRUE(p.configure());
  ASSERT_TRUE(p.start());
  EXPECT_TRUE(activity.hasRunningThread());
  EXPECT_FALSE(activity.isActivityThread()) << "the test thread is not the activity thread";
  ASSERT_TRUE(waitUntil([&] { return p.updateCount() >= 5; }));
  EXPECT_GT(activity.stats().steps, 0U);
  ASSERT_TRUE(p.stop());
  EXPECT_FALSE(activity.hasRunningThread());
  EXPECT_EQ(p.not_activity_thread.load(), 0);
}

TEST(PeriodicActivity, StopJoinsTheThreadBeforeStopHook) {
  Probe p;
  p.setActivity(std::make_unique<PeriodicActivity>(200us, 0, Scheduler::Other));
  for (int round = 0; round < 20; ++round) {
    ASSERT_TRUE(p.configure());
    ASSERT_TRUE(p.start());
    const auto before = p.updateCount();
    ASSERT_TRUE(waitUntil([&] { return p.updateCount() > before; }));
    ASSERT_TRUE(p.stop());
    // Joined: no update is running or can start, and the counters agree.
    const auto count = p.updateCount();
    EXPECT_EQ(dynamic_cast<PeriodicActivity&>(p.activity()).stats().steps, count);
    EXPECT_FALSE(p.inside_update.load());
  }
  EXPECT_FALSE(p.update_during_stop_hook.load());
}

TEST(PeriodicActivity, IsActivityThreadHoldsFromTheVeryFirstStep) {
  // The first step runs as soon as the thread exists, possibly before start() returns; 100
  // start/stop cycles (each ends after the first update).
  Probe p;
  p.setActivity(std::make_unique<PeriodicActivity>(1ms, 0, Scheduler::Other));
  for (int round = 0; round < 100; ++round) {
    ASSERT_TRUE(p.configure());
    const auto before = p.updateCount();
    ASSERT_TRUE(p.start());
    ASSERT_TRUE(waitUntil([&] { return p.updateCount() > before; }));
    ASSERT_TRUE(p.stop());
  }
  EXPECT_EQ(p.not_activity_thread.load(), 0);
}

TEST(PeriodicActivity, FifoFallsBackToOtherWhenNotPermitted) {
  Probe p;
  p.setActivity(std::make_unique<PeriodicActivity>(1ms, 80, Scheduler::Fifo));
  auto& activity = dynamic_cast<PeriodicActivity&>(p.activity());
  EXPECT_EQ(activity.scheduler(), Scheduler::Fifo);
  EXPECT_EQ(activity.priority(), 80);
  ASSERT_TRUE(p.configure());
  ASSERT_TRUE(p.start());
  ASSERT_TRUE(waitUntil([&] { return p.updateCount() >= 2; }));
  const std::string text = activity.describe();
  EXPECT_CONTAINS(text, "periodic 1 ms, SCHED_FIFO priority 80");
  if (activity.effectiveScheduler() == Scheduler::Other) {
    EXPECT_CONTAINS(text, "(refused: running SCHED_OTHER)");
  } else {
    EXPECT_EQ(activity.effectiveScheduler(), Scheduler::Fifo);
    EXPECT_EQ(text.find("refused"), std::string::npos) << text;
  }
  ASSERT_TRUE(p.stop());
}

TEST(PeriodicActivity, DescribesPeriodAndScheduler) {
  EXPECT_EQ(PeriodicActivity(2ms, 0, Scheduler::Other).describe(), "periodic 2 ms, SCHED_OTHER");
  EXPECT_EQ(PeriodicActivity(1s, 0, Scheduler::Other).describe(), "periodic 1 s, SCHED_OTHER");
  EXPECT_EQ(PeriodicActivity(500us, 0, Scheduler::Other).describe(), "periodic 500 us, SCHED_OTHER");
  EXPECT_EQ(PeriodicActivity(1500ns, 0, Scheduler::Other).describe(), "periodic 1500 ns, SCHED_OTHER");
  EXPECT_EQ(PeriodicActivity(10ms, 80).describe(), "periodic 10 ms, SCHED_FIFO priority 80");
  EXPECT_EQ(PeriodicActivity(10ms, 0, Scheduler::Other).period(), 10ms);
}

TEST(PeriodicActivity, InvalidPeriodOrPriorityIsRefused) {
  EXPECT_CONTAINS(messageOf([] { PeriodicActivity a(0ns); }), "a periodic activity needs a period > 0 s, got 0 ns");
  EXPECT_CONTAINS(messageOf([] { PeriodicActivity a(-5ms, 10, Scheduler::Other); }), "needs a period > 0 s");
  EXPECT_CONTAINS(messageOf([] { PeriodicActivity a(1ms, 0, Scheduler::Fifo); }),
                  "SCHED_FIFO priority must be in 1..99, got 0");
  EXPECT_CONTAINS(messageOf([] { PeriodicActivity a(1ms, 100); }), "SCHED_FIFO priority must be in 1..99, got 100");
  EXPECT_CONTAINS(messageOf([] { EventActivity a(-1); }), "SCHED_FIFO priority must be in 1..99, got -1");
  EXPECT_EQ(messageOf([] { PeriodicActivity a(1ms, 0, Scheduler::Other); }), "(no error)");
}

TEST(PeriodicActivity, ComponentReadsSteadyClockTime) {
  Probe p;
  p.setActivity(std::make_unique<PeriodicActivity>(1ms, 0, Scheduler::Other));
  const auto a = p.now();
  const auto b = p.now();
  EXPECT_LE(a, b);
  EXPECT_GT(a.count(), 0);
}

// --- EventActivity ----------------------------------------------------------------------------

TEST(EventActivity, StepsOnlyWhenTriggered) {
  Probe p;
  OutputPort<double> out{"out", "", "1"};
  connect(out, p.in);
  p.setActivity(std::make_unique<EventActivity>(0, Scheduler::Other));
  auto& activity = dynamic_cast<EventActivity&>(p.activity());
  ASSERT_TRUE(p.configure());
  ASSERT_TRUE(p.start());
  // One write, one step: each write waits until its step happened, so no extra step can hide.
  for (std::uint64_t i = 1; i <= 5; ++i) {
    ASSERT_EQ(out.write(1.0 * static_cast<double>(i)), WriteStatus::Written);
    ASSERT_TRUE(waitUntil([&] { return p.updateCount() >= i; }));
    EXPECT_EQ(p.updateCount(), i);
  }
  activity.trigger();  // an explicit trigger is a step too
  ASSERT_TRUE(waitUntil([&] { return p.updateCount() >= 6; }));
  ASSERT_TRUE(p.stop());
  EXPECT_EQ(p.updateCount(), 6U);
  EXPECT_EQ(activity.stats().steps, 6U);
  EXPECT_EQ(p.not_activity_thread.load(), 0);
}

TEST(EventActivity, ItsHandOverAgesFromATriggerUntilTheStepTakingItEnds) {
  Probe p;
  p.setActivity(std::make_unique<EventActivity>(0, Scheduler::Other));
  Activity& activity = p.activity();
  const auto age = [&](std::chrono::nanoseconds at) { return activity.handoverAge(at); };
  activity.trigger();  // before the start: not the started activity's
  EXPECT_EQ(age(monotonicNow() + 1s), 0ns) << "not running: no age";
  ASSERT_TRUE(p.configure());
  ASSERT_TRUE(p.start());
  EXPECT_EQ(age(monotonicNow() + 1s), 0ns) << "nothing waits";
  p.hold = true;
  const auto before = monotonicNow();
  activity.trigger();
  const auto after = monotonicNow();
  ASSERT_TRUE(waitUntil([&] { return p.inside_update.load(); }));
  // Taken by the step under way, not answered until it ends: the age counts from the trigger.
  EXPECT_GE(age(after + 1s), 1s);
  EXPECT_LE(age(after + 1s), 1s + (after - before));
  activity.trigger();  // a second trigger while the first is served does not reset the age
  EXPECT_GE(age(after + 1s), 1s);
  p.hold = false;
  ASSERT_TRUE(waitUntil([&] { return p.updateCount() >= 2 && age(monotonicNow()) == 0ns; }))
      << "both answered: nothing waits";
  ASSERT_TRUE(p.stop());
  EXPECT_EQ(age(monotonicNow() + 1s), 0ns);
}

TEST(PeriodicActivity, ItsHandOverAgesFromItsLastStepsEnd) {
  Probe p;
  p.setActivity(std::make_unique<PeriodicActivity>(1ms, 0, Scheduler::Other));
  Activity& activity = p.activity();
  ASSERT_TRUE(p.configure());
  ASSERT_TRUE(p.start());
  ASSERT_TRUE(waitUntil([&] { return p.updateCount() >= 3; }));
  p.hold = true;  // a step that does not end
  ASSERT_TRUE(waitUntil([&] { return p.inside_update.load(); }));
  const auto held = monotonicNow();
  EXPECT_GE(activity.handoverAge(held + 1s), 1s) << "its last step ended before this one began";
  p.hold = false;
  ASSERT_TRUE(p.stop());
  EXPECT_EQ(activity.handoverAge(monotonicNow() + 1s), 0ns) << "stopped: no age";
}

TEST(EventActivity, TriggersRightAfterStartAreNotLost) {
  // A trigger that arrives while the thread is still starting must step it; 100 cycles.
  Probe p;
  OutputPort<double> out{"out", "", "1"};
  connect(out, p.in);
  p.setActivity(std::make_unique<EventActivity>(0, Scheduler::Other));
  for (int round = 0; round < 100; ++round) {
    ASSERT_TRUE(p.configure());
    const auto before = p.updateCount();
    ASSERT_TRUE(p.start());
    ASSERT_EQ(out.write(1.0), WriteStatus::Written);
    ASSERT_TRUE(waitUntil([&] { return p.updateCount() > before; })) << "round " << round;
    ASSERT_TRUE(p.stop());
  }
}

TEST(EventActivity, Describes) {
  EXPECT_EQ(EventActivity(0, Scheduler::Other).describe(), "event-driven, SCHED_OTHER");
  EXPECT_EQ(EventActivity(70).describe(), "event-driven, SCHED_FIFO priority 70");
  EXPECT_EQ(EventActivity(70).period(), 0ns);
  EXPECT_EQ(SlaveActivity().describe(), "slave");
}

TEST(EventActivity, AnUpdateExceptionOnTheThreadIsContainedAndRecoverable) {
  Probe p("Sensor");
  OutputPort<double> out{"out", "", "1"};
  InputPort<Event> events{"watch", "", ""};
  connect(out, p.in);
  connect(p.events(), events, ConnPolicy::buffer(8));
  p.setActivity(std::make_unique<EventActivity>(0, Scheduler::Other));
  ASSERT_TRUE(p.configure());
  ASSERT_TRUE(p.start());
  p.throw_next = true;
  ASSERT_EQ(out.write(1.0), WriteStatus::Written);
  Event e;
  ASSERT_TRUE(waitUntil([&] { return events.read(e) == FlowStatus::NewData; }));
  EXPECT_EQ(e.name.view().substr(0, 12), "e_exception@");
  EXPECT_EQ(e.source, "Sensor");
  EXPECT_EQ(p.state(), State::Exception);
  EXPECT_CONTAINS(p.lastError(), "updateHook threw: sensor unplugged");
  ASSERT_TRUE(p.recover());
  ASSERT_TRUE(p.configure());
  ASSERT_TRUE(p.start());
  const auto before = p.updateCount();
  ASSERT_EQ(out.write(2.0), WriteStatus::Written);
  ASSERT_TRUE(waitUntil([&] { return p.updateCount() > before; }));
  EXPECT_EQ(p.state(), State::Running);
  ASSERT_TRUE(p.stop());
}

TEST(EventActivity, ActivityCanBeSwappedWhileStopped) {
  Probe p;
  p.setActivity(std::make_unique<EventActivity>(0, Scheduler::Other));
  ASSERT_TRUE(p.configure());
  ASSERT_TRUE(p.start());
  EXPECT_CONTAINS(messageOf([&] { p.setActivity(std::make_unique<SlaveActivity>()); }), "stop it first");
  ASSERT_TRUE(p.stop());
  p.setActivity(std::make_unique<PeriodicActivity>(1ms, 0, Scheduler::Other));
  ASSERT_TRUE(p.start());
  const auto before = p.updateCount();
  ASSERT_TRUE(waitUntil([&] { return p.updateCount() > before; }));
  ASSERT_TRUE(p.stop());
}

// --- The thread's life ------------------------------------------------------------------------

TEST(ThreadActivity, AStopParksTheThreadAndTheNextStartStepsOnTheSameOne) {
  // A deployment switch stops and starts components: no thread is joined or created again.
  Probe p;
  p.setActivity(std::make_unique<EventActivity>(0, Scheduler::Other));
  ASSERT_TRUE(p.configure());
  std::thread::id first{};
  for (int round = 0; round < 20; ++round) {
    const auto before = p.updateCount();
    ASSERT_TRUE(p.start());
    p.activity().trigger();
    ASSERT_TRUE(waitUntil([&] { return p.updateCount() > before; })) << "round " << round;
    ASSERT_TRUE(p.stop());
    const auto stopped_at = p.updateCount();
    p.activity().trigger();  // parked: nothing steps
    std::this_thread::sleep_for(2ms);
    EXPECT_EQ(p.updateCount(), stopped_at) << "round " << round;
    if (round == 0) first = p.last_thread.load();
    EXPECT_EQ(p.last_thread.load(), first) << "round " << round;
  }
  EXPECT_NE(first, std::this_thread::get_id());
  EXPECT_EQ(p.not_activity_thread.load(), 0);
}

TEST(ThreadActivity, StartedFromARealTimeThreadItsThreadComesFromTheLauncherWithoutAllocatingThere) {
  startActivityLauncher();
  Probe periodic("Periodic");
  Probe event("Event");
  OutputPort<double> out{"out", "", "1"};
  connect(out, event.in);
  periodic.setActivity(std::make_unique<PeriodicActivity>(1ms, 0, Scheduler::Other));
  event.setActivity(std::make_unique<EventActivity>(0, Scheduler::Other));
  ASSERT_TRUE(periodic.configure());
  ASSERT_TRUE(event.configure());
  long allocations = -1;
  std::thread realtime([&] {
    markRealtimeThread(true);
    allocations = test_support::allocationsOnThisThreadDuring([&] {
      (void)periodic.start();
      (void)event.start();
      (void)out.write(1.0);
    });
  });
  realtime.join();
  EXPECT_EQ(allocations, 0) << "operator new calls on the real-time thread while it started two threaded activities";
  ASSERT_TRUE(periodic.isRunning());
  ASSERT_TRUE(event.isRunning());
  EXPECT_TRUE(waitUntil([&] { return periodic.updateCount() > 2 && event.updateCount() >= 1; }));
  // Stopped at once from the real-time thread as well, and started again from an ordinary one.
  std::thread stopper([&] {
    markRealtimeThread(true);
    EXPECT_TRUE(periodic.stop());
    EXPECT_TRUE(event.stop());
  });
  stopper.join();
  ASSERT_TRUE(periodic.start());
  const auto before = periodic.updateCount();
  EXPECT_TRUE(waitUntil([&] { return periodic.updateCount() > before; }));
  EXPECT_TRUE(periodic.stop());  // before the Probes are destroyed: a step must not meet a destructor
  EXPECT_EQ(periodic.not_activity_thread.load() + event.not_activity_thread.load(), 0);
}

TEST(ThreadActivity, AnActivityStoppedAndDestroyedBeforeTheLauncherRanIsSafe) {
  // Start, stop and destroy in a burst from a real-time thread: every stop returns once no step
  // can run, every destruction ends its thread, whatever the launcher's progress.
  startActivityLauncher();
  std::thread realtime([] {
    markRealtimeThread(true);
    for (int round = 0; round < 50; ++round) {
      Probe p;
      p.setActivity(std::make_unique<EventActivity>(0, Scheduler::Other));
      ASSERT_TRUE(p.configure());
      ASSERT_TRUE(p.start());
      if (round % 2 == 0) {
        ASSERT_TRUE(p.stop());
      }
    }
  });
  realtime.join();
}

}  // namespace
}  // namespace cobra::core
