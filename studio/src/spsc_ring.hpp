#pragma once
// A bounded single-producer single-consumer queue of trivially copyable items: push and pop
// never wait and never allocate (a full queue refuses the item). Private to cobra::studio.

#include <array>
#include <atomic>
#include <cstddef>
#include <type_traits>

namespace cobra::studio {

template <class T, std::size_t Capacity>
class SpscRing {
  static_assert(std::is_trivially_copyable_v<T>, "items are copied between threads");

 public:
  // Producer: false when full.
  bool push(const T& item) {
    const std::size_t head = head_.load(std::memory_order_relaxed);
    if (head - tail_.load(std::memory_order_acquire) == Capacity) return false;
    items_[head % Capacity] = item;
    head_.store(head + 1, std::memory_order_release);
    return true;
  }
  // Consumer: false when empty.
  bool pop(T& item) {
    const std::size_t tail = tail_.load(std::memory_order_relaxed);
    if (head_.load(std::memory_order_acquire) == tail) return false;
    item = items_[tail % Capacity];
    tail_.store(tail + 1, std::memory_order_release);
    return true;
  }

 private:
  std::array<T, Capacity> items_{};
  alignas(64) std::atomic<std::size_t> head_{0};
  alignas(64) std::atomic<std::size_t> tail_{0};
};

}  // namespace cobra::studio
