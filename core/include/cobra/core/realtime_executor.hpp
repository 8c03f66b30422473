#pragma once
/// @file
/// The wall-clock execution of a deployment: the lockstep clock's schedule (lockstep_clock.hpp),
/// run every period on one real-time thread paced by absolute deadlines. A run on the wall clock
/// thus makes the lockstep run's decisions up to timing: every component steps once per period of
/// its own, in the order the clock gives, and a controller never reads a sample one period old or
/// twice by an accident of scheduling (as ros2_control's read-update-write loop, OROCOS slave
/// activities under one master, an EtherCAT master's cycle). Work that cannot finish within a
/// period runs on threads of its own beside it (an activity's `own_pace`, deploy/spec.hpp).
///
/// Every tick is measured without allocating: the wake-up latency (how late the thread woke
/// after its deadline), the compute time of the whole tick and of each component's step, and the
/// deadline misses (a tick whose work ended after the next tick's deadline).

#include <array>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "cobra/core/activity.hpp"

namespace cobra::core {

class Component;
class LockstepClock;

/// Durations (ns) counted in log-linear buckets: 32 per power of two (a quantile is known to
/// within 3 %), from 0 to 2^40 ns (18 min). Adding is real-time safe (no allocation, no lock);
/// one thread adds, any thread may read (relaxed atomics: a reader sees a recent count).
class DurationHistogram {
 public:
  void add(std::int64_t ns) noexcept;
  std::uint64_t count() const noexcept { return count_.load(std::memory_order_relaxed); }
  /// Largest duration added (exact), in ns; 0 when empty.
  std::int64_t max() const noexcept { return max_.load(std::memory_order_relaxed); }
  /// The q-quantile (0 < q < 1), in ns: the upper edge of the bucket that holds it, capped by
  /// max(); 0 when empty.
  std::int64_t quantile(double q) const noexcept;
  void reset() noexcept;

 private:
  static constexpr int kSubBits = 5;  // 32 buckets per power of two
  static constexpr int kOctaves = 41;
  static constexpr std::size_t kBuckets = (kOctaves + 1) << kSubBits;
  static std::size_t bucketOf(std::int64_t ns) noexcept;
  static std::int64_t upperEdge(std::size_t bucket) noexcept;
  std::array<std::atomic<std::uint64_t>, kBuckets> buckets_{};
  std::atomic<std::uint64_t> count_{0};
  std::atomic<std::int64_t> max_{0};
};

/// Median, p99, p99.9 and worst of a histogram, in s (what reports and tests read).
struct DurationFigures {
  std::uint64_t count = 0;
  double median = 0.0, p99 = 0.0, p999 = 0.0, worst = 0.0;  ///< s
};
DurationFigures figuresOf(const DurationHistogram& histogram);

/// What the executor does when a tick misses its deadline (misses are always counted).
struct DeadlinePolicy {
  /// Emit `e_deadline_missed` (once per run of consecutive misses) through the `on_event` hook.
  bool emit_event = false;
  /// After this many consecutive misses, emit `e_deadline_safe_stop` once and report
  /// `safeStopAsked()`: the run ends in a safe stop. 0: never.
  int safe_stop_after = 0;
};

struct ExecutorOptions {
  /// The tick, in ns (> 0): every tick runs the clock's instants due within one tick. Every
  /// periodic component's period must be a multiple of it.
  std::chrono::nanoseconds period{1'000'000};
  /// SCHED_FIFO priority 1..99 (Scheduler::Other ignores it).
  int priority = 80;
  Scheduler scheduler = Scheduler::Fifo;
  /// The CPU the thread is pinned to; -1: any.
  int cpu = -1;
  /// mlockall(MCL_CURRENT | MCL_FUTURE) at start, so no page fault stalls a tick.
  bool lock_memory = true;
  DeadlinePolicy policy;
  /// Called on the executor's thread with "e_deadline_missed" or "e_deadline_safe_stop" (see
  /// DeadlinePolicy) and "e_handover_stale_<component>" (watchHandover); must be real-time safe
  /// (e.g. Component::emitEvent). May be empty.
  std::function<void(const char* event)> on_event;
  /// After a stall longer than this many ticks (the machine stopped the process), the executor
  /// slips: it stops catching up tick after tick, moves its deadlines and the run's epoch by the
  /// time lost, and counts it (slipped()). Shorter delays are caught up at once.
  int max_catch_up_ticks = 50;
};

/// A component that runs at its own pace (a thread of its own beside the executor) and how old
/// what it hands over got: see Activity::handoverAge and RealtimeExecutor::watchHandover.
struct HandoverFigures {
  std::string component;
  double max_age = 0.0;     ///< s: the bound the deployment declared
  double worst_age = 0.0;   ///< s: the oldest its hand-over was at a tick
  std::uint64_t stale = 0;  ///< episodes past max_age (each emitted its event once)
};

/// Compute time of one component's steps on the executor's thread.
struct ComponentTiming {
  std::string component;
  DurationFigures compute;  ///< per step, s
};

/// Runs a LockstepClock's schedule on the wall clock, on one thread of its own.
class RealtimeExecutor {
 public:
  /// @throws Error for a period <= 0, a priority outside 1..99 for SCHED_FIFO, or a cpu below -1.
  RealtimeExecutor(LockstepClock& clock, ExecutorOptions options);
  /// Stops the thread if it runs.
  ~RealtimeExecutor();
  RealtimeExecutor(const RealtimeExecutor&) = delete;
  RealtimeExecutor& operator=(const RealtimeExecutor&) = delete;

  /// Starts the thread: run time 0 is the clock's now at the first tick (setRunEpoch). A
  /// scheduler, an affinity or a memory lock the process may not have is one warning each
  /// (warnings()), printed once to stderr, and the run goes on.
  void start();
  /// Asks the thread to stop after its current tick and joins it. Idempotent.
  void stop();
  bool running() const { return running_.load(std::memory_order_acquire); }

  /// Runs `work` on the executor's thread between two ticks (as the lockstep clock's caller runs
  /// between two advances) and waits for it: actions, faults and inputs of a run that touch
  /// components or switch deployments. Runs it at once when the thread is not running (or when
  /// called from it). Rethrows what `work` throws. Not real-time: callers are other threads.
  void runBetweenTicks(const std::function<void()>& work);

  /// "SCHED_FIFO priority 80 refused (Operation not permitted): ..." and the like.
  std::vector<std::string> warnings() const;
  /// The scheduler the thread got (Other when Fifo was refused); valid once started.
  Scheduler effectiveScheduler() const { return effective_.load(std::memory_order_relaxed); }
  bool memoryLocked() const { return memory_locked_.load(std::memory_order_relaxed); }

  std::uint64_t ticks() const { return ticks_.load(std::memory_order_relaxed); }
  std::uint64_t deadlineMisses() const { return misses_.load(std::memory_order_relaxed); }
  /// Longest run of consecutive missed ticks.
  std::uint64_t worstConsecutiveMisses() const { return worst_consecutive_.load(std::memory_order_relaxed); }
  /// True once the policy's safe_stop_after was reached.
  bool safeStopAsked() const { return safe_stop_.load(std::memory_order_acquire); }
  /// Time given up after stalls (see ExecutorOptions::max_catch_up_ticks), in ns.
  std::chrono::nanoseconds slipped() const { return std::chrono::nanoseconds(slipped_ns_.load(std::memory_order_relaxed)); }
  /// Wake-up latency: how late each tick started after its deadline.
  const DurationHistogram& wakeLatency() const { return latency_; }
  /// Compute time of each tick (the clock's steps and switches, plus work between ticks).
  const DurationHistogram& tickCompute() const { return compute_; }
  /// The part of each tick outside the components' steps: the clock's own work and what it runs
  /// between instants (deployment and configuration switches).
  const DurationHistogram& betweenSteps() const { return between_steps_; }
  /// Each piece of work run between ticks (runBetweenTicks: actions, faults, inputs).
  const DurationHistogram& workBetweenTicks() const { return work_time_; }
  /// Per component, in the clock's order (allocates: not for the real-time thread).
  std::vector<ComponentTiming> componentTimings() const;

  /// Watches, every tick, the hand-over age of `component`, which runs at its own pace: when it
  /// passes `max_age` the executor emits `e_handover_stale_<component>` through `on_event` (once
  /// until the age is back within the bound) and counts the episode. Watching a component again
  /// sets its new bound. Call before start() or between ticks on the executor's thread (a
  /// deployment switch that gives a component its own pace); room for kMaxWatches components,
  /// fixed at construction. The component must outlive the executor.
  /// @throws Error for a max_age <= 0, more than kMaxWatches components, or a call from another
  /// thread while the executor runs.
  void watchHandover(const Component& component, std::chrono::nanoseconds max_age);
  static constexpr std::size_t kMaxWatches = 32;
  /// The watched components' figures (allocates: not for the real-time thread).
  std::vector<HandoverFigures> handoverFigures() const;
  const ExecutorOptions& options() const { return options_; }

 private:
  void loop();
  void applyScheduling();
  void onStep(const Component& component, std::chrono::nanoseconds cpu) noexcept;
  void takeWork() noexcept;
  void checkHandovers(std::chrono::nanoseconds now) noexcept;
  void warn(std::string text);

  LockstepClock& clock_;
  ExecutorOptions options_;
  std::thread thread_;
  std::atomic<bool> running_{false};
  std::atomic<bool> stop_{false};
  std::atomic<Scheduler> effective_{Scheduler::Other};
  std::atomic<bool> memory_locked_{false};

  // Work from other threads (runBetweenTicks): one at a time, callers serialised by the mutex
  // (never taken by the executor's thread).
  struct Work {
    const std::function<void()>* work;
    std::exception_ptr error;
    std::atomic<bool> done{false};
  };
  std::mutex callers_;
  std::atomic<Work*> work_{nullptr};

  mutable std::mutex warnings_mutex_;
  std::vector<std::string> warnings_;

  std::atomic<std::uint64_t> ticks_{0}, misses_{0}, worst_consecutive_{0};
  std::atomic<std::int64_t> slipped_ns_{0};
  std::atomic<bool> safe_stop_{false};
  DurationHistogram latency_, compute_, between_steps_, work_time_;
  std::int64_t stepped_ns_ = 0;  // this tick's component steps so far (the executor thread's)
  // Per component: slots made at start for the clock's components (and spare ones for
  // components a deployment switch adds), so the step observer never allocates.
  static constexpr std::size_t kSpareSlots = 32;
  struct Slot {
    std::atomic<const Component*> component{nullptr};
    DurationHistogram compute;
  };
  std::unique_ptr<Slot[]> slots_;
  std::size_t slot_count_ = 0;
  std::atomic<std::size_t> slots_used_{0};
  std::size_t next_slot_ = 0;  // the executor thread's guess: components step in order
  // The own-pace components watched (watchHandover): slots fixed at construction, filled in
  // order; a slot is read by other threads once `watch_count_` covers it.
  struct Watch {
    std::atomic<const Component*> component{nullptr};
    std::atomic<std::int64_t> max_age_ns{0};
    char event[96] = {};  // "e_handover_stale_<name>", made by watchHandover: emitting it allocates nothing
    std::atomic<std::int64_t> worst_ns{0};
    std::atomic<std::uint64_t> stale{0};
    bool is_stale = false;  // the executor thread's
  };
  std::unique_ptr<Watch[]> watches_;
  std::atomic<std::size_t> watch_count_{0};
};

}  // namespace cobra::core
