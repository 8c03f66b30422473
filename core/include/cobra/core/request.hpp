#pragma once
/// @file
/// A void request operation answered in its component's own next step (ARCHITECTURE §2: supervisors
/// ask with void requests such as askPlan(), components answer with events).

#include <atomic>

#include "cobra/core/activity.hpp"

namespace cobra::core {

/// The pending flag of one request. The operation (registered with ExecutionThread::Client)
/// calls ask(): from any thread, it marks the request and wakes the component's activity, without
/// waiting for the component, so a supervisor's step never pays for its peer's work nor waits
/// for its peer's period. The component's updateHook calls take() and does the work there, in
/// its own thread; a request asked twice before that step is answered once.
/// Real time: ask and take allocate nothing, block on nothing and throw nothing.
class PendingRequest {
 public:
  void ask(Activity& activity) noexcept {
    asked_.store(true, std::memory_order_release);
    activity.trigger();
  }
  /// True (once) if asked since the last take.
  bool take() noexcept { return asked_.exchange(false, std::memory_order_acq_rel); }
  /// Forgets a request not taken yet (e.g. one asked before the component was started).
  void clear() noexcept { asked_.store(false, std::memory_order_relaxed); }

 private:
  std::atomic<bool> asked_{false};
};

}  // namespace cobra::core
