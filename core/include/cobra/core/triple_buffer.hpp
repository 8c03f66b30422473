#pragma once
/// @file
/// cobra's one wait-free triple buffer: a writer publishes whole values, a reader takes the
/// newest. The `data` policy of every port connection (`core/channel.hpp`) and the studio's
/// snapshots of a run are this class.

#include <atomic>
#include <cstdint>

namespace cobra::core {

/// Wait-free single-writer single-reader "latest value" cell.
///
/// Contract:
/// - One writer thread calls `back()` and `publish()`; one reader thread calls `update()`,
///   `front()` and `hasUnread()`. The two may be different threads, or the same one.
/// - Neither side ever waits for, retries against or blocks the other: each call is a bounded
///   number of instructions and at most one atomic exchange.
/// - No allocation after construction: the three buffers are copies of the value given to the
///   constructor, and each is only ever written in place (a `std::vector` sized at construction
///   and filled element by element never reallocates). T's own assignment decides the rest.
/// - The reader never sees a value while it is written (no torn values, whatever T is), and
///   never an older value after a newer one; values published between two `update()` calls
///   are skipped (only the newest counts).
///
/// How: the writer fills its own *back* buffer, then exchanges it with the *middle* one, setting
/// a "fresh" bit in the same word; the reader exchanges its *front* buffer with the middle one
/// only when that bit is set. One shared word per transfer: the exchange is acq_rel, so the
/// writer's writes to the buffer it hands over happen before the reader's reads of it, and the
/// reader's last reads of the buffer it hands back happen before the writer writes it again.
/// (A seqlock would make the reader retry while the writer writes; here neither retries.)
template <class T>
class TripleBuffer {
 public:
  /// Every buffer starts as a copy of `initial` (which sizes what it holds).
  explicit TripleBuffer(const T& initial) : buffers_{{initial}, {initial}, {initial}} {}
  TripleBuffer(const TripleBuffer&) = delete;
  TripleBuffer& operator=(const TripleBuffer&) = delete;

  /// Writer: its buffer, to fill before `publish()`. It holds some earlier value, not
  /// necessarily the last one published.
  T& back() noexcept { return buffers_[back_].value; }
  /// Writer: makes the back buffer the newest value (one atomic exchange, acq_rel).
  void publish() noexcept {
    back_ = middle_.exchange(static_cast<std::uint8_t>(back_ | kFresh), std::memory_order_acq_rel) & kIndex;
  }
  /// Writer: copies `value` into the back buffer and publishes it.
  void write(const T& value) {
    back() = value;
    publish();
  }

  /// Reader: takes the newest value published since the last call; false (and `front()` stays
  /// as it was) when none was.
  bool update() noexcept {
    // Relaxed is enough for the test: the exchange below is the acquire that matters.
    if ((middle_.load(std::memory_order_relaxed) & kFresh) == 0) return false;
    front_ = middle_.exchange(front_, std::memory_order_acq_rel) & kIndex;
    return true;
  }
  /// Reader: the value taken by the last successful `update()` (the constructor's before any).
  const T& front() const noexcept { return buffers_[front_].value; }
  /// Either side: whether a value was published that the reader has not taken yet (a hint for
  /// the writer; exact for the reader).
  bool hasUnread() const noexcept { return (middle_.load(std::memory_order_acquire) & kFresh) != 0; }

 private:
  static constexpr std::uint8_t kIndex = 3, kFresh = 4;
  // Each buffer on cache lines of its own: the writer filling one never invalidates the line the
  // reader is copying from.
  struct alignas(64) Buffer {
    T value;
  };
  Buffer buffers_[3];
  alignas(64) std::uint8_t back_ = 0;     // writer only
  alignas(64) std::uint8_t front_ = 1;    // reader only
  alignas(64) std::atomic<std::uint8_t> middle_{2};  // index of the middle buffer | kFresh when unread
};

}  // namespace cobra::core
