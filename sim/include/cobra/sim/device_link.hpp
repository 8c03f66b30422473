#pragma once
/// @file
/// The link between the two sides of a simulated device: the *world side*, stepped by a sim-world
/// component (it takes the truth, advances the model, injects faults), and the *host side*, a bus
/// or device interface (fieldbus::CanBus, Cia402Bus, HandTrackerDevice) that a driver calls.
///
/// Ordering rule (what makes a lockstep run independent of the order in which the world's
/// component and the driver step within an instant): every value crossing the link is stamped
/// with the clock of its writer (the world component's clock, which in one deployment is the
/// driver's too), and the other side sees it only at a later time. So within a lockstep instant t
/// the driver sees what the world produced at instants < t, and the world sees what the driver
/// wrote at instants < t, whichever of them steps first. The latency is therefore one step of the
/// reader: the driver reads the frames of the world's previous step, always.
///
/// Without a clock (a single-threaded test driving both sides itself) every value is seen at once.
///
/// Threads: one thread may run the world side and another the host side (periodic activities):
/// the queues below are single-producer single-consumer and lock-free, the host side never blocks.

#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>

namespace cobra::sim {

/// The time of one side, for the visibility rule.
struct LinkTime {
  bool clocked = false;  ///< false: no clock attached, everything is visible at once
  std::int64_t now = 0;  ///< ns
  /// Whether a value stamped `stamp` (ns) may be seen now.
  bool visible(std::int64_t stamp) const noexcept { return !clocked || stamp < now; }
};

/// Stamp of values that are visible from the start (a device's power-on state).
inline constexpr std::int64_t kAlwaysVisible = std::numeric_limits<std::int64_t>::min();

/// Clock and connection state shared by the two sides of one simulated device.
class DeviceLink {
 public:
  using Clock = std::function<std::int64_t()>;  ///< ns; the world component's clock

  /// World side, configure time: from now on values are stamped with `clock`.
  void attach(Clock clock);
  /// World side: the device is unplugged from now on (the host sees a link down), and `clock` is
  /// never called again once this returns (it waits for host calls in progress). noexcept.
  void detach() noexcept;
  /// World side: the time the world stamps its values with.
  LinkTime worldTime() const noexcept;

  /// Host side: one call on the device. While it exists the clock stays callable.
  class Access {
   public:
    explicit Access(DeviceLink& link) noexcept;
    ~Access();
    Access(const Access&) = delete;
    Access& operator=(const Access&) = delete;
    /// False when the world side detached: the device is gone.
    bool up() const noexcept { return up_; }
    const LinkTime& time() const noexcept { return time_; }

   private:
    DeviceLink& link_;
    bool up_ = false;
    LinkTime time_;
  };

 private:
  enum State : int { kDirect, kAttached, kDetached };
  std::atomic<int> state_{kDirect};
  std::atomic<int> in_flight_{0};
  Clock clock_;
};

/// Bounded single-producer single-consumer FIFO of `N` elements; lock-free, allocation-free.
template <class T, std::size_t N>
class SpscQueue {
 public:
  /// Producer. False when full (nothing is queued).
  bool push(const T& value) noexcept {
    const std::size_t tail = tail_.load(std::memory_order_relaxed);
    if (tail - head_.load(std::memory_order_acquire) == N) return false;
    slots_[tail % N] = value;
    tail_.store(tail + 1, std::memory_order_release);
    return true;
  }
  /// Consumer: copies the oldest element without taking it. False when empty.
  bool front(T& out) const noexcept {
    const std::size_t head = head_.load(std::memory_order_relaxed);
    if (head == tail_.load(std::memory_order_acquire)) return false;
    out = slots_[head % N];
    return true;
  }
  /// Consumer: drops the oldest element (call only after front() returned true).
  void pop() noexcept { head_.store(head_.load(std::memory_order_relaxed) + 1, std::memory_order_release); }

 private:
  std::array<T, N> slots_{};
  std::atomic<std::size_t> head_{0}, tail_{0};
};

/// The newest value one side writes and the other reads, with the ordering rule: the reader gets
/// the newest value it may see at its time (the one written before it, when the newest was
/// written in the reader's own instant). One writer thread, one reader thread; lock-free (a triple
/// buffer), allocation-free.
template <class T>
class StampedMailbox {
 public:
  /// Writer: `value` stamped `stamp` (ns). A second write with the same stamp replaces the first.
  void write(const T& value, std::int64_t stamp) noexcept {
    Slot& next = slots_[back_];
    if (written_ && last_stamp_ < stamp) {
      next.previous = last_value_;
      next.has_previous = true;
    } else {
      next.previous = last_previous_;
      next.has_previous = has_last_previous_;
    }
    next.current = value;
    next.stamp = stamp;
    last_previous_ = next.previous;
    has_last_previous_ = next.has_previous;
    last_value_ = value;
    last_stamp_ = stamp;
    written_ = true;
    back_ = middle_.exchange(static_cast<std::uint8_t>(back_ | kFresh), std::memory_order_acq_rel) & kIndex;
  }

  /// Reader: the newest value visible at `time`, or nullptr when none is. Valid until the next call.
  const T* newest(const LinkTime& time) noexcept {
    if (middle_.load(std::memory_order_acquire) & kFresh) {
      front_ = middle_.exchange(front_, std::memory_order_acq_rel) & kIndex;
      have_ = true;
    }
    if (!have_) return nullptr;
    const Slot& s = slots_[front_];
    if (time.visible(s.stamp)) return &s.current;
    return s.has_previous ? &s.previous : nullptr;
  }

 private:
  static constexpr std::uint8_t kIndex = 0x3, kFresh = 0x4;
  struct Slot {
    T current{}, previous{};
    bool has_previous = false;
    std::int64_t stamp = 0;
  };
  std::array<Slot, 3> slots_{};
  std::atomic<std::uint8_t> middle_{1};
  std::uint8_t back_ = 0;   // writer's
  std::uint8_t front_ = 2;  // reader's
  bool have_ = false;       // reader's: something was read
  // Writer's memory of what it wrote last.
  T last_value_{}, last_previous_{};
  bool written_ = false, has_last_previous_ = false;
  std::int64_t last_stamp_ = 0;
};

}  // namespace cobra::sim
