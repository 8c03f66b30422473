#pragma once
/// @file
/// Deterministic simulated time: steps a set of components in a fixed order, as fast as the CPU
/// allows, honouring each one's period in simulated time. Tests use this, not wall-clock sleeps.

#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <thread>
#include <vector>

#include "cobra/core/activity.hpp"
#include "cobra/core/clock_sync.hpp"

namespace cobra::core {

class LockstepClock;

/// The activity a LockstepClock gives each of its components.
class LockstepActivity final : public Activity {
 public:
  LockstepActivity(LockstepClock& clock, std::chrono::nanoseconds period) : clock_(&clock), period_(period) {}
  /// Leaves its clock, so a replaced or destroyed activity is never stepped.
  ~LockstepActivity() override;
  std::string describe() const override;
  std::chrono::nanoseconds period() const override { return period_; }
  std::chrono::nanoseconds now() const override;
  void trigger() noexcept override;
  /// True while an executor steps the clock from another thread than the caller's (then a
  /// property change or an own-thread operation is queued for the component's next step).
  bool hasRunningThread() const override;
  /// True on the thread of the executor that steps the clock (in a step or between instants).
  bool isActivityThread() const override;
  /// The executor's thread stops components between instants (deployment switches).
  bool stoppableFromOwnThread() const override { return true; }

 private:
  friend class LockstepClock;
  LockstepClock* clock_;  // nullptr once the clock is gone; now() then keeps its last time
  std::chrono::nanoseconds last_now_{0};
  std::chrono::nanoseconds period_;
  std::chrono::nanoseconds next_due_{0};
  // Set from any thread (event ports, operations, an own-pace component's write), taken by the
  // clock's stepping thread.
  std::atomic<bool> triggered_{false};
};

/// One thread, one simulated clock. A component added with period p > 0 steps at every
/// multiple of p; with period 0 it steps only when triggered (event ports, operations), in the
/// same instant as the writer, after the periodic components (components triggered by a write
/// from outside the clock step at the start of the next `advance`). Within an instant,
/// components step in the order they were added. Two runs with the same inputs give identical
/// traces.
class LockstepClock {
 public:
  LockstepClock() = default;
  /// Detaches its activities: their components keep them (stepped by nobody) until replaced.
  ~LockstepClock();
  LockstepClock(const LockstepClock&) = delete;
  LockstepClock& operator=(const LockstepClock&) = delete;

  /// Gives `component` a LockstepActivity on this clock. Destroying the component, or giving it
  /// another activity, takes it off the clock. @throws Error when the component is Running or
  /// already added.
  void add(Component& component, std::chrono::nanoseconds period);
  /// Takes `component` off the clock (it keeps its activity, stepped by nobody).
  void remove(Component& component);

  /// Simulated time, in ns since the clock was made. Readable from any thread.
  std::chrono::nanoseconds now() const { return std::chrono::nanoseconds(now_.load(std::memory_order_relaxed)); }
  /// Runs every step due in [now, now + duration), then sets now to now + duration.
  void advance(std::chrono::nanoseconds duration);
  /// `hook` runs at the end of every instant, after its steps (and at the start of `advance`),
  /// outside any component's step: the Configurator carries out deployment switches there.
  /// When it returns true (it changed something), the components it triggered step in the same
  /// instant, and it runs again. One hook; setting another replaces it.
  void setBetweenInstants(std::function<bool()> hook) { between_instants_ = std::move(hook); }
  /// `observer` is called after every component step with the time the step took: wall-clock
  /// (steady_clock) and the stepping thread's CPU time (CLOCK_THREAD_CPUTIME_ID, which leaves out
  /// the time the OS ran something else), both in ns: profiling a simulated run, e.g. the
  /// supervisors' step times of a whole procedure. It runs in the stepping thread and must not
  /// allocate to keep the run real-time clean; the clock adds four clock reads per step only
  /// while one is set.
  /// With `cpu_time` false the CPU time is not read (it is passed as 0): two clock reads per step
  /// instead of four, for an observer that needs the wall-clock duration only (the executor).
  using StepObserver = std::function<void(const Component&, std::chrono::nanoseconds wall, std::chrono::nanoseconds cpu)>;
  void setStepObserver(StepObserver observer, bool cpu_time = true) {
    step_observer_ = std::move(observer);
    observe_cpu_time_ = cpu_time;
  }
  /// `sync` (not owned; nullptr: none) is met at the end of every `advance`: one simulated run
  /// split over processes (core/clock_sync.hpp). It must outlive its use by this clock.
  void setClockSync(ClockSync* sync) { sync_ = sync; }
  ClockSync* clockSync() const { return sync_; }
  /// Number of component steps run so far.
  std::uint64_t steps() const { return steps_; }
  /// The thread that steps this clock when an executor runs it on the wall clock
  /// (realtime_executor.hpp); default-constructed: none (the caller of advance steps it). While
  /// set, other threads reach the components through runBetweenSteps, as with threaded activities.
  void setSteppingThread(std::thread::id id) noexcept { stepping_thread_.store(id, std::memory_order_release); }
  std::thread::id steppingThread() const noexcept { return stepping_thread_.load(std::memory_order_acquire); }
  /// The components on the clock with their periods (0: when triggered), in stepping order.
  /// Not thread-safe: call it between instants.
  std::vector<std::pair<const Component*, std::chrono::nanoseconds>> schedule() const;
  /// Most rounds of triggered steps in one instant before the clock reports a trigger loop.
  static constexpr int kMaxTriggerRounds = 100;

 private:
  friend class LockstepActivity;
  void runInstant(std::chrono::nanoseconds t);
  void runTriggered(std::chrono::nanoseconds t);
  /// runTriggered, then the between-instants hook until it has nothing more to do.
  void settle(std::chrono::nanoseconds t);
  void forget(const LockstepActivity* activity);

  struct Entry {
    Component* component;
    LockstepActivity* activity;
  };
  /// Steps one component (timed when a step observer is set).
  void step(const Entry& e);
  std::vector<Entry> entries_;
  std::atomic<std::int64_t> now_{0};  // ns
  std::uint64_t steps_ = 0;
  std::atomic<std::thread::id> stepping_thread_{};
  std::function<bool()> between_instants_;
  StepObserver step_observer_;
  bool observe_cpu_time_ = true;
  ClockSync* sync_ = nullptr;
  /// Set when an event-driven (period 0) component is triggered: runTriggered scans for them
  /// only then (it runs twice per instant; most instants' second call finds nothing).
  std::atomic<bool> trigger_pending_{false};
};

}  // namespace cobra::core
