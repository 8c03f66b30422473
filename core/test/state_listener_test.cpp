// Unit tests of the state announcement of a component (component.hpp: StateListener,
// addStateListener, removeStateListener): every lifecycle change is told once with its from and
// to states, a hook that throws on the activity's thread is told from there, the slots are fixed
// (a fifth listener is refused, adding twice counts once, also from two threads at once), removal
// stops the calls, also from inside a listener, waits for another thread's announcement under
// way, and telling allocates nothing.

#include <gtest/gtest.h>

#include "cobra/test_support/counting_new.hpp"
#include "cobra/test_support/test_support.hpp"

#include <atomic>
#include <chrono>
#include <memory>
#include <stdexcept>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "cobra/core/activity.hpp"
#include "cobra/core/component.hpp"

namespace cobra::core {
namespace {

using cobra::test_support::allocationsDuring;
using cobra::test_support::messageOf;

class Probe : public Component {
 public:
  explicit Probe(std::string name = "P") : Component(std::move(name), Role::Calculation, "state listener probe") {}
  bool throw_in_update = false;

 protected:
  void updateHook() override {
    if (throw_in_update) throw std::runtime_error("update exploded");
  }
};

void step(Component& c) { dynamic_cast<SlaveActivity&>(c.activity()).step(); }

// Keeps what it was told in a fixed array (a listener must not allocate).
struct Recorder final : StateListener {
  struct Change {
    const Component* component;
    State from, to;
  };
  std::array<Change, 16> changes{};
  std::atomic<int> count{0};
  void stateChanged(const Component& component, State from, State to) noexcept override {
    const int i = count.fetch_add(1);
    if (i < static_cast<int>(changes.size())) changes[static_cast<std::size_t>(i)] = {&component, from, to};
  }
  std::vector<std::pair<State, State>> seen() const {
    std::vector<std::pair<State, State>> out;
    for (int i = 0; i < count.load() && i < static_cast<int>(changes.size()); ++i)
      out.emplace_back(changes[static_cast<std::size_t>(i)].from, changes[static_cast<std::size_t>(i)].to);
    return out;
  }
};

TEST(StateListener, HearsEveryLifecycleChangeOnceWithItsFromAndToStates) {
  Probe p;
  Recorder r;
  p.addStateListener(r);
  ASSERT_TRUE(p.configure());
  ASSERT_TRUE(p.start());
  ASSERT_TRUE(p.stop());
  ASSERT_TRUE(p.cleanup());
  const std::vector<std::pair<State, State>> expected = {{State::PreOperational, State::Stopped},
                                                         {State::Stopped, State::Running},
                                                         {State::Running, State::Stopped},
                                                         {State::Stopped, State::PreOperational}};
  EXPECT_EQ(r.seen(), expected);
  EXPECT_EQ(r.changes[0].component, &p);
}

TEST(StateListener, ARefusedCallOrAnUnchangedStateTellsNothing) {
  Probe p;
  Recorder r;
  p.addStateListener(r);
  EXPECT_FALSE(p.start());  // PreOperational: refused
  ASSERT_TRUE(p.configure());
  ASSERT_TRUE(p.configure());  // Stopped -> Stopped: no change
  EXPECT_EQ(r.count.load(), 1);
}

TEST(StateListener, AHookThrowingOnTheActivityIsToldExceptionFromRunning) {
  Probe p;
  Recorder r;
  p.addStateListener(r);
  ASSERT_TRUE(p.configure());
  ASSERT_TRUE(p.start());
  p.throw_in_update = true;
  step(p);
  ASSERT_EQ(p.state(), State::Exception);
  ASSERT_EQ(r.count.load(), 3);
  EXPECT_EQ(r.changes[2].from, State::Running);
  EXPECT_EQ(r.changes[2].to, State::Exception);
  ASSERT_TRUE(p.recover());
  EXPECT_EQ(r.seen().back(), std::make_pair(State::Exception, State::PreOperational));
}

TEST(StateListener, EveryListenerIsToldAndAddingOneTwiceCountsOnce) {
  Probe p;
  Recorder a, b;
  p.addStateListener(a);
  p.addStateListener(a);
  p.addStateListener(b);
  ASSERT_TRUE(p.configure());
  EXPECT_EQ(a.count.load(), 1);
  EXPECT_EQ(b.count.load(), 1);
}

TEST(StateListener, TheSlotsAreFixedAndAFifthListenerIsRefusedNamingTheComponent) {
  Probe p("Gain");
  std::array<Recorder, Component::kMaxStateListeners + 1> many;
  for (std::size_t i = 0; i < Component::kMaxStateListeners; ++i) p.addStateListener(many[i]);
  EXPECT_EQ(messageOf([&] { p.addStateListener(many.back()); }),
            "component 'Gain': already 4 state listeners (Component::kMaxStateListeners); remove one first");
  p.removeStateListener(many[0]);
  p.addStateListener(many.back());  // a freed slot is reused
  ASSERT_TRUE(p.configure());
  EXPECT_EQ(many[0].count.load(), 0);
  EXPECT_EQ(many.back().count.load(), 1);
}

TEST(StateListener, ARemovedListenerIsNotToldAgain) {
  Probe p;
  Recorder r;
  p.addStateListener(r);
  ASSERT_TRUE(p.configure());
  p.removeStateListener(r);
  ASSERT_TRUE(p.start());
  EXPECT_EQ(r.count.load(), 1);
}

// A listener that removes itself when told: removal from inside stateChanged returns (it does not
// wait for its own thread's announcement), and it is not told again.
TEST(StateListener, AListenerRemovingItselfFromInsideStateChangedIsNotToldAgain) {
  struct Once final : StateListener {
    Component* from = nullptr;
    int told = 0;
    void stateChanged(const Component&, State, State) noexcept override {
      ++told;
      from->removeStateListener(*this);
    }
  };
  Probe p;
  Once once;
  Recorder after;
  once.from = &p;
  p.addStateListener(once);
  p.addStateListener(after);
  ASSERT_TRUE(p.configure());
  ASSERT_TRUE(p.start());
  EXPECT_EQ(once.told, 1);
  EXPECT_EQ(after.count.load(), 2);  // the listeners after it are still told
}

// Thread A's change (configure) is being told to `slow`; thread B's change (start) is told to
// `remover`, which removes `slow` from inside its stateChanged: the removal skips B's own
// announcement but waits for A's call to `slow` to end, so `slow` may be destroyed after it.
TEST(StateListener, RemovalFromInsideAListenerWaitsForAnotherThreadsCallUnderWay) {
  std::atomic<bool> a_inside{false}, b_removing{false}, a_call_ended{false}, ended_before_removal_returned{false};
  struct Slow final : StateListener {
    std::atomic<bool> *inside, *removing, *ended;
    void stateChanged(const Component&, State, State to) noexcept override {
      if (to != State::Stopped) return;  // only A's configure is slow
      inside->store(true);
      while (!removing->load()) std::this_thread::yield();
      // Lets a removal that does not wait return before this call ends (it must not).
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
      ended->store(true);
    }
  } slow;
  slow.inside = &a_inside;
  slow.removing = &b_removing;
  slow.ended = &a_call_ended;
  struct Remover final : StateListener {
    Component* from = nullptr;
    StateListener* target = nullptr;
    std::atomic<bool> *removing, *ended, *ended_first;
    void stateChanged(const Component&, State, State to) noexcept override {
      if (to != State::Running) return;
      removing->store(true);
      from->removeStateListener(*target);
      ended_first->store(ended->load());
    }
  } remover;
  Probe p;
  remover.from = &p;
  remover.target = &slow;
  remover.removing = &b_removing;
  remover.ended = &a_call_ended;
  remover.ended_first = &ended_before_removal_returned;
  p.addStateListener(slow);
  p.addStateListener(remover);
  std::thread a([&] { ASSERT_TRUE(p.configure()); });
  while (!a_inside.load()) std::this_thread::yield();
  std::thread b([&] { ASSERT_TRUE(p.start()); });  // Stopped already: A's change is made, its telling under way
  b.join();
  a.join();
  EXPECT_TRUE(ended_before_removal_returned.load());
  EXPECT_EQ(p.state(), State::Running);
}

// Two threads each remove a listener from inside their own announcement of one component at the
// same time: neither waits for the other's (they would wait for each other forever); both return.
TEST(StateListener, TwoThreadsRemovingFromInsideTheirAnnouncementsDoNotWaitForEachOther) {
  struct Both final : StateListener {
    Component* from = nullptr;
    std::array<Recorder, 2> targets;
    std::atomic<int> inside{0};
    void stateChanged(const Component&, State, State) noexcept override {
      inside.fetch_add(1);
      while (inside.load() < 2) std::this_thread::yield();
      for (Recorder& target : targets) from->removeStateListener(target);
    }
  } both;
  Probe p;
  both.from = &p;
  p.addStateListener(both);
  p.addStateListener(both.targets[0]);
  p.addStateListener(both.targets[1]);
  std::thread a([&] { ASSERT_TRUE(p.configure()); });
  while (both.inside.load() < 1) std::this_thread::yield();
  std::thread b([&] { ASSERT_TRUE(p.start()); });
  a.join();
  b.join();
  ASSERT_TRUE(p.stop());
  EXPECT_EQ(both.targets[0].count.load(), 0);  // removed before either thread told them
  EXPECT_EQ(both.targets[1].count.load(), 0);
}

// Two threads add one listener at once, round after round: it takes one slot (told once).
TEST(StateListener, TwoThreadsAddingOneListenerAtOnceTakeOneSlot) {
  constexpr int kRounds = 1000;
  const std::vector<std::unique_ptr<Probe>> probes = [] {
    std::vector<std::unique_ptr<Probe>> out;
    for (int r = 0; r < kRounds; ++r) out.push_back(std::make_unique<Probe>());
    return out;
  }();
  std::vector<Recorder> listeners(kRounds);
  std::atomic<int> arrived{0};  // 2 per round: both threads reach round r before either adds
  const auto add = [&] {
    for (int r = 0; r < kRounds; ++r) {
      arrived.fetch_add(1);
      while (arrived.load() < 2 * (r + 1)) {
      }
      probes[static_cast<std::size_t>(r)]->addStateListener(listeners[static_cast<std::size_t>(r)]);
    }
  };
  std::thread first(add), second(add);
  first.join();
  second.join();
  int twice = 0;
  for (int r = 0; r < kRounds; ++r) {
    ASSERT_TRUE(probes[static_cast<std::size_t>(r)]->configure());
    if (listeners[static_cast<std::size_t>(r)].count.load() != 1) ++twice;
  }
  EXPECT_EQ(twice, 0) << "rounds of " << kRounds << " where one listener took two slots";
}

// The lifecycle calls between configure and cleanup allocate nothing of their own here (hooks that
// allocate nothing, a slave activity); with four listeners they allocate no more: telling is free.
TEST(StateListener, TellingTheListenersAllocatesNothing) {
  const auto cycle = [](Probe& p) {
    return allocationsDuring([&] {
      (void)p.start();
      (void)p.stop();
      (void)p.start();
      (void)p.stop();
    });
  };
  Probe quiet;
  ASSERT_TRUE(quiet.configure());
  const long without = cycle(quiet);
  Probe heard;
  std::array<Recorder, Component::kMaxStateListeners> listeners;
  for (Recorder& r : listeners) heard.addStateListener(r);
  ASSERT_TRUE(heard.configure());
  const long with = cycle(heard);
  EXPECT_EQ(with, without);
  for (const Recorder& r : listeners) EXPECT_EQ(r.count.load(), 5);
}

// A watcher's usual listener: a counter the watcher's thread compares with what it last saw.
TEST(StateListener, ACounterListenerLetsAWatcherLookOnlyAfterAChange) {
  struct Counter final : StateListener {
    std::atomic<std::uint64_t> changes{0};
    void stateChanged(const Component&, State, State to) noexcept override {
      if (to == State::Exception || to == State::FatalError) changes.fetch_add(1, std::memory_order_release);
    }
  } counter;
  Probe p;
  p.addStateListener(counter);
  ASSERT_TRUE(p.configure());
  ASSERT_TRUE(p.start());
  step(p);
  EXPECT_EQ(counter.changes.load(), 0u);
  p.throw_in_update = true;
  step(p);
  EXPECT_EQ(counter.changes.load(), 1u);
}

}  // namespace
}  // namespace cobra::core
