#pragma once
/// @file
/// cobra's one bounded lock-free single-producer single-consumer ring. The `buffer(n)` and
/// `circular(n)` connections (`core/channel.hpp`) pass their slots through two of them, as the
/// Reporter passes its CSV rows to its file writer thread; the studio queues a run's events and
/// its inputs through them.

#include <atomic>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <type_traits>

namespace cobra::core {

/// What `push` does when the ring is full.
enum class RingOverflow {
  Refuse,       ///< push returns false; the item is not queued.
  EvictOldest,  ///< `pushEvicting` takes the oldest item away from the consumer and queues the new one.
};

/// Bounded FIFO queue between one producer thread and one consumer thread.
///
/// Contract:
/// - One thread pushes, one thread pops (the same or different ones); nothing else is safe.
/// - Lock-free and wait-free for both sides with `Refuse`; with `EvictOldest` the consumer's
///   `pop` is lock-free (it retries only when the producer evicted the item it was taking).
/// - No allocation after construction: the `capacity` items are allocated once, by the
///   constructor, and items are copied in and out (T is trivially copyable).
/// - Items come out in the order they went in, each exactly once, never torn.
///
/// Memory ordering: the producer writes the item, then advances `tail` with release; the consumer
/// reads `tail` with acquire before reading the item, then advances `head` with release (acq_rel
/// compare-and-swap with `EvictOldest`), which the producer reads with acquire before it writes
/// that cell again. Head and tail are free-running 64-bit counters (no wrap in practice), each on
/// a cache line of its own.
///
/// With `EvictOldest` both sides may advance `head`, so the consumer and an evicting producer
/// may read the same cell at once while the producer later writes it: the cells are then
/// `std::atomic<T>` (T must be lock-free atomic, e.g. an index) and accessed relaxed.
template <class T, RingOverflow Overflow = RingOverflow::Refuse>
class SpscRing {
  static_assert(std::is_trivially_copyable_v<T>, "SpscRing copies items between threads: T must be trivially copyable");
  static constexpr bool kEvicting = Overflow == RingOverflow::EvictOldest;
  static_assert(!kEvicting || std::atomic<T>::is_always_lock_free,
                "an evicting SpscRing's items are read by both sides: T must be a lock-free atomic type (an index)");
  using Cell = std::conditional_t<kEvicting, std::atomic<T>, T>;

 public:
  /// A ring that holds up to `capacity` items (at least 1).
  explicit SpscRing(std::size_t capacity)
      : capacity_(capacity < 1 ? 1 : capacity), mask_(std::bit_ceil(capacity_) - 1), cells_(new Cell[mask_ + 1]()) {}
  SpscRing(const SpscRing&) = delete;
  SpscRing& operator=(const SpscRing&) = delete;

  std::size_t capacity() const noexcept { return capacity_; }

  /// Producer: queues `item`; false (nothing queued) when the ring is full.
  bool push(const T& item) noexcept {
    const std::uint64_t tail = tail_.load(std::memory_order_relaxed);
    if (tail - head_.load(std::memory_order_acquire) >= capacity_) return false;
    store(tail, item);
    tail_.store(tail + 1, std::memory_order_release);
    return true;
  }

  /// Producer, `EvictOldest` only: queues `item`, first taking the oldest item away when the ring
  /// is full. Returns true and sets `evicted` to that item when one was taken; false when there
  /// was room (the consumer may have taken the oldest one first).
  bool pushEvicting(const T& item, T& evicted) noexcept
    requires kEvicting
  {
    const std::uint64_t tail = tail_.load(std::memory_order_relaxed);
    std::uint64_t head = head_.load(std::memory_order_acquire);
    bool took = false;
    if (tail - head >= capacity_) {
      const T oldest = cells_[head & mask_].load(std::memory_order_relaxed);
      // Whoever advances head owns the item; on failure the consumer took it and there is room.
      if (head_.compare_exchange_strong(head, head + 1, std::memory_order_acq_rel)) {
        evicted = oldest;
        took = true;
      }
    }
    store(tail, item);
    tail_.store(tail + 1, std::memory_order_release);
    return took;
  }

  /// Consumer: takes the oldest item into `item`; false (item untouched) when the ring is empty.
  bool pop(T& item) noexcept {
    if constexpr (kEvicting) {
      std::uint64_t head = head_.load(std::memory_order_acquire);
      for (;;) {
        if (tail_.load(std::memory_order_acquire) == head) return false;
        const T value = cells_[head & mask_].load(std::memory_order_relaxed);
        // On failure `head` is reloaded: the producer evicted this item, try the next one.
        if (head_.compare_exchange_weak(head, head + 1, std::memory_order_acq_rel, std::memory_order_acquire)) {
          item = value;
          return true;
        }
      }
    } else {
      const std::uint64_t head = head_.load(std::memory_order_relaxed);
      if (tail_.load(std::memory_order_acquire) == head) return false;
      item = cells_[head & mask_];
      head_.store(head + 1, std::memory_order_release);
      return true;
    }
  }

  /// Items queued: exact for either side when the other is idle, approximate while it works.
  std::size_t size() const noexcept {
    const std::uint64_t head = head_.load(std::memory_order_acquire);
    const std::uint64_t tail = tail_.load(std::memory_order_acquire);
    return tail > head ? static_cast<std::size_t>(tail - head) : 0;
  }
  bool empty() const noexcept { return size() == 0; }

 private:
  void store(std::uint64_t tail, const T& item) noexcept {
    if constexpr (kEvicting) {
      cells_[tail & mask_].store(item, std::memory_order_relaxed);
    } else {
      cells_[tail & mask_] = item;
    }
  }

  const std::size_t capacity_;
  // The cells are a power of two (at least capacity_), so that an index is a mask, not a division
  // (the divisions made a buffer(n) connection's write and read of a double about 4 ns slower,
  // bench/type_paths_bench); the ring still holds at most capacity_ items.
  const std::size_t mask_;
  const std::unique_ptr<Cell[]> cells_;
  alignas(64) std::atomic<std::uint64_t> head_{0};  // advanced by the consumer (and an evicting producer)
  alignas(64) std::atomic<std::uint64_t> tail_{0};  // advanced by the producer
};

}  // namespace cobra::core
