#pragma once
/// @file
/// Per-reason counters of received frames (accepted = the `Ok` slot), lock-free, written by one
/// receiver thread and read by anyone, usable in shared memory (zero bits = all zero).

#include <array>
#include <atomic>
#include <cstdint>

#include "cobra/bridges/wire.hpp"

namespace cobra::bridges {

struct ReceiveCounters {
  std::array<std::atomic<std::uint64_t>, wire::kDecodeStatusCount> by_status{};

  /// Counts one frame with outcome `status`. Single writer: a relaxed load + store, no RMW needed.
  void count(wire::DecodeStatus status) noexcept {
    auto& c = by_status[static_cast<std::size_t>(status)];
    c.store(c.load(std::memory_order_relaxed) + 1, std::memory_order_relaxed);
  }
  std::uint64_t get(wire::DecodeStatus status) const noexcept {
    return by_status[static_cast<std::size_t>(status)].load(std::memory_order_relaxed);
  }
  std::uint64_t accepted() const noexcept { return get(wire::DecodeStatus::Ok); }
  /// Sum over every rejection reason.
  std::uint64_t rejected() const noexcept {
    std::uint64_t sum = 0;
    for (std::size_t i = 1; i < by_status.size(); ++i) sum += by_status[i].load(std::memory_order_relaxed);
    return sum;
  }
};

}  // namespace cobra::bridges
