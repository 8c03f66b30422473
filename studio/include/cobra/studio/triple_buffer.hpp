#pragma once
/// @file
/// A wait-free triple buffer: one writer publishes whole values, one reader takes the newest.
/// Neither ever waits for the other, and nothing allocates after construction: the writer fills
/// its own buffer, then swaps it with the middle one; the reader swaps the middle one with its own
/// when it is newer. (A seqlock would make the reader retry while the writer writes; here the
/// reader never retries and the values may hold vectors sized once at construction.)

#include <atomic>
#include <cstdint>

namespace cobra::studio {

template <class T>
class TripleBuffer {
 public:
  /// Every buffer starts as `initial` (its vectors sized: writing into them then never allocates).
  explicit TripleBuffer(const T& initial) : buffers_{initial, initial, initial} {}

  /// The writer's buffer, to fill before publish().
  T& back() { return buffers_[back_]; }
  /// Makes the back buffer the newest value. Wait-free, allocation-free.
  void publish() {
    const std::uint8_t old = middle_.exchange(static_cast<std::uint8_t>(back_ | kFresh), std::memory_order_acq_rel);
    back_ = old & kIndex;
  }

  /// Takes the newest value published since the last call; false (and nothing changes) when none.
  bool update() {
    if ((middle_.load(std::memory_order_relaxed) & kFresh) == 0) return false;
    const std::uint8_t old = middle_.exchange(front_, std::memory_order_acq_rel);
    front_ = old & kIndex;
    return true;
  }
  /// The reader's value (the newest as of the last update()).
  const T& front() const { return buffers_[front_]; }

 private:
  static constexpr std::uint8_t kIndex = 3, kFresh = 4;
  T buffers_[3];
  std::uint8_t back_ = 0, front_ = 1;      // each owned by one side
  std::atomic<std::uint8_t> middle_{2};    // index | kFresh when published and not yet taken
};

}  // namespace cobra::studio
