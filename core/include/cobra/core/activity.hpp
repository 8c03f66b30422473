#pragma once
/// @file
/// Activities decide when a component's update runs: periodic thread, event-driven thread,
/// slave (stepped by a master), or the lockstep simulation clock (lockstep_clock.hpp).

#include <atomic>
#include <chrono>
#include <cstdint>
#include <string>
#include <thread>

namespace cobra::core {

class Component;

/// "1 ms", "250 us", "3 s": the shortest exact text of a duration.
std::string formatDuration(std::chrono::nanoseconds duration);

/// CLOCK_MONOTONIC now, in ns since boot.
std::chrono::nanoseconds monotonicNow() noexcept;
/// Run time: the time every clock of a run reports (`Activity::now()`, event stamps, logs), in ns.
/// A threaded activity's now() is CLOCK_MONOTONIC minus the run's epoch; the epoch is the
/// process's start until a run sets it (setRunEpoch), e.g. the real-time executor, so that its
/// lockstep clock and the threads beside it report the same time.
std::chrono::nanoseconds runEpoch() noexcept;
/// Sets the run's epoch: the CLOCK_MONOTONIC time (ns since boot) at which run time is 0.
void setRunEpoch(std::chrono::nanoseconds monotonic) noexcept;

/// Starts the activity launcher (once per process; later calls do nothing): the thread that
/// creates the threads of activities started from a real-time thread (markRealtimeThread).
/// Call it from an ordinary thread before the real-time one needs it (RealtimeExecutor::start).
void startActivityLauncher();
/// Marks the calling thread as real-time (true) or not (false, the default). A ThreadActivity
/// started from a real-time thread (a deployment switch between two ticks of the executor) does
/// not create its thread there: creating a thread maps its stack, which under mlockall is faulted
/// in whole (8 MiB by default: about 15 ms, measured). The launcher creates it and stepping
/// begins when it runs; the start itself allocates nothing and does not block. Without a
/// launcher running, the thread is created in place as from any other thread.
void markRealtimeThread(bool realtime) noexcept;

/// Base class. An activity belongs to one component (`Component::setActivity`); the component
/// starts it after startHook and stops it before stopHook.
class Activity {
 public:
  virtual ~Activity() = default;
  Activity(const Activity&) = delete;
  Activity& operator=(const Activity&) = delete;

  /// e.g. "periodic 1 ms, SCHED_FIFO priority 80".
  virtual std::string describe() const = 0;
  /// Period in s of simulated or real time; zero for activities that are not periodic.
  virtual std::chrono::nanoseconds period() const { return std::chrono::nanoseconds(0); }
  /// The clock components read with `Component::now()`, in ns: run time (CLOCK_MONOTONIC minus
  /// runEpoch()) by default; simulated time on the lockstep clock.
  virtual std::chrono::nanoseconds now() const;
  /// Asks for a step soon (event-port data, operation requests). Real-time safe.
  virtual void trigger() noexcept {}
  /// True while a thread of this activity is stepping the component.
  virtual bool hasRunningThread() const { return false; }
  /// True when called from this activity's own thread.
  virtual bool isActivityThread() const { return false; }
  /// True when Component::stop may be called from the activity's own thread: the activity has no
  /// thread of its own to join (a lockstep clock stepped by an executor stops components between
  /// its instants, on its thread).
  virtual bool stoppableFromOwnThread() const { return false; }
  /// How old, at `now` (CLOCK_MONOTONIC, see monotonicNow), what the component hands over through
  /// this activity may be: for a periodic thread, the time since its last step ended (since its
  /// start before the first); for an event-driven thread, the time the oldest trigger not yet
  /// answered by a finished step has waited (0 when none waits). 0 when the activity has no
  /// thread of its own or is not running. The real-time executor watches it for the components
  /// that run at their own pace (deploy/spec.hpp: `max_age`). Real-time safe, any thread.
  virtual std::chrono::nanoseconds handoverAge(std::chrono::nanoseconds now) const noexcept {
    (void)now;
    return std::chrono::nanoseconds(0);
  }

 protected:
  Activity() = default;
  friend class Component;
  /// Begins stepping (threaded activities spawn their thread). Called by Component::start.
  virtual void startStepping() {}
  /// Stops stepping and joins the thread. Called by Component::stop/recover, never from the
  /// activity's own thread.
  virtual void stopStepping() {}
  /// Runs one step of the owner: pending changes, then updateHook when Running.
  void stepComponent() noexcept;

  Component* component_ = nullptr;
};

/// No thread: the component steps when its master calls `step()`. The default activity.
class SlaveActivity final : public Activity {
 public:
  SlaveActivity() = default;
  std::string describe() const override { return "slave"; }
  void trigger() noexcept override { triggered_.store(true, std::memory_order_release); }
  /// Runs one step now, in the caller's thread.
  void step() noexcept {
    triggered_.store(false, std::memory_order_relaxed);
    stepComponent();
  }
  /// True when something asked for a step since the last one.
  bool triggered() const { return triggered_.load(std::memory_order_acquire); }

 private:
  std::atomic<bool> triggered_{false};
};

/// Scheduling class of an activity thread.
enum class Scheduler { Fifo, Other };

/// Statistics of a threaded activity, readable from any thread.
struct ActivityStats {
  std::uint64_t steps = 0;
  std::uint64_t overruns = 0;   ///< periods skipped because a step ended after the next deadline
  std::int64_t max_lateness_ns = 0;  ///< worst wake-up delay after the deadline, in ns
};

/// Common part of the threaded activities: thread creation with the requested scheduler.
/// SCHED_FIFO needs CAP_SYS_NICE or an rtprio limit; when refused, one warning is printed for
/// the whole process and the thread runs SCHED_OTHER.
///
/// The thread is created at the first start and kept until the activity is destroyed: a stop
/// parks it (no step runs once stopStepping returned), a start wakes it, as RTT's activities do.
/// A deployment switch that stops and starts a component then creates and joins no thread.
class ThreadActivity : public Activity {
 public:
  ~ThreadActivity() override;
  bool hasRunningThread() const override { return running_.load(std::memory_order_acquire); }
  bool isActivityThread() const override {
    return thread_id_.load(std::memory_order_acquire) == std::this_thread::get_id();
  }
  int priority() const { return priority_; }
  Scheduler scheduler() const { return scheduler_; }
  /// The scheduler the thread actually got (Other when Fifo was refused).
  Scheduler effectiveScheduler() const { return effective_.load(std::memory_order_relaxed); }
  ActivityStats stats() const;
  std::chrono::nanoseconds handoverAge(std::chrono::nanoseconds now) const noexcept override;

 protected:
  ThreadActivity(int priority, Scheduler scheduler);
  void startStepping() override;
  void stopStepping() override;
  /// Stepping: runs until `stopRequested()`, then returns (the thread parks until the next start).
  virtual void loop() = 0;
  /// Stops stepping and ends the thread. Subclasses call it in their destructor, before their
  /// loop() is gone.
  void endThread();
  bool stopRequested() const { return stop_.load(std::memory_order_acquire); }
  /// Wakes the loop so it notices a stop request.
  virtual void wake() noexcept {}
  std::string schedulerText() const;

  std::atomic<std::uint64_t> steps_{0};
  std::atomic<std::uint64_t> overruns_{0};
  std::atomic<std::int64_t> max_lateness_ns_{0};
  /// ns (CLOCK_MONOTONIC) from which handoverAge counts; 0: nothing waits (see handoverAge).
  /// Periodic: the end of the last step. Event-driven: the oldest trigger not yet taken by a step
  /// (`waiting_since_ns_`) and the oldest one taken by the step under way (`serving_since_ns_`).
  std::atomic<std::int64_t> waiting_since_ns_{0};
  std::atomic<std::int64_t> serving_since_ns_{0};

 private:
  friend class ActivityLauncher;
  void applyScheduling();
  /// Creates the thread (on the starter's thread or the launcher's).
  void createThread();
  /// The thread's body: loop() once per start, parked in between, until endThread.
  void serve();
  int priority_;
  Scheduler scheduler_;
  std::atomic<Scheduler> effective_{Scheduler::Other};
  // Assigned by the thread that creates it (the starter's or the launcher's), read by endThread
  // once `created_` is set.
  std::thread thread_;
  std::atomic<bool> created_{false};
  bool thread_requested_ = false;  // touched only by the thread that starts and stops the activity
  // The activity thread's id, stored by that thread itself for its whole life (other threads
  // must not read `thread_`, which its creator may still be assigning when the thread begins).
  std::atomic<std::thread::id> thread_id_{};
  std::atomic<bool> running_{false};  // between a start and the end of the stop that follows
  std::atomic<bool> stop_{false};
  std::atomic<bool> exit_{false};
  std::atomic<std::uint32_t> starts_{0};  // bumped by each start (and by endThread); the thread waits on it
  std::atomic<std::uint32_t> parked_{0};  // the start whose loop() last returned; stopStepping waits on it
};

/// Steps the component every `period` on its own thread, sleeping until absolute deadlines
/// (CLOCK_MONOTONIC), so the period does not drift with the step duration. A step that ends
/// after the next deadline skips the missed periods (counted as overruns).
class PeriodicActivity final : public ThreadActivity {
 public:
  /// @param period in ns (> 0); @param priority 1..99 for SCHED_FIFO, ignored for Other.
  /// @throws Error when period is not positive or priority is outside 1..99 for Fifo.
  explicit PeriodicActivity(std::chrono::nanoseconds period, int priority = 50, Scheduler scheduler = Scheduler::Fifo);
  ~PeriodicActivity() override;
  std::string describe() const override;
  std::chrono::nanoseconds period() const override { return period_; }

 protected:
  void loop() override;

 private:
  std::chrono::nanoseconds period_;
};

/// Steps the component on its own thread whenever it is triggered: new data on an event port,
/// an own-thread operation call, or a property change. Several triggers before the thread
/// wakes give one step.
class EventActivity final : public ThreadActivity {
 public:
  explicit EventActivity(int priority = 50, Scheduler scheduler = Scheduler::Fifo);
  ~EventActivity() override;
  std::string describe() const override;
  void trigger() noexcept override;

 protected:
  void startStepping() override;
  void loop() override;
  void wake() noexcept override { trigger(); }

 private:
  std::atomic<std::uint32_t> triggers_{0};
  /// Trigger count when stepping started: triggers after it (even before the thread runs) step.
  std::uint32_t seen_at_start_ = 0;
};

}  // namespace cobra::core
