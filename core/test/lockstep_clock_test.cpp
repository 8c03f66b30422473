// Unit tests of the lockstep simulation clock (lockstep_clock.hpp): periods in simulated time,
// step order, event-driven components in their writer's instant, trigger loops, determinism.

#include <gtest/gtest.h>

#include "cobra/test_support/test_support.hpp"

#include <chrono>
#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "cobra/core/component.hpp"
#include "cobra/core/lockstep_clock.hpp"

namespace cobra::core {
namespace {

using namespace std::chrono_literals;
using Trace = std::vector<std::pair<std::int64_t, std::string>>;  // (time in ns, who)

/// Appends (now, name) to a shared trace on every update.
class Ticker : public Component {
 public:
  Ticker(std::string name, Trace& trace) : Component(std::move(name), Role::Calculation, "ticks"), trace_(&trace) {}
  std::vector<std::chrono::nanoseconds> times;

 protected:
  void updateHook() override {
    times.push_back(now());
    trace_->emplace_back(now().count(), name());
  }

 private:
  Trace* trace_;
};

/// Writes a pseudo-random (seeded) sample every update.
class Source : public Component {
 public:
  Source(std::string name, std::uint32_t seed) : Component(std::move(name), Role::Calculation, "samples"), state_(seed) {
    addPort(out);
  }
  OutputPort<double> out{"out", "sample", "1"};

 protected:
  void updateHook() override {
    state_ = state_ * 1664525U + 1013904223U;  // LCG: same seed, same samples
    out.write(static_cast<double>(state_ >> 8) / 16777216.0);
  }

 private:
  std::uint32_t state_;
};

/// Event-driven: y = k u on every new sample; also records (time, y).
class Gain : public Component {
 public:
  Gain(std::string name, double k) : Component(std::move(name), Role::Calculation, "y = k u"), k_(k) {
    addEventPort(in);
    addPort(out);
  }
  InputPort<double> in{"in", "u", "1"};
  OutputPort<double> out{"out", "y", "1"};
  std::vector<std::pair<std::int64_t, double>> trace;

 protected:
  void updateHook() override {
    double u = 0.0;
    while (in.read(u) == FlowStatus::NewData) {
      trace.emplace_back(now().count(), k_ * u);
      out.write(k_ * u);
    }
  }

 private:
  double k_;
};

void startAll(std::initializer_list<Component*> components) {
  for (Component* c : components) {
    ASSERT_TRUE(c->configure());
    ASSERT_TRUE(c->start());
  }
}

TEST(LockstepClock, PeriodsAreHonouredInSimulatedTime) {
  Trace trace;
  Ticker fast("Fast", trace);
  Ticker slow("Slow", trace);
  LockstepClock clock;
  clock.add(fast, 1ms);
  clock.add(slow, 3ms);
  startAll({&fast, &slow});
  clock.advance(30ms);
  ASSERT_EQ(fast.times.size(), 30U);
  ASSERT_EQ(slow.times.size(), 10U);
  for (std::size_t i = 0; i < fast.times.size(); ++i) EXPECT_EQ(fast.times[i], std::chrono::milliseconds(i));
  for (std::size_t i = 0; i < slow.times.size(); ++i) EXPECT_EQ(slow.times[i], std::chrono::milliseconds(3 * i));
  EXPECT_EQ(clock.now(), 30ms);
  EXPECT_EQ(clock.steps(), 40U);
  EXPECT_EQ(fast.now(), 30ms) << "components read the simulated clock";
  EXPECT_EQ(fast.updateCount(), 30U);
}

TEST(LockstepClock, AdvancingInPiecesGivesTheSameSteps) {
  Trace whole;
  Trace pieces;
  Ticker a("A", whole);
  Ticker b("B", pieces);
  LockstepClock one;
  LockstepClock two;
  one.add(a, 3ms);
  two.add(b, 3ms);
  startAll({&a, &b});
  one.advance(30ms);
  for (int i = 0; i < 12; ++i) two.advance(2500us);
  EXPECT_EQ(a.times, b.times);
  EXPECT_EQ(two.now(), 30ms);
}

TEST(LockstepClock, ComponentsStepInTheOrderTheyWereAdded) {
  Trace trace;
  Ticker b("B", trace);
  Ticker a("A", trace);
  LockstepClock clock;
  clock.add(b, 2ms);
  clock.add(a, 1ms);
  startAll({&a, &b});
  clock.advance(3ms);
  const Trace expected{{0, "B"}, {0, "A"}, {1'000'000, "A"}, {2'000'000, "B"}, {2'000'000, "A"}};
  EXPECT_EQ(trace, expected);
}

TEST(LockstepClock, AStepObserverSeesEveryStepWithItsWallClockDuration) {
  Trace trace;
  Ticker b("B", trace);
  Ticker a("A", trace);
  LockstepClock clock;
  clock.add(b, 2ms);
  clock.add(a, 1ms);
  startAll({&a, &b});
  std::vector<std::string> observed;
  std::chrono::nanoseconds total{0};
  clock.setStepObserver([&](const Component& c, std::chrono::nanoseconds took, std::chrono::nanoseconds cpu) {
    observed.push_back(c.name());
    EXPECT_GE(took.count(), 0);
    EXPECT_GE(cpu.count(), 0);
    total += took;
  });
  clock.advance(3ms);
  EXPECT_EQ(observed, (std::vector<std::string>{"B", "A", "A", "B", "A"}));
  EXPECT_EQ(clock.steps(), 5u);
  EXPECT_GT(total.count(), 0);
  clock.setStepObserver(nullptr);  // off again: steps go on untimed
  clock.advance(1ms);
  EXPECT_EQ(observed.size(), 5u);
  EXPECT_EQ(clock.steps(), 6u);
}

TEST(LockstepClock, AComponentAddedLaterStartsAtTheNextMultipleOfItsPeriod) {
  Trace trace;
  Ticker early("Early", trace);
  Ticker late("Late", trace);
  LockstepClock clock;
  clock.add(early, 1ms);
  startAll({&early, &late});
  clock.advance(2500us);
  ASSERT_TRUE(late.stop());
  clock.add(late, 2ms);
  ASSERT_TRUE(late.start());
  clock.advance(4ms);  // up to 6.5 ms
  EXPECT_EQ(late.times, (std::vector<std::chrono::nanoseconds>{4ms, 6ms}));
}

TEST(LockstepClock, StoppedComponentsDoNotUpdate) {
  Trace trace;
  Ticker t("T", trace);
  LockstepClock clock;
  clock.add(t, 1ms);
  clock.advance(5ms);
  EXPECT_TRUE(t.times.empty());
  startAll({&t});
  clock.advance(2ms);
  EXPECT_EQ(t.times.size(), 2U);
}

TEST(LockstepClock, EventDrivenComponentsRunInTheSameInstantAsTheirWriter) {
  Source src("Src", 1);
  Gain first("First", 2.0);
  Gain second("Second", 10.0);
  LockstepClock clock;
  clock.add(second, 0ns);  // added first, still runs after its (periodic) writers
  clock.add(src, 5ms);
  clock.add(first, 0ns);
  connect(src.out, first.in);
  connect(first.out, second.in);
  startAll({&src, &first, &second});
  clock.advance(20ms);
  ASSERT_EQ(first.trace.size(), 4U);
  ASSERT_EQ(second.trace.size(), 4U);
  for (std::size_t i = 0; i < 4; ++i) {
    EXPECT_EQ(first.trace[i].first, static_cast<std::int64_t>(i) * 5'000'000);
    EXPECT_EQ(second.trace[i].first, first.trace[i].first) << "same instant as its writer";
    EXPECT_DOUBLE_EQ(second.trace[i].second, 10.0 * first.trace[i].second);
  }
  EXPECT_EQ(clock.steps(), 12U);
}

TEST(LockstepClock, EventDrivenComponentsWithoutDataDoNotStep) {
  Source src("Src", 1);
  Gain idle("Idle", 1.0);
  LockstepClock clock;
  clock.add(src, 1ms);
  clock.add(idle, 0ns);
  startAll({&src, &idle});
  clock.advance(10ms);
  EXPECT_EQ(idle.updateCount(), 0U);
  EXPECT_EQ(clock.steps(), 10U);
}

TEST(LockstepClock, AWriteFromOutsideIsHandledAtTheStartOfTheNextAdvance) {
  Gain g("G", 3.0);
  OutputPort<double> outside{"outside", "written by the test", "1"};
  LockstepClock clock;
  clock.add(g, 0ns);
  connect(outside, g.in);
  startAll({&g});
  clock.advance(4ms);
  ASSERT_EQ(outside.write(2.0), WriteStatus::Written);
  EXPECT_TRUE(g.trace.empty()) << "nothing steps outside advance";
  clock.advance(1ms);
  ASSERT_EQ(g.trace.size(), 1U);
  EXPECT_EQ(g.trace[0], (std::pair<std::int64_t, double>{4'000'000, 6.0}));
}

TEST(LockstepClock, ATriggerLoopIsReportedClearly) {
  Source src("Src", 1);
  Gain ping("Ping", 1.0);
  Gain pong("Pong", 1.0);
  LockstepClock clock;
  clock.add(ping, 0ns);
  clock.add(pong, 0ns);
  connect(src.out, ping.in);
  connect(ping.out, pong.in);
  connect(pong.out, ping.in);
  startAll({&ping, &pong});
  clock.advance(2ms);  // nothing writes yet: the cycle is quiet
  EXPECT_EQ(clock.steps(), 0U);
  clock.add(src, 1ms);  // first step at 2 ms
  startAll({&src});
  try {
    clock.advance(1ms);
    FAIL() << "the loop was not detected";
  } catch (const Error& e) {
    EXPECT_CONTAINS(e.what(), "kept triggering each other for 100 rounds");
    EXPECT_CONTAINS(e.what(), "t = 2000000 ns");
    EXPECT_CONTAINS(e.what(), "cycle of event ports");
  }
}

TEST(LockstepClock, AddAndAdvanceRefuseMisuse) {
  Trace trace;
  Ticker t("T", trace);
  LockstepClock clock;
  clock.add(t, 1ms);
  try {
    clock.add(t, 2ms);
    FAIL();
  } catch (const Error& e) {
    EXPECT_CONTAINS(e.what(), "component 'T' is already on this clock");
  }
  Ticker neg("Neg", trace);
  EXPECT_THROW(clock.add(neg, -1ms), Error);
  EXPECT_CONTAINS(
      [&] {
        try {
          clock.advance(-1ms);
        } catch (const Error& e) {
          return std::string(e.what());
        }
        return std::string();
      }(),
      "negative duration");
  Ticker running("Running", trace);
  startAll({&running});
  EXPECT_THROW(clock.add(running, 1ms), Error);  // Running: its activity cannot change
  ASSERT_TRUE(running.stop());
}

TEST(LockstepClock, RemovedComponentsNoLongerStep) {
  Trace trace;
  Ticker t("T", trace);
  LockstepClock clock;
  clock.add(t, 1ms);
  startAll({&t});
  clock.advance(3ms);
  clock.remove(t);
  clock.advance(3ms);
  EXPECT_EQ(t.times.size(), 3U);
}

TEST(LockstepClock, ADestroyedOrReassignedComponentLeavesTheClock) {
  Trace trace;
  LockstepClock clock;
  Ticker kept("Kept", trace);
  clock.add(kept, 1ms);
  {
    Ticker gone("Gone", trace);
    clock.add(gone, 1ms);
    ASSERT_TRUE(gone.configure() && gone.start());
    clock.advance(2ms);
    ASSERT_TRUE(gone.stop());
  }
  Ticker moved("Moved", trace);
  clock.add(moved, 1ms);
  moved.setActivity(std::make_unique<SlaveActivity>());  // replaces (and destroys) its lockstep activity
  ASSERT_TRUE(kept.configure() && kept.start());
  ASSERT_TRUE(moved.configure() && moved.start());
  clock.advance(3ms);  // would step freed activities if the clock kept them
  EXPECT_EQ(kept.times.size(), 3U);
  EXPECT_TRUE(moved.times.empty());
}

TEST(LockstepClock, ComponentsOutliveTheirClock) {
  Trace trace;
  Ticker ticker("T", trace);
  {
    LockstepClock clock;
    clock.add(ticker, 1ms);
    clock.advance(5ms);
  }
  EXPECT_EQ(ticker.now(), 5ms) << "the activity keeps the clock's last time";
  ticker.setActivity(std::make_unique<SlaveActivity>());
}

TEST(LockstepClock, ActivityDescribesItsPeriod) {
  Trace trace;
  Ticker p("P", trace);
  Ticker e("E", trace);
  LockstepClock clock;
  clock.add(p, 1ms);
  clock.add(e, 0ns);
  EXPECT_EQ(p.activity().period(), 1ms);
  EXPECT_EQ(p.activity().describe(), "lockstep every 1 ms of simulated time");
  EXPECT_EQ(e.activity().describe(), "lockstep, when triggered");
}

/// One run of a small pipeline: a seeded source at 1 ms, a 3 ms source, two event-driven gains.
std::vector<std::pair<std::int64_t, double>> runPipeline() {
  Source a("A", 42);
  Source b("B", 7);
  Gain g1("G1", 0.5);
  Gain g2("G2", -2.0);
  LockstepClock clock;
  clock.add(a, 1ms);
  clock.add(b, 3ms);
  clock.add(g1, 0ns);
  clock.add(g2, 0ns);
  connect(a.out, g1.in, ConnPolicy::buffer(8));
  connect(b.out, g1.in, ConnPolicy::buffer(8));
  connect(g1.out, g2.in, ConnPolicy::buffer(8));
  for (Component* c : std::initializer_list<Component*>{&a, &b, &g1, &g2}) {
    (void)c->configure();
    (void)c->start();
  }
  clock.advance(100ms);
  auto trace = g1.trace;
  trace.insert(trace.end(), g2.trace.begin(), g2.trace.end());
  return trace;
}

/// Records when the clock met it, and what the component had done by then.
class RecordingSync : public ClockSync {
 public:
  explicit RecordingSync(const Ticker& ticker) : ticker_(&ticker) {}
  std::vector<std::pair<std::chrono::nanoseconds, std::size_t>> met;  // (t, the ticker's steps so far)
  void reached(std::chrono::nanoseconds t) noexcept override { met.emplace_back(t, ticker_->times.size()); }
  void setDone(bool) noexcept override {}
  bool peersDone() const noexcept override { return true; }
  std::vector<std::string> lostPeers() const override { return {}; }

 private:
  const Ticker* ticker_;
};

TEST(LockstepClock, MeetsItsClockSyncAtTheEndOfEveryAdvanceAfterItsSteps) {
  Trace trace;
  Ticker ticker("T", trace);
  LockstepClock clock;
  clock.add(ticker, 1ms);
  ASSERT_TRUE(ticker.configure());
  ASSERT_TRUE(ticker.start());
  RecordingSync sync(ticker);
  clock.setClockSync(&sync);
  EXPECT_EQ(clock.clockSync(), &sync);
  clock.advance(1ms);   // the step at 0
  clock.advance(3ms);   // the steps at 1, 2 and 3 ms
  clock.setClockSync(nullptr);
  clock.advance(1ms);   // not met
  ASSERT_EQ(sync.met.size(), 2U);
  EXPECT_EQ(sync.met[0], std::make_pair(std::chrono::nanoseconds(1ms), std::size_t{1}));
  EXPECT_EQ(sync.met[1], std::make_pair(std::chrono::nanoseconds(4ms), std::size_t{4}));
  EXPECT_TRUE(ticker.stop());
}

TEST(LockstepClock, TwoRunsOfAPipelineGiveIdenticalTraces) {
  const auto first = runPipeline();
  const auto second = runPipeline();
  EXPECT_EQ(first.size(), 2U * (100 + 34));
  EXPECT_EQ(first, second);
}

}  // namespace
}  // namespace cobra::core
