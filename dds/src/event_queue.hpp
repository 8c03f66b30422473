#pragma once
// A bounded lock-free queue of events from any number of foreign threads (Fast DDS's listener
// threads, the lockstep clock's thread) to one consumer: the DdsLink's own step, which writes
// them on its `events` port, so that port keeps the single-writer contract of cobra's ports
// (core/channel.hpp: one writer thread per connection). Private to cobra_dds.
//
// Dmitry Vyukov's bounded queue: each cell carries a sequence number that says whose turn it
// is (a producer's when it equals the ticket it took, the consumer's one past it). Producers
// take tickets with a compare-and-swap on one counter and never wait for each other beyond
// that; the consumer touches only cells and its own index. Neither side allocates, locks or
// throws; a full queue refuses the event (push returns false) and counts it.

#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>

#include "cobra/core/event.hpp"

namespace cobra::dds::detail {

template <std::size_t Capacity>
class EventQueue {
  static_assert(Capacity >= 2 && (Capacity & (Capacity - 1)) == 0, "Capacity must be a power of two");

 public:
  EventQueue() noexcept {
    for (std::size_t i = 0; i < Capacity; ++i) cells_[i].sequence.store(i, std::memory_order_relaxed);
  }
  EventQueue(const EventQueue&) = delete;
  EventQueue& operator=(const EventQueue&) = delete;

  /// Any thread. False (and the event counted as dropped) when `Capacity` events wait already.
  bool push(const core::Event& event) noexcept {
    std::size_t ticket = enqueue_.load(std::memory_order_relaxed);
    while (true) {
      Cell& cell = cells_[ticket & (Capacity - 1)];
      const std::size_t sequence = cell.sequence.load(std::memory_order_acquire);
      const auto turn = static_cast<std::intptr_t>(sequence) - static_cast<std::intptr_t>(ticket);
      if (turn == 0) {
        if (enqueue_.compare_exchange_weak(ticket, ticket + 1, std::memory_order_relaxed)) {
          cell.event = event;
          cell.sequence.store(ticket + 1, std::memory_order_release);
          return true;
        }
      } else if (turn < 0) {  // the cell still holds the event of one lap ago: full
        dropped_.fetch_add(1, std::memory_order_relaxed);
        return false;
      } else {  // another producer took this ticket
        ticket = enqueue_.load(std::memory_order_relaxed);
      }
    }
  }

  /// The one consumer thread only. False when empty.
  bool pop(core::Event& out) noexcept {
    Cell& cell = cells_[dequeue_ & (Capacity - 1)];
    if (cell.sequence.load(std::memory_order_acquire) != dequeue_ + 1) return false;
    out = cell.event;
    cell.sequence.store(dequeue_ + Capacity, std::memory_order_release);
    ++dequeue_;
    return true;
  }

  /// Events refused because the queue was full, since it was made (any thread).
  std::uint64_t dropped() const noexcept { return dropped_.load(std::memory_order_relaxed); }

 private:
  struct Cell {
    std::atomic<std::size_t> sequence{0};
    core::Event event;
  };
  std::array<Cell, Capacity> cells_;
  alignas(64) std::atomic<std::size_t> enqueue_{0};
  alignas(64) std::size_t dequeue_ = 0;  // the consumer's
  std::atomic<std::uint64_t> dropped_{0};
};

}  // namespace cobra::dds::detail
