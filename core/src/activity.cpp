#include "cobra/core/activity.hpp"

#include <pthread.h>
#include <sched.h>
#include <sys/prctl.h>
#include <time.h>

#include <algorithm>
#include <array>
#include <mutex>
#include <cerrno>
#include <cstdio>
#include <cstring>

#include "cobra/core/component.hpp"
#include "cobra/core/error.hpp"

namespace cobra::core {
std::chrono::nanoseconds monotonicNow() noexcept {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return std::chrono::seconds(ts.tv_sec) + std::chrono::nanoseconds(ts.tv_nsec);
}

namespace {

/// ns since boot at which run time is 0: the process's start until a run sets it.
std::atomic<std::int64_t> run_epoch_ns{monotonicNow().count()};

timespec toTimespec(std::chrono::nanoseconds t) {
  timespec ts{};
  ts.tv_sec = static_cast<time_t>(t.count() / 1'000'000'000);
  ts.tv_nsec = static_cast<long>(t.count() % 1'000'000'000);
  return ts;
}

std::atomic<bool> fifo_warning_printed{false};

thread_local bool realtime_thread = false;

/// Longest a stop request waits for a sleeping periodic activity.
constexpr std::chrono::nanoseconds kStopCheck = std::chrono::milliseconds(20);

}  // namespace

std::string formatDuration(std::chrono::nanoseconds duration) {
  const auto ns = duration.count();
  if (ns != 0 && ns % 1'000'000'000 == 0) return std::to_string(ns / 1'000'000'000) + " s";
  if (ns != 0 && ns % 1'000'000 == 0) return std::to_string(ns / 1'000'000) + " ms";
  if (ns != 0 && ns % 1'000 == 0) return std::to_string(ns / 1'000) + " us";
  return std::to_string(ns) + " ns";
}

std::chrono::nanoseconds runEpoch() noexcept {
  return std::chrono::nanoseconds(run_epoch_ns.load(std::memory_order_relaxed));
}

void setRunEpoch(std::chrono::nanoseconds monotonic) noexcept {
  run_epoch_ns.store(monotonic.count(), std::memory_order_relaxed);
}

/// One thread that creates activity threads for real-time threads. Requests go through a fixed
/// array of slots (no allocation, no lock on the requester's side); the launcher waits on a
/// counter. Lives until the process ends.
class ActivityLauncher {
 public:
  static ActivityLauncher* running() noexcept { return instance_.load(std::memory_order_acquire); }
  static void start() {
    static std::mutex starting;
    const std::lock_guard lock(starting);
    if (running() != nullptr) return;
    static ActivityLauncher launcher;  // joined at exit, after every activity is gone
    instance_.store(&launcher, std::memory_order_release);
  }
  /// False when every slot is taken (then the caller creates the thread itself).
  bool post(ThreadActivity* activity) noexcept {
    for (auto& slot : slots_) {
      ThreadActivity* expected = nullptr;
      if (slot.compare_exchange_strong(expected, activity, std::memory_order_acq_rel)) {
        requests_.fetch_add(1, std::memory_order_release);
        requests_.notify_one();
        return true;
      }
    }
    return false;
  }

 private:
  ActivityLauncher() : thread_([this] { serve(); }) {}
  ~ActivityLauncher() {
    stopping_.store(true, std::memory_order_release);
    requests_.fetch_add(1, std::memory_order_release);
    requests_.notify_one();
    thread_.join();
  }
  void serve() {
    std::uint32_t seen = 0;
    for (;;) {
      requests_.wait(seen, std::memory_order_acquire);
      seen = requests_.load(std::memory_order_acquire);
      for (auto& slot : slots_)
        if (ThreadActivity* activity = slot.exchange(nullptr, std::memory_order_acq_rel)) activity->createThread();
      if (stopping_.load(std::memory_order_acquire)) return;
    }
  }

  static inline std::atomic<ActivityLauncher*> instance_{nullptr};
  std::array<std::atomic<ThreadActivity*>, 64> slots_{};
  std::atomic<std::uint32_t> requests_{0};
  std::atomic<bool> stopping_{false};
  std::thread thread_;  // last: starts once the members above exist
};

void startActivityLauncher() { ActivityLauncher::start(); }

void markRealtimeThread(bool realtime) noexcept { realtime_thread = realtime; }

std::chrono::nanoseconds Activity::now() const { return monotonicNow() - runEpoch(); }

void Activity::stepComponent() noexcept {
  if (component_ != nullptr) component_->step();
}

ThreadActivity::ThreadActivity(int priority, Scheduler scheduler) : priority_(priority), scheduler_(scheduler) {
  if (scheduler == Scheduler::Fifo && (priority < 1 || priority > 99))
    throw Error("SCHED_FIFO priority must be in 1..99, got " + std::to_string(priority));
}

ThreadActivity::~ThreadActivity() {
  // Subclasses stop their thread in their own destructor, before their loop() is gone.
}

ActivityStats ThreadActivity::stats() const {
  return {steps_.load(std::memory_order_relaxed), overruns_.load(std::memory_order_relaxed),
          max_lateness_ns_.load(std::memory_order_relaxed)};
}

std::string ThreadActivity::schedulerText() const {
  if (scheduler_ == Scheduler::Other) return "SCHED_OTHER";
  std::string text = "SCHED_FIFO priority " + std::to_string(priority_);
  if (running_.load() && effective_.load() != Scheduler::Fifo) text += " (refused: running SCHED_OTHER)";
  return text;
}

void ThreadActivity::applyScheduling() {
  // Linux delays timer wake-ups of SCHED_OTHER threads by up to 50 us to batch them; an
  // activity wants its deadline, so ask for 1 ns of slack.
  prctl(PR_SET_TIMERSLACK, 1UL, 0UL, 0UL, 0UL);
  if (scheduler_ != Scheduler::Fifo) {
    effective_.store(Scheduler::Other);
    return;
  }
  sched_param param{};
  param.sched_priority = priority_;
  const int rc = pthread_setschedparam(pthread_self(), SCHED_FIFO, &param);
  if (rc == 0) {
    effective_.store(Scheduler::Fifo);
    return;
  }
  effective_.store(Scheduler::Other);
  if (!fifo_warning_printed.exchange(true)) {
    std::fprintf(stderr,
                 "[cobra] warning: SCHED_FIFO priority %d refused (%s); activities run SCHED_OTHER without "
                 "real-time guarantees. Grant CAP_SYS_NICE or an rtprio limit (/etc/security/limits.conf) to fix. "
                 "This warning is printed once.\n",
                 priority_, std::strerror(rc));
  }
}

void ThreadActivity::startStepping() {
  if (running_.load()) return;
  // A periodic thread's hand-over ages from its start (its first step is due within a period);
  // an event-driven one's from its first trigger after the start (EventActivity::startStepping).
  serving_since_ns_.store(0, std::memory_order_relaxed);
  if (period().count() > 0) waiting_since_ns_.store(monotonicNow().count(), std::memory_order_relaxed);
  stop_.store(false, std::memory_order_release);
  running_.store(true, std::memory_order_release);
  starts_.fetch_add(1, std::memory_order_acq_rel);
  if (thread_requested_) {
    starts_.notify_one();  // the parked thread steps again
    return;
  }
  thread_requested_ = true;
  if (ActivityLauncher* launcher = ActivityLauncher::running(); realtime_thread && launcher != nullptr &&
                                                                launcher->post(this))
    return;
  createThread();
}

void ThreadActivity::createThread() {
  thread_ = std::thread([this] { serve(); });
  created_.store(true, std::memory_order_release);
  created_.notify_all();
}

void ThreadActivity::serve() {
  thread_id_.store(std::this_thread::get_id(), std::memory_order_release);
  applyScheduling();
  std::uint32_t run = 0;
  for (;;) {
    starts_.wait(run, std::memory_order_acquire);  // parked until the next start (or the end)
    run = starts_.load(std::memory_order_acquire);
    if (exit_.load(std::memory_order_acquire)) break;
    loop();
    parked_.store(run, std::memory_order_release);
    parked_.notify_all();
  }
  thread_id_.store(std::thread::id(), std::memory_order_release);  // before the id can be reused
}

void ThreadActivity::stopStepping() {
  if (!running_.load(std::memory_order_acquire)) return;
  const std::uint32_t run = starts_.load(std::memory_order_acquire);
  stop_.store(true, std::memory_order_release);
  wake();
  // Until the loop of this start returned: from then on no step runs. (A thread still being
  // created by the launcher begins with the stop request set, and parks at once.)
  for (std::uint32_t parked = parked_.load(std::memory_order_acquire); parked != run;
       parked = parked_.load(std::memory_order_acquire))
    parked_.wait(parked, std::memory_order_acquire);
  running_.store(false, std::memory_order_release);
}

std::chrono::nanoseconds ThreadActivity::handoverAge(std::chrono::nanoseconds now) const noexcept {
  if (!running_.load(std::memory_order_acquire)) return std::chrono::nanoseconds(0);
  const std::int64_t waiting = waiting_since_ns_.load(std::memory_order_acquire);
  const std::int64_t serving = serving_since_ns_.load(std::memory_order_acquire);
  const std::int64_t since = serving != 0 && (waiting == 0 || serving < waiting) ? serving : waiting;
  return std::chrono::nanoseconds(since == 0 ? 0 : std::max<std::int64_t>(0, now.count() - since));
}

void ThreadActivity::endThread() {
  stopStepping();
  if (!thread_requested_) return;
  created_.wait(false, std::memory_order_acquire);  // a launcher's creation still under way
  exit_.store(true, std::memory_order_release);
  starts_.fetch_add(1, std::memory_order_acq_rel);
  starts_.notify_one();
  thread_.join();
}

PeriodicActivity::PeriodicActivity(std::chrono::nanoseconds period, int priority, Scheduler scheduler)
    : ThreadActivity(priority, scheduler), period_(period) {
  if (period.count() <= 0) throw Error("a periodic activity needs a period > 0 s, got " + std::to_string(period.count()) + " ns");
}

PeriodicActivity::~PeriodicActivity() { endThread(); }

std::string PeriodicActivity::describe() const { return "periodic " + formatDuration(period_) + ", " + schedulerText(); }

void PeriodicActivity::loop() {
  auto deadline = monotonicNow();
  // What it hands over is as old as its last step's end: from its start until the first.
  waiting_since_ns_.store(deadline.count(), std::memory_order_release);
  while (!stopRequested()) {
    const auto woke = monotonicNow();
    const auto late = (woke - deadline).count();
    if (late > max_lateness_ns_.load(std::memory_order_relaxed)) max_lateness_ns_.store(late, std::memory_order_relaxed);
    stepComponent();
    steps_.fetch_add(1, std::memory_order_relaxed);
    deadline += period_;
    const auto after = monotonicNow();
    waiting_since_ns_.store(after.count(), std::memory_order_release);
    if (after > deadline) {
      // Skip the periods we missed instead of running a burst of late steps.
      const auto missed = (after - deadline) / period_ + 1;
      overruns_.fetch_add(static_cast<std::uint64_t>(missed), std::memory_order_relaxed);
      deadline += missed * period_;
    }
    // Sleep to the absolute deadline, in slices of at most kStopCheck so that a stop request
    // is noticed promptly even with long periods (the deadline itself does not move).
    for (;;) {
      const auto slice_end = std::min(deadline, monotonicNow() + kStopCheck);
      const timespec ts = toTimespec(slice_end);
      while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr) == EINTR) {
      }
      if (slice_end == deadline || stopRequested()) break;
    }
  }
}

EventActivity::EventActivity(int priority, Scheduler scheduler) : ThreadActivity(priority, scheduler) {}

EventActivity::~EventActivity() { endThread(); }

std::string EventActivity::describe() const { return "event-driven, " + schedulerText(); }

void EventActivity::trigger() noexcept {
  // The first trigger nothing has taken yet starts the wait (a later one does not reset it).
  std::int64_t none = 0;
  waiting_since_ns_.compare_exchange_strong(none, monotonicNow().count(), std::memory_order_acq_rel);
  triggers_.fetch_add(1, std::memory_order_release);
  triggers_.notify_one();
}

void EventActivity::startStepping() {
  // Taken before the thread exists: a trigger that arrives while the thread is starting (e.g. a
  // change queued by runBetweenSteps right after start) must still wake it.
  if (hasRunningThread()) return;
  waiting_since_ns_.store(0, std::memory_order_release);  // before the count: a trigger after it ages
  seen_at_start_ = triggers_.load(std::memory_order_acquire);
  ThreadActivity::startStepping();
}

void EventActivity::loop() {
  std::uint32_t seen = seen_at_start_;
  while (!stopRequested()) {
    triggers_.wait(seen, std::memory_order_acquire);
    seen = triggers_.load(std::memory_order_acquire);
    if (stopRequested()) break;
    // The triggers this step takes are answered when it ends: until then their wait goes on.
    serving_since_ns_.store(waiting_since_ns_.exchange(0, std::memory_order_acq_rel), std::memory_order_release);
    stepComponent();
    steps_.fetch_add(1, std::memory_order_relaxed);
    serving_since_ns_.store(0, std::memory_order_release);
  }
}

}  // namespace cobra::core
