// Unit tests of the real-time executor (realtime_executor.hpp): the lockstep schedule on the wall
// clock (the same trace as the lockstep clock), work between ticks, property changes from other
// threads, deadline misses and their policy, the duration histogram against a sorted reference,
// no allocation on the executor's thread in steady state, and the errors of bad options.

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <random>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include "cobra/core/component.hpp"
#include "cobra/core/lockstep_clock.hpp"
#include "cobra/core/port.hpp"
#include "cobra/core/property.hpp"
#include "cobra/core/realtime_executor.hpp"
#include "cobra/test_support/counting_new.hpp"
#include "cobra/test_support/test_support.hpp"

namespace cobra::core {
namespace {

using namespace std::chrono_literals;

/// Writes 1, 2, 3, ... every step; every 5th sample also goes to an event port.
class Producer : public Component {
 public:
  Producer() : Component("Producer", Role::Calculation, "counts") {
    addPort(out);
    addPort(pulse);
  }
  OutputPort<double> out{"out", "the count", "1"};
  OutputPort<double> pulse{"pulse", "every 5th count", "1"};

 protected:
  void updateHook() override {
    ++count_;
    out.write(count_);
    if (static_cast<long>(count_) % 5 == 0) pulse.write(count_);
  }

 private:
  double count_ = 0.0;
};

/// Records (time, value read) into a preallocated trace; a property scales what it records.
class Recorder : public Component {
 public:
  explicit Recorder(std::string name, bool event_port = false) : Component(std::move(name), Role::Calculation, "records") {
    if (event_port) addEventPort(in);
    else addPort(in);
    addProperty(gain);
    trace.reserve(100000);
  }
  InputPort<double> in{"in", "a count", "1"};
  Property<double> gain{"gain", 1.0, "1", "scale of what is recorded"};
  struct Sample {
    std::int64_t t;
    double value;
    bool operator==(const Sample&) const = default;
  };
  std::vector<Sample> trace;
  std::atomic<long> steps{0};
  /// Allocations made by the stepping thread so far (counting_new's per-thread counter).
  std::atomic<long> thread_allocations{0};
  /// When > 0, each step sleeps this long (a step that overruns its period).
  std::atomic<std::int64_t> stall_ns{0};

 protected:
  void updateHook() override {
    double v = 0.0;
    if (in.read(v) != FlowStatus::NoData && trace.size() < trace.capacity()) trace.push_back({now().count(), v * gain.get()});
    if (const auto stall = stall_ns.load(); stall > 0) std::this_thread::sleep_for(std::chrono::nanoseconds(stall));
    thread_allocations.store(test_support::threadNewCalls());
    steps.fetch_add(1);
  }
};

/// The same little deployment on a clock: a producer every `base` (1 ms unless given), a recorder of
/// its count every 2 `base` and an event-driven recorder of its pulses.
struct Rig {
  LockstepClock clock;
  Producer producer;
  Recorder slow{"Slow"}, reactor{"Reactor", true};
  explicit Rig(std::chrono::nanoseconds base = 1ms) {
    connect(producer.out, slow.in);
    connect(producer.pulse, reactor.in, ConnPolicy::buffer(4));
    clock.add(producer, base);
    clock.add(slow, 2 * base);
    clock.add(reactor, 0ns);
    for (Component* c : {static_cast<Component*>(&producer), static_cast<Component*>(&slow), static_cast<Component*>(&reactor)}) {
      EXPECT_TRUE(c->configure());
      EXPECT_TRUE(c->start());
    }
  }
  ~Rig() {
    for (Component* c : {static_cast<Component*>(&reactor), static_cast<Component*>(&slow), static_cast<Component*>(&producer)})
      if (c->isRunning()) (void)c->stop();
  }
};

ExecutorOptions quickOptions() {
  ExecutorOptions o;
  o.period = 1ms;
  o.lock_memory = false;  // a unit test does not lock the test runner's memory
  return o;
}

/// Waits (bounded) until `done` holds; false when the bound passed.
template <class F>
bool eventually(F&& done, std::chrono::seconds bound = 20s) {
  const auto end = std::chrono::steady_clock::now() + bound;
  while (!done()) {
    if (std::chrono::steady_clock::now() > end) return false;
    std::this_thread::sleep_for(1ms);
  }
  return true;
}

TEST(RealtimeExecutor, RunsTheLockstepScheduleOnTheWallClock) {
  Rig lockstep;
  lockstep.clock.advance(300ms);
  ASSERT_EQ(lockstep.slow.trace.size(), 150u);

  Rig wall;
  RealtimeExecutor executor(wall.clock, quickOptions());
  executor.start();
  ASSERT_TRUE(eventually([&] { return wall.slow.steps.load() >= 160; }));  // past the lockstep run's 300 ms
  executor.stop();
  // Every sample the recorders read, at the instant they read it, is the lockstep run's.
  ASSERT_GE(wall.slow.trace.size(), 150u);
  ASSERT_GE(wall.reactor.trace.size(), lockstep.reactor.trace.size());
  wall.slow.trace.resize(150);
  wall.reactor.trace.resize(lockstep.reactor.trace.size());
  EXPECT_EQ(wall.slow.trace, lockstep.slow.trace);
  EXPECT_EQ(wall.reactor.trace, lockstep.reactor.trace);
  EXPECT_GE(executor.ticks(), 300u);
  EXPECT_GE(executor.wakeLatency().count(), executor.ticks()) << "one wake-up latency per tick";
}

TEST(RealtimeExecutor, ThreadsBesideTheClockReadTheSameRunTime) {
  Rig rig;
  RealtimeExecutor executor(rig.clock, quickOptions());
  executor.start();
  ASSERT_TRUE(eventually([&] { return rig.slow.steps.load() >= 50; }));
  // An activity with no clock of its own (a thread beside the executor) reads run time too.
  SlaveActivity beside;
  const auto clock_now = rig.clock.now();
  const auto beside_now = beside.now();
  executor.stop();
  EXPECT_LT(std::chrono::abs(beside_now - clock_now), 50ms)
      << "run time beside the clock " << beside_now.count() << " ns, on it " << clock_now.count() << " ns";
}

TEST(RealtimeExecutor, WorkBetweenTicksRunsOnItsThreadAndRethrows) {
  Rig rig;
  RealtimeExecutor executor(rig.clock, quickOptions());
  executor.start();
  ASSERT_TRUE(eventually([&] { return rig.slow.steps.load() >= 5; }));
  std::thread::id where;
  long steps_before = 0, steps_after = 0;
  executor.runBetweenTicks([&] {
    where = std::this_thread::get_id();
    steps_before = rig.slow.steps.load();
    std::this_thread::sleep_for(5ms);  // nothing steps meanwhile
    steps_after = rig.slow.steps.load();
  });
  EXPECT_EQ(where, rig.clock.steppingThread());
  EXPECT_NE(where, std::this_thread::get_id());
  EXPECT_EQ(steps_before, steps_after);
  EXPECT_THROW(executor.runBetweenTicks([] { throw Error("from the work"); }), Error);
  EXPECT_TRUE(executor.running()) << "an error of the work is the caller's, not the executor's";
  executor.stop();
  bool ran = false;
  executor.runBetweenTicks([&] { ran = true; });
  EXPECT_TRUE(ran) << "once stopped, work runs at once in the caller";
}

TEST(RealtimeExecutor, APropertySetFromAnotherThreadTakesEffectBetweenSteps) {
  Rig rig;
  RealtimeExecutor executor(rig.clock, quickOptions());
  executor.start();
  ASSERT_TRUE(eventually([&] { return rig.slow.steps.load() >= 5; }));
  EXPECT_TRUE(rig.slow.activity().hasRunningThread()) << "the executor steps it from another thread";
  rig.slow.gain.set(-1.0);  // queued for the component's next step, which the executor runs
  const auto set_at = rig.slow.steps.load();
  ASSERT_TRUE(eventually([&] { return rig.slow.steps.load() >= set_at + 5; }));
  executor.stop();
  EXPECT_LT(rig.slow.trace.back().value, 0.0);
}

TEST(RealtimeExecutor, DeadlineMissesAreCountedEmittedAndEndInASafeStop) {
  // A 20 ms tick: three consecutive misses before the stall would take the machine stalling the
  // thread for 60 ms (with a 1 ms tick, one 4 ms preemption of a sanitizer build on a busy CI
  // machine asked for the safe stop before the stall began).
  constexpr auto base = 20ms;
  Rig rig(base);
  ExecutorOptions o = quickOptions();
  o.period = base;
  o.policy.emit_event = true;
  o.policy.safe_stop_after = 3;
  std::vector<std::string> events;
  events.reserve(8);
  o.on_event = [&](const char* e) { events.emplace_back(e); };
  RealtimeExecutor executor(rig.clock, o);
  executor.start();
  ASSERT_TRUE(eventually([&] { return rig.slow.steps.load() >= 5; }));
  EXPECT_FALSE(executor.safeStopAsked());
  rig.slow.stall_ns.store(std::chrono::nanoseconds(5 * base).count());  // every 40 ms step takes 100 ms
  ASSERT_TRUE(eventually([&] { return executor.safeStopAsked(); }));
  executor.stop();
  EXPECT_GE(executor.deadlineMisses(), 3u);
  EXPECT_GE(executor.worstConsecutiveMisses(), 3u);
  ASSERT_GE(events.size(), 2u);
  EXPECT_EQ(events.front(), "e_deadline_missed");
  EXPECT_NE(std::find(events.begin(), events.end(), "e_deadline_safe_stop"), events.end());
  EXPECT_GE(executor.tickCompute().max(), std::chrono::nanoseconds(5 * base).count());
  const auto timings = executor.componentTimings();
  ASSERT_EQ(timings.size(), 3u);
  EXPECT_EQ(timings[1].component, "Slow");
  EXPECT_GE(timings[1].compute.worst, 0.1);
  EXPECT_LT(timings[0].compute.worst, timings[1].compute.worst);
}

TEST(RealtimeExecutor, AMissEventAfterALongStallIsStampedWithTheRunTimeTheClockResumesAt) {
  // A stall far longer than max_catch_up_ticks: the executor slips its deadlines and the run's
  // epoch. The miss event is emitted after the slip, so run time read beside the clock (what an
  // event's stamp is) agrees with the clock's time within the catch-up bound, not the stall. Every
  // miss event is checked (the machine may add short misses of its own, caught up, not slipped).
  Rig rig;
  ExecutorOptions o = quickOptions();
  o.max_catch_up_ticks = 5;
  o.policy.emit_event = true;
  constexpr std::size_t kMost = 64;
  std::array<std::int64_t, kMost> clock_at{}, beside_at{};
  std::atomic<std::size_t> seen{0};
  o.on_event = [&](const char* e) {  // on the executor's thread, after the tick's advance
    const std::size_t i = seen.load();
    if (std::string_view(e) != "e_deadline_missed" || i >= kMost) return;
    clock_at[i] = rig.clock.now().count();
    beside_at[i] = SlaveActivity().now().count();
    seen.store(i + 1);
  };
  RealtimeExecutor executor(rig.clock, o);
  executor.start();
  ASSERT_TRUE(eventually([&] { return rig.slow.steps.load() >= 5; }));
  rig.slow.stall_ns.store(std::chrono::nanoseconds(200ms).count());
  ASSERT_TRUE(eventually([&] { return executor.slipped() >= 150ms; }));
  rig.slow.stall_ns.store(0);
  const long steps = rig.slow.steps.load();
  ASSERT_TRUE(eventually([&] { return rig.slow.steps.load() >= steps + 5; }));
  executor.stop();
  ASSERT_GE(seen.load(), 1u);
  for (std::size_t i = 0; i < seen.load(); ++i)
    EXPECT_LT(std::abs(beside_at[i] - clock_at[i]), std::chrono::nanoseconds(10ms).count())
        << "miss " << i << ": run time beside the clock " << beside_at[i] << " ns, on it " << clock_at[i] << " ns";
}

TEST(RealtimeExecutor, AnOwnPaceHandOverOlderThanItsBoundIsEmittedOncePerEpisode) {
  Rig rig;
  // A searcher on a thread of its own beside the executor, answering the producer's pulses (every
  // 5 ms); while each answer takes 150 ms, the pulses wait longer than its 50 ms bound. (The bound
  // is far above what a busy machine may keep a SCHED_OTHER thread waiting, so that no episode
  // comes from the machine: a sanitizer build on CI's two cores, other tests beside it.)
  Recorder searcher{"Searcher", true};
  connect(rig.producer.pulse, searcher.in, ConnPolicy::buffer(4));
  searcher.setActivity(std::make_unique<EventActivity>(1, Scheduler::Other));
  ASSERT_TRUE(searcher.configure());
  ASSERT_TRUE(searcher.start());
  ExecutorOptions o = quickOptions();
  std::vector<std::string> events;
  events.reserve(64);
  std::atomic<int> emitted{0};
  o.on_event = [&](const char* e) {
    if (events.size() < events.capacity()) events.emplace_back(e);
    emitted.fetch_add(1);
  };
  RealtimeExecutor executor(rig.clock, o);
  executor.watchHandover(searcher, 50ms);
  executor.start();
  ASSERT_TRUE(eventually([&] { return searcher.steps.load() >= 20; }));
  EXPECT_EQ(emitted.load(), 0) << "answered within a few ms: never stale";
  searcher.stall_ns.store(std::chrono::nanoseconds(150ms).count());
  ASSERT_TRUE(eventually([&] { return emitted.load() >= 1; }));
  searcher.stall_ns.store(0);
  const long steps = searcher.steps.load();
  ASSERT_TRUE(eventually([&] { return searcher.steps.load() >= steps + 20; }));  // answering promptly again
  const int episodes = emitted.load();
  const long later = searcher.steps.load();
  ASSERT_TRUE(eventually([&] { return searcher.steps.load() >= later + 20; }));
  executor.stop();
  (void)searcher.stop();
  EXPECT_EQ(emitted.load(), episodes) << "no episode while it answered within its bound";
  ASSERT_FALSE(events.empty());
  EXPECT_EQ(events.front(), "e_handover_stale_Searcher");
  const auto figures = executor.handoverFigures();
  ASSERT_EQ(figures.size(), 1u);
  EXPECT_EQ(figures[0].component, "Searcher");
  EXPECT_DOUBLE_EQ(figures[0].max_age, 0.05);
  EXPECT_GE(figures[0].worst_age, 0.05);
  EXPECT_EQ(figures[0].stale, static_cast<std::uint64_t>(episodes));
  // Once stopped its hand-over has no age: a component stopped by a switch is not stale.
  EXPECT_EQ(searcher.activity().handoverAge(std::chrono::nanoseconds(std::chrono::steady_clock::now().time_since_epoch())), 0ns);
}

TEST(RealtimeExecutor, AWatchNeedsAPositiveBoundAndTheExecutorsThreadWhileItRuns) {
  Rig rig;
  RealtimeExecutor executor(rig.clock, quickOptions());
  EXPECT_EQ(test_support::messageOf([&] { executor.watchHandover(rig.reactor, 0ns); }),
            "real-time executor: watching the hand-over of 'Reactor': max_age must be > 0 s, got 0 ns");
  executor.watchHandover(rig.reactor, 1s);
  executor.watchHandover(rig.reactor, 2s);  // watched again: its new bound
  ASSERT_EQ(executor.handoverFigures().size(), 1u);
  EXPECT_DOUBLE_EQ(executor.handoverFigures()[0].max_age, 2.0);
  executor.start();
  EXPECT_CONTAINS(test_support::messageOf([&] { executor.watchHandover(rig.slow, 1s); }),
                  "called from another thread while the executor runs; watch before start or between ticks");
  executor.runBetweenTicks([&] { executor.watchHandover(rig.slow, 1s); });  // a switch, between ticks
  executor.stop();
  EXPECT_EQ(executor.handoverFigures().size(), 2u);
}

TEST(RealtimeExecutor, TicksAllocateNothingOnTheExecutorThread) {
  Rig rig;
  RealtimeExecutor executor(rig.clock, quickOptions());
  executor.watchHandover(rig.reactor, 1s);  // the hand-over check runs every tick too
  executor.start();
  ASSERT_TRUE(eventually([&] { return rig.slow.steps.load() >= 20; }));  // warmed up
  const long before = rig.slow.thread_allocations.load();
  const long steps = rig.slow.steps.load();
  ASSERT_TRUE(eventually([&] { return rig.slow.steps.load() >= steps + 200; }));
  const long after = rig.slow.thread_allocations.load();
  executor.stop();
  EXPECT_EQ(after - before, 0) << "operator new calls on the executor's thread over 200 steps of 'Slow'";
}

TEST(RealtimeExecutor, TheCounterOfTheExecutorThreadCanSeeAnAllocation) {
  // Guards the test above against a counter that cannot fail: the same thread, allocating.
  Rig rig;
  RealtimeExecutor executor(rig.clock, quickOptions());
  executor.start();
  ASSERT_TRUE(eventually([&] { return rig.slow.steps.load() >= 5; }));
  const long before = rig.slow.thread_allocations.load();
  static std::vector<int>* volatile escaped = nullptr;
  executor.runBetweenTicks([] {
    escaped = new std::vector<int>(10);
    delete escaped;
  });
  const long steps = rig.slow.steps.load();
  ASSERT_TRUE(eventually([&] { return rig.slow.steps.load() >= steps + 2; }));
  executor.stop();
  EXPECT_GE(rig.slow.thread_allocations.load() - before, 2);
}

TEST(RealtimeExecutor, AComponentPeriodThatIsNoMultipleOfTheTickIsRefused) {
  LockstepClock clock;
  Recorder odd("Odd");
  clock.add(odd, 1500us);
  RealtimeExecutor executor(clock, quickOptions());
  const std::string message = test_support::messageOf([&] { executor.start(); });
  EXPECT_EQ(message, "real-time executor: component 'Odd' has period 1500 us, not a multiple of the executor's period 1 ms");
  EXPECT_FALSE(executor.running());
}

TEST(RealtimeExecutor, BadOptionsAreRefusedWithTheirReason) {
  LockstepClock clock;
  ExecutorOptions o = quickOptions();
  o.period = 0ns;
  EXPECT_EQ(test_support::messageOf([&] { RealtimeExecutor e(clock, o); }),
            "real-time executor: the period must be > 0 s, got 0 ns");
  o = quickOptions();
  o.priority = 100;
  EXPECT_EQ(test_support::messageOf([&] { RealtimeExecutor e(clock, o); }),
            "real-time executor: SCHED_FIFO priority must be in 1..99, got 100");
  o = quickOptions();
  o.cpu = -2;
  EXPECT_EQ(test_support::messageOf([&] { RealtimeExecutor e(clock, o); }),
            "real-time executor: cpu must be -1 (any) or a CPU number, got -2");
}

TEST(DurationHistogram, QuantilesAgreeWithASortedReferenceWithin3Percent) {
  std::mt19937_64 random(20261128);  // seeded: 10 draws of 20,000 log-uniform durations
  for (int draw = 0; draw < 10; ++draw) {
    DurationHistogram h;
    std::vector<std::int64_t> reference;
    std::uniform_real_distribution<double> exponent(1.0, 9.0);  // 10 ns .. 1 s
    for (int i = 0; i < 20000; ++i) {
      const auto ns = static_cast<std::int64_t>(std::pow(10.0, exponent(random)));
      h.add(ns);
      reference.push_back(ns);
    }
    std::sort(reference.begin(), reference.end());
    for (const double q : {0.5, 0.9, 0.99, 0.999}) {
      const auto rank = static_cast<std::size_t>(std::ceil(q * static_cast<double>(reference.size()))) - 1;
      const double exact = static_cast<double>(reference[rank]);
      EXPECT_GE(static_cast<double>(h.quantile(q)), exact) << "q " << q << ", draw " << draw;
      EXPECT_LE(static_cast<double>(h.quantile(q)), exact * 1.032) << "q " << q << ", draw " << draw;
    }
    EXPECT_EQ(h.max(), reference.back());
    EXPECT_EQ(h.count(), reference.size());
  }
  DurationHistogram empty;
  EXPECT_EQ(empty.quantile(0.5), 0);
  const DurationFigures f = figuresOf(empty);
  EXPECT_EQ(f.count, 0u);
}

}  // namespace
}  // namespace cobra::core
