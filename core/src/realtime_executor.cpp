#include "cobra/core/realtime_executor.hpp"

#include <malloc.h>
#include <pthread.h>
#include <sched.h>
#include <sys/mman.h>
#include <sys/prctl.h>
#include <time.h>

#include <algorithm>
#include <bit>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "cobra/core/component.hpp"
#include "cobra/core/error.hpp"
#include "cobra/core/lockstep_clock.hpp"

namespace cobra::core {

// --- DurationHistogram -----------------------------------------------------------------------

std::size_t DurationHistogram::bucketOf(std::int64_t ns) noexcept {
  if (ns < (1 << kSubBits)) return static_cast<std::size_t>(std::max<std::int64_t>(ns, 0));
  const auto v = static_cast<std::uint64_t>(ns);
  const int octave = static_cast<int>(std::bit_width(v)) - 1;  // >= kSubBits
  const int shift = octave - kSubBits;
  const std::size_t sub = static_cast<std::size_t>((v >> shift) & ((1u << kSubBits) - 1));
  const std::size_t bucket = (static_cast<std::size_t>(shift + 1) << kSubBits) + sub;
  return std::min(bucket, kBuckets - 1);
}

std::int64_t DurationHistogram::upperEdge(std::size_t bucket) noexcept {
  if (bucket < (1u << kSubBits)) return static_cast<std::int64_t>(bucket);
  const std::size_t shift = (bucket >> kSubBits) - 1;
  const std::uint64_t sub = bucket & ((1u << kSubBits) - 1);
  return static_cast<std::int64_t>((((1ull << kSubBits) + sub + 1) << shift) - 1);
}

void DurationHistogram::add(std::int64_t ns) noexcept {
  auto& bucket = buckets_[bucketOf(ns)];
  // One writer: a load and a store, not a locked read-modify-write.
  bucket.store(bucket.load(std::memory_order_relaxed) + 1, std::memory_order_relaxed);
  count_.store(count_.load(std::memory_order_relaxed) + 1, std::memory_order_relaxed);
  if (ns > max_.load(std::memory_order_relaxed)) max_.store(ns, std::memory_order_relaxed);
}

std::int64_t DurationHistogram::quantile(double q) const noexcept {
  const std::uint64_t total = count();
  if (total == 0) return 0;
  const auto rank = static_cast<std::uint64_t>(std::ceil(q * static_cast<double>(total)));
  std::uint64_t seen = 0;
  for (std::size_t b = 0; b < kBuckets; ++b) {
    seen += buckets_[b].load(std::memory_order_relaxed);
    if (seen >= std::max<std::uint64_t>(rank, 1)) return std::min(upperEdge(b), max());
  }
  return max();
}

void DurationHistogram::reset() noexcept {
  for (auto& b : buckets_) b.store(0, std::memory_order_relaxed);
  count_.store(0, std::memory_order_relaxed);
  max_.store(0, std::memory_order_relaxed);
}

DurationFigures figuresOf(const DurationHistogram& h) {
  const auto s = [](std::int64_t ns) { return static_cast<double>(ns) * 1e-9; };
  return {h.count(), s(h.quantile(0.5)), s(h.quantile(0.99)), s(h.quantile(0.999)), s(h.max())};
}

// --- RealtimeExecutor ------------------------------------------------------------------------

namespace {

timespec toTimespec(std::chrono::nanoseconds t) {
  timespec ts{};
  ts.tv_sec = static_cast<time_t>(t.count() / 1'000'000'000);
  ts.tv_nsec = static_cast<long>(t.count() % 1'000'000'000);
  return ts;
}

/// Sleeps until `deadline` (CLOCK_MONOTONIC, absolute): a late wake-up does not shift the next.
void sleepUntil(std::chrono::nanoseconds deadline) noexcept {
  const timespec ts = toTimespec(deadline);
  while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr) == EINTR) {
  }
}

/// Touches `bytes` of stack now, so that the first deep call of a tick does not page-fault.
void prefaultStack() noexcept {
  constexpr std::size_t bytes = 256 * 1024;
  unsigned char stack[bytes];
  std::memset(stack, 0, bytes);
  asm volatile("" : : "r"(stack) : "memory");  // the writes stay: the compiler sees the stack used
}

}  // namespace

RealtimeExecutor::RealtimeExecutor(LockstepClock& clock, ExecutorOptions options)
    : clock_(clock), options_(std::move(options)), watches_(new Watch[kMaxWatches]) {
  if (options_.period.count() <= 0)
    throw Error("real-time executor: the period must be > 0 s, got " + formatDuration(options_.period));
  if (options_.scheduler == Scheduler::Fifo && (options_.priority < 1 || options_.priority > 99))
    throw Error("real-time executor: SCHED_FIFO priority must be in 1..99, got " + std::to_string(options_.priority));
  if (options_.cpu < -1) throw Error("real-time executor: cpu must be -1 (any) or a CPU number, got " + std::to_string(options_.cpu));
  if (options_.max_catch_up_ticks < 1) options_.max_catch_up_ticks = 1;
}

RealtimeExecutor::~RealtimeExecutor() { stop(); }

void RealtimeExecutor::warn(std::string text) {
  std::fprintf(stderr, "[cobra] warning: %s\n", text.c_str());
  const std::lock_guard lock(warnings_mutex_);
  warnings_.push_back(std::move(text));
}

std::vector<std::string> RealtimeExecutor::warnings() const {
  const std::lock_guard lock(warnings_mutex_);
  return warnings_;
}

void RealtimeExecutor::start() {
  if (running_.load()) return;
  const auto schedule = clock_.schedule();
  for (const auto& [component, period] : schedule)
    if (period.count() > 0 && period % options_.period != std::chrono::nanoseconds(0))
      throw Error("real-time executor: component '" + component->name() + "' has period " + formatDuration(period) +
                  ", not a multiple of the executor's period " + formatDuration(options_.period));
  slot_count_ = schedule.size() + kSpareSlots;
  slots_ = std::make_unique<Slot[]>(slot_count_);
  for (std::size_t i = 0; i < schedule.size(); ++i) slots_[i].component.store(schedule[i].first);
  slots_used_.store(schedule.size());
  next_slot_ = 0;
  if (options_.lock_memory) {
    // With every page locked, a heap that shrinks and grows again would map and populate pages at
    // every turn (system time, and the mm lock every thread's faults take): keep what it has.
    mallopt(M_TRIM_THRESHOLD, -1);
    mallopt(M_MMAP_MAX, 0);
    if (mlockall(MCL_CURRENT | MCL_FUTURE) == 0) memory_locked_.store(true);
    else
      warn(std::string("mlockall refused (") + std::strerror(errno) +
           "): the run's memory may be paged out and stall a tick; grant CAP_IPC_LOCK or raise the memlock limit "
           "(/etc/security/limits.conf)");
  }
  clock_.setStepObserver([this](const Component& c, std::chrono::nanoseconds wall, std::chrono::nanoseconds) {
    onStep(c, wall);
  }, false);
  // Own-pace components started by a deployment switch between two ticks get their threads from
  // the launcher, not from this thread (activity.hpp, markRealtimeThread).
  startActivityLauncher();
  stop_.store(false);
  running_.store(true, std::memory_order_release);
  std::atomic<bool> ready{false};
  thread_ = std::thread([this, &ready] {
    clock_.setSteppingThread(std::this_thread::get_id());
    markRealtimeThread(true);
    applyScheduling();
    prefaultStack();
    ready.store(true, std::memory_order_release);
    ready.notify_one();
    loop();
    clock_.setSteppingThread(std::thread::id());
  });
  ready.wait(false, std::memory_order_acquire);  // from here on other threads queue their work
}

void RealtimeExecutor::stop() {
  if (!thread_.joinable()) return;
  stop_.store(true, std::memory_order_release);
  thread_.join();
  running_.store(false, std::memory_order_release);
  clock_.setStepObserver(nullptr);
  // Work queued after the last tick runs here: the thread no longer takes it.
  takeWork();
}

void RealtimeExecutor::applyScheduling() {
  // A timer wake-up of a SCHED_OTHER thread may be delayed up to 50 us to batch it: ask for 1 ns.
  prctl(PR_SET_TIMERSLACK, 1UL, 0UL, 0UL, 0UL);
  if (options_.cpu >= 0) {
    cpu_set_t set;
    CPU_ZERO(&set);
    CPU_SET(options_.cpu, &set);
    if (const int rc = pthread_setaffinity_np(pthread_self(), sizeof set, &set); rc != 0)
      warn("CPU affinity to CPU " + std::to_string(options_.cpu) + " refused (" + std::strerror(rc) +
           "): the executor runs on any CPU");
  }
  if (options_.scheduler != Scheduler::Fifo) return;
  sched_param param{};
  param.sched_priority = options_.priority;
  if (const int rc = pthread_setschedparam(pthread_self(), SCHED_FIFO, &param); rc != 0) {
    warn("SCHED_FIFO priority " + std::to_string(options_.priority) + " refused (" + std::strerror(rc) +
         "): the executor runs SCHED_OTHER without real-time guarantees; grant CAP_SYS_NICE or an rtprio limit "
         "(/etc/security/limits.conf)");
    return;
  }
  effective_.store(Scheduler::Fifo);
}

void RealtimeExecutor::onStep(const Component& component, std::chrono::nanoseconds wall) noexcept {
  const std::size_t used = slots_used_.load(std::memory_order_relaxed);
  std::size_t found = slot_count_;
  if (next_slot_ < used && slots_[next_slot_].component.load(std::memory_order_relaxed) == &component) {
    found = next_slot_;
  } else {
    for (std::size_t i = 0; i < used; ++i)
      if (slots_[i].component.load(std::memory_order_relaxed) == &component) {
        found = i;
        break;
      }
    if (found == slot_count_ && used < slot_count_) {  // a component a switch added
      slots_[used].component.store(&component, std::memory_order_relaxed);
      slots_used_.store(used + 1, std::memory_order_release);
      found = used;
    }
  }
  stepped_ns_ += wall.count();
  if (found == slot_count_) return;  // more new components than spare slots: not timed
  slots_[found].compute.add(wall.count());
  next_slot_ = found + 1;
}

void RealtimeExecutor::takeWork() noexcept {
  Work* work = work_.exchange(nullptr, std::memory_order_acq_rel);
  if (work == nullptr) return;
  const auto started = monotonicNow();
  try {
    (*work->work)();
  } catch (...) {
    work->error = std::current_exception();
  }
  work_time_.add((monotonicNow() - started).count());
  work->done.store(true, std::memory_order_release);
  work->done.notify_one();
}

void RealtimeExecutor::runBetweenTicks(const std::function<void()>& work) {
  const std::lock_guard lock(callers_);
  if (!running_.load(std::memory_order_acquire) || clock_.steppingThread() == std::this_thread::get_id()) {
    work();
    return;
  }
  Work pending{&work, nullptr};
  work_.store(&pending, std::memory_order_release);
  // The thread may be stopping: stop() takes what is left after joining it.
  pending.done.wait(false, std::memory_order_acquire);
  if (pending.error) std::rethrow_exception(pending.error);
}

void RealtimeExecutor::loop() {
  const auto period = options_.period;
  // Run time 0 is the clock's now at the first tick: threads beside the clock read the same time.
  auto deadline = monotonicNow() + period;
  setRunEpoch(deadline - clock_.now());
  std::uint64_t consecutive = 0;
  while (!stop_.load(std::memory_order_acquire)) {
    sleepUntil(deadline);
    const auto woke = monotonicNow();
    latency_.add((woke - deadline).count());
    if (stop_.load(std::memory_order_acquire)) break;
    takeWork();
    const auto advancing = monotonicNow();
    stepped_ns_ = 0;
    clock_.advance(period);
    const auto done = monotonicNow();
    checkHandovers(done);
    compute_.add((done - woke).count());
    between_steps_.add((done - advancing).count() - stepped_ns_);
    ticks_.fetch_add(1, std::memory_order_relaxed);
    deadline += period;
    if (done <= deadline) {
      consecutive = 0;
      continue;
    }
    // The tick ended after the next one was due: a miss. The next ticks run at once to catch up
    // (the schedule stays the lockstep one), unless the stall was so long that catching up would
    // run a burst of ticks: then the deadlines and the run's epoch slip by the time lost.
    misses_.fetch_add(1, std::memory_order_relaxed);
    ++consecutive;
    if (consecutive > worst_consecutive_.load(std::memory_order_relaxed))
      worst_consecutive_.store(consecutive, std::memory_order_relaxed);
    const auto behind = done - deadline;
    if (behind > options_.max_catch_up_ticks * period) {
      const auto slip = (behind / period) * period;
      deadline += slip;
      slipped_ns_.fetch_add(slip.count(), std::memory_order_relaxed);
      setRunEpoch(runEpoch() + slip);
    }
    // The events after the slip: their stamps (run time read beside the clock) then stay within
    // max_catch_up_ticks of the clock's time, as every other event's (a stamp taken before a
    // slip was the stall's length ahead of the instant the run observed the event at).
    if (consecutive == 1 && options_.policy.emit_event && options_.on_event) options_.on_event("e_deadline_missed");
    if (options_.policy.safe_stop_after > 0 && consecutive == static_cast<std::uint64_t>(options_.policy.safe_stop_after)) {
      safe_stop_.store(true, std::memory_order_release);
      if (options_.on_event) options_.on_event("e_deadline_safe_stop");
    }
  }
}

void RealtimeExecutor::watchHandover(const Component& component, std::chrono::nanoseconds max_age) {
  // The message is made only for an error: between ticks this runs on the executor's thread.
  const auto head = [&] { return "real-time executor: watching the hand-over of '" + component.name() + "': "; };
  if (running() && clock_.steppingThread() != std::this_thread::get_id())
    throw Error(head() + "called from another thread while the executor runs; watch before start or between ticks");
  if (max_age.count() <= 0) throw Error(head() + "max_age must be > 0 s, got " + formatDuration(max_age));
  const std::size_t used = watch_count_.load(std::memory_order_acquire);
  for (std::size_t i = 0; i < used; ++i)
    if (watches_[i].component.load(std::memory_order_relaxed) == &component) {
      watches_[i].max_age_ns.store(max_age.count(), std::memory_order_relaxed);
      return;
    }
  if (used == kMaxWatches)
    throw Error(head() + "the executor watches " + std::to_string(kMaxWatches) + " own-pace components already");
  Watch& watch = watches_[used];
  std::snprintf(watch.event, sizeof watch.event, "e_handover_stale_%s", component.name().c_str());
  watch.max_age_ns.store(max_age.count(), std::memory_order_relaxed);
  watch.component.store(&component, std::memory_order_relaxed);
  watch_count_.store(used + 1, std::memory_order_release);
}

void RealtimeExecutor::checkHandovers(std::chrono::nanoseconds now) noexcept {
  const std::size_t used = watch_count_.load(std::memory_order_acquire);
  for (std::size_t i = 0; i < used; ++i) {
    Watch& watch = watches_[i];
    // A switch may give the component another activity, between ticks on this thread: asked here.
    const Component& component = *watch.component.load(std::memory_order_relaxed);
    const std::int64_t age = component.activity().handoverAge(now).count();
    if (age > watch.worst_ns.load(std::memory_order_relaxed)) watch.worst_ns.store(age, std::memory_order_relaxed);
    const bool stale = age > watch.max_age_ns.load(std::memory_order_relaxed);
    if (stale && !watch.is_stale) {
      watch.stale.fetch_add(1, std::memory_order_relaxed);
      if (options_.on_event) options_.on_event(watch.event);
    }
    watch.is_stale = stale;
  }
}

std::vector<HandoverFigures> RealtimeExecutor::handoverFigures() const {
  std::vector<HandoverFigures> out;
  const std::size_t used = watch_count_.load(std::memory_order_acquire);
  for (std::size_t i = 0; i < used; ++i) {
    const Watch& watch = watches_[i];
    out.push_back({watch.component.load(std::memory_order_relaxed)->name(),
                   static_cast<double>(watch.max_age_ns.load(std::memory_order_relaxed)) * 1e-9,
                   static_cast<double>(watch.worst_ns.load(std::memory_order_relaxed)) * 1e-9,
                   watch.stale.load(std::memory_order_relaxed)});
  }
  return out;
}

std::vector<ComponentTiming> RealtimeExecutor::componentTimings() const {
  std::vector<ComponentTiming> out;
  const std::size_t used = slots_used_.load(std::memory_order_acquire);
  for (std::size_t i = 0; i < used; ++i) {
    const Component* c = slots_[i].component.load(std::memory_order_relaxed);
    if (c == nullptr) continue;
    out.push_back({c->name(), figuresOf(slots_[i].compute)});
  }
  return out;
}

}  // namespace cobra::core
