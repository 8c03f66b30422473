#include "cobra/core/lockstep_clock.hpp"

#include <algorithm>
#include <chrono>
#include <ctime>
#include <cstdio>
#include <limits>

#include "cobra/core/component.hpp"
#include "cobra/core/error.hpp"

namespace cobra::core {

std::string LockstepActivity::describe() const {
  return period_.count() > 0 ? "lockstep every " + formatDuration(period_) + " of simulated time"
                             : "lockstep, when triggered";
}

std::chrono::nanoseconds LockstepActivity::now() const { return clock_ ? clock_->now() : last_now_; }

void LockstepActivity::trigger() noexcept {
  triggered_.store(true, std::memory_order_release);
  if (period_.count() == 0 && clock_ != nullptr) clock_->trigger_pending_.store(true, std::memory_order_release);
}

bool LockstepActivity::hasRunningThread() const {
  if (clock_ == nullptr) return false;
  const std::thread::id stepping = clock_->steppingThread();
  return stepping != std::thread::id() && stepping != std::this_thread::get_id();
}

bool LockstepActivity::isActivityThread() const {
  return clock_ != nullptr && clock_->steppingThread() == std::this_thread::get_id();
}

LockstepActivity::~LockstepActivity() {
  if (clock_ != nullptr) clock_->forget(this);
}

LockstepClock::~LockstepClock() {
  for (const Entry& e : entries_) {
    e.activity->last_now_ = now();
    e.activity->clock_ = nullptr;
  }
}

void LockstepClock::forget(const LockstepActivity* activity) {
  std::erase_if(entries_, [&](const Entry& e) { return e.activity == activity; });
}

void LockstepClock::add(Component& component, std::chrono::nanoseconds period) {
  if (period.count() < 0) throw Error("lockstep clock: component '" + component.name() + "' needs a period >= 0");
  for (const Entry& e : entries_)
    if (e.component == &component)
      throw Error("lockstep clock: component '" + component.name() + "' is already on this clock");
  auto activity = std::make_unique<LockstepActivity>(*this, period);
  if (period.count() > 0) {
    // First step at the first multiple of the period not before now.
    activity->next_due_ = ((now() + period - std::chrono::nanoseconds(1)) / period) * period;
  }
  LockstepActivity* raw = activity.get();
  component.setActivity(std::move(activity));
  entries_.push_back({&component, raw});
}

void LockstepClock::remove(Component& component) {
  for (const Entry& e : entries_) {
    if (e.component == &component) {
      e.activity->last_now_ = now();
      e.activity->clock_ = nullptr;
    }
  }
  std::erase_if(entries_, [&](const Entry& e) { return e.component == &component; });
}

void LockstepClock::advance(std::chrono::nanoseconds duration) {
  if (duration.count() < 0) throw Error("lockstep clock: cannot advance by a negative duration");
  const auto end = now() + duration;
  // Components triggered from outside the clock (a write by the caller) react first, at now.
  settle(now());
  for (;;) {
    auto next = std::chrono::nanoseconds(std::numeric_limits<std::int64_t>::max());
    for (const Entry& e : entries_)
      if (e.activity->period_.count() > 0) next = std::min(next, e.activity->next_due_);
    if (next >= end) break;
    runInstant(next);
  }
  now_.store(end.count(), std::memory_order_relaxed);
  if (sync_ != nullptr) sync_->reached(end);
}

std::vector<std::pair<const Component*, std::chrono::nanoseconds>> LockstepClock::schedule() const {
  std::vector<std::pair<const Component*, std::chrono::nanoseconds>> out;
  out.reserve(entries_.size());
  for (const Entry& e : entries_) out.emplace_back(e.component, e.activity->period_);
  return out;
}

namespace {
/// CPU time of the calling thread (ns since an arbitrary origin).
std::chrono::nanoseconds threadCpuTime() noexcept {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return std::chrono::seconds(ts.tv_sec) + std::chrono::nanoseconds(ts.tv_nsec);
}
}  // namespace

void LockstepClock::step(const Entry& e) {
  if (!step_observer_) {
    e.activity->stepComponent();
  } else {
    const auto cpu_started = observe_cpu_time_ ? threadCpuTime() : std::chrono::nanoseconds(0);
    const auto started = std::chrono::steady_clock::now();
    e.activity->stepComponent();
    const auto wall = std::chrono::steady_clock::now() - started;
    step_observer_(*e.component, wall, observe_cpu_time_ ? threadCpuTime() - cpu_started : std::chrono::nanoseconds(0));
  }
  ++steps_;
}

void LockstepClock::runInstant(std::chrono::nanoseconds t) {
  now_.store(t.count(), std::memory_order_relaxed);
  for (const Entry& e : entries_) {
    LockstepActivity& a = *e.activity;
    if (a.period_.count() > 0 && a.next_due_ == t) {
      a.next_due_ += a.period_;
      a.triggered_.store(false, std::memory_order_relaxed);
      step(e);
    }
  }
  settle(t);
}

void LockstepClock::settle(std::chrono::nanoseconds t) {
  runTriggered(t);
  for (int round = 0; between_instants_ && round < kMaxTriggerRounds; ++round) {
    if (!between_instants_()) return;
    runTriggered(t);
  }
}

void LockstepClock::runTriggered(std::chrono::nanoseconds t) {
  // Event-driven components react in the same instant, in the order they were added, until
  // no more triggers arrive.
  for (int round = 0; round < kMaxTriggerRounds; ++round) {
    // No event-driven component was triggered since the last scan.
    if (!trigger_pending_.exchange(false, std::memory_order_acq_rel)) return;
    bool any = false;
    for (const Entry& e : entries_) {
      LockstepActivity& a = *e.activity;
      if (a.period_.count() == 0 && a.triggered_.exchange(false, std::memory_order_acq_rel)) {
        step(e);
        any = true;
      }
    }
    if (!any) return;
  }
  throw Error("lockstep clock: event-driven components kept triggering each other for " +
              std::to_string(kMaxTriggerRounds) + " rounds at t = " + std::to_string(t.count()) +
              " ns; look for a cycle of event ports");
}

}  // namespace cobra::core
