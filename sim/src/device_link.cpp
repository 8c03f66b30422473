#include "cobra/sim/device_link.hpp"

#include <thread>

namespace cobra::sim {

void DeviceLink::attach(Clock clock) {
  clock_ = std::move(clock);
  state_.store(clock_ ? kAttached : kDirect, std::memory_order_seq_cst);
}

void DeviceLink::detach() noexcept {
  state_.store(kDetached, std::memory_order_seq_cst);
  // A host call that saw the link up may still be reading the clock: wait for it (a few
  // instructions; the world side is not real-time).
  while (in_flight_.load(std::memory_order_seq_cst) != 0) std::this_thread::yield();
}

LinkTime DeviceLink::worldTime() const noexcept {
  if (state_.load(std::memory_order_acquire) != kAttached) return {};
  return {true, clock_()};
}

DeviceLink::Access::Access(DeviceLink& link) noexcept : link_(link) {
  // seq_cst on both sides (increment here, then read the state; store the state in detach, then
  // read the count): either this call sees the link detached, or detach waits for it.
  link_.in_flight_.fetch_add(1, std::memory_order_seq_cst);
  const int state = link_.state_.load(std::memory_order_seq_cst);
  up_ = state != kDetached;
  if (state == kAttached) time_ = {true, link_.clock_()};
}

DeviceLink::Access::~Access() { link_.in_flight_.fetch_sub(1, std::memory_order_seq_cst); }

}  // namespace cobra::sim
