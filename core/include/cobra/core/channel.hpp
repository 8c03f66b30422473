#pragma once
/// @file
/// The lock-free storage of one connection (one writer thread, one reader thread).

#include <atomic>
#include <cstdint>
#include <memory>
#include <vector>

#include "cobra/core/conn_policy.hpp"

namespace cobra::core {

class PortBase;
class TransportEnd;

/// Untyped part of a connection: the two ports it links and its policy.
class ChannelBase {
 public:
  ChannelBase(ConnPolicy policy, PortBase& writer, PortBase& reader)
      : policy_(policy), writer_(&writer), reader_(&reader) {}
  virtual ~ChannelBase() = default;
  ChannelBase(const ChannelBase&) = delete;
  ChannelBase& operator=(const ChannelBase&) = delete;

  const ConnPolicy& policy() const { return policy_; }
  PortBase& writer() const { return *writer_; }
  PortBase& reader() const { return *reader_; }

  /// For one end of a transport's connection (see transport.hpp): the port at the far end when
  /// it is in this process, else nullptr; always nullptr for a local connection.
  PortBase* peer() const { return peer_.load(std::memory_order_acquire); }
  /// The transport's end this channel belongs to, or nullptr for a local connection.
  TransportEnd* transportEnd() const { return transport_end_.get(); }
  /// Ties a transport's end to this channel: `end` lives as long as the channel, `peer` as above.
  void holdTransportEnd(std::shared_ptr<TransportEnd> end, PortBase* peer) {
    transport_end_ = std::move(end);
    peer_.store(peer, std::memory_order_release);  // other threads may ask connectedTo meanwhile
  }

 private:
  ConnPolicy policy_;
  PortBase* writer_;
  PortBase* reader_;
  std::atomic<PortBase*> peer_{nullptr};
  std::shared_ptr<TransportEnd> transport_end_;
};

/// Lock-free single-producer single-consumer channel holding up to `n` samples of T.
///
/// Samples live in n + 3 preallocated slots that are copy-assigned, never reallocated: once the
/// slots have the size of the data (see `OutputPort::setDataSample`), push and pop allocate
/// nothing. Slot ownership moves between the writer, the queue and the reader through atomic
/// indices, so a value is never read while it is being written (no torn values, whatever T is).
/// The queue head is the only contended word: the reader takes the oldest sample, and in
/// circular mode the writer may take it first to overwrite it; a compare-and-swap decides.
/// Slots: n in the queue, 2 held by the reader (the last value and, briefly, the next one),
/// 1 held by the writer.
///
/// The `data` policy (latest value only) uses a triple buffer instead: the writer fills its
/// back slot and swaps it with the middle one in a single atomic exchange that also sets a
/// "new" flag; the reader swaps its front slot with the middle one only when the flag is set.
/// One shared word per transfer keeps the cross-core traffic minimal, which matters because
/// most connections in a control loop are `data`.
template <class T>
class Channel final : public ChannelBase {
 public:
  Channel(ConnPolicy policy, PortBase& writer, PortBase& reader, const T& sample)
      : ChannelBase(policy, writer, reader),
        capacity_(policy.size),
        overwrite_(policy.kind != ConnPolicy::Kind::Buffer),
        latest_only_(policy.kind == ConnPolicy::Kind::Data),
        free_capacity_(policy.size + 3),
        slots_(policy.size + 3, Slot{sample}),
        queue_(new std::atomic<std::uint32_t>[capacity_]),
        free_(new std::atomic<std::uint32_t>[free_capacity_]) {
    for (std::size_t i = 0; i < capacity_; ++i) queue_[i].store(0, std::memory_order_relaxed);
    writer_spare_ = 0;
    // Slot 0 is the writer's spare; slots 1 .. n+2 start on the free list.
    for (std::size_t i = 0; i < free_capacity_; ++i)
      free_[i].store(static_cast<std::uint32_t>((i + 1) % free_capacity_), std::memory_order_relaxed);
    free_tail_.store(free_capacity_ - 1, std::memory_order_release);
  }

  /// Writer side. Real-time safe: no allocation once slots are sized, no lock, no throw
  /// (unless T's copy assignment throws, which the built-in types do not).
  WriteStatus push(const T& value) {
    if (latest_only_) {
      slots_[back_].value = value;
      back_ = latest_.exchange(back_ | kFresh, std::memory_order_acq_rel) & kIndexMask;
      return WriteStatus::Written;
    }
    const std::uint64_t tail = tail_.load(std::memory_order_relaxed);
    if (!overwrite_ && tail - head_.load(std::memory_order_acquire) >= capacity_) return WriteStatus::Dropped;
    const std::uint32_t slot = writer_spare_;
    slots_[slot].value = value;
    std::uint64_t head = head_.load(std::memory_order_acquire);
    if (tail - head >= capacity_) {
      // Circular and full: take the oldest sample away from the reader and reuse its slot.
      const std::uint32_t oldest = queue_[head % capacity_].load(std::memory_order_relaxed);
      if (head_.compare_exchange_strong(head, head + 1, std::memory_order_acq_rel)) {
        publish(tail, slot);
        writer_spare_ = oldest;
        return WriteStatus::Written;
      }
      // The reader took it first; there is room now.
    }
    publish(tail, slot);
    writer_spare_ = takeFree();
    return WriteStatus::Written;
  }

  /// Reader side. Copies the oldest unread sample into `out` (NewData); when there is none,
  /// copies the last sample read again if `copy_old` (OldData), or returns NoData when nothing
  /// was ever read. Real-time safe like push.
  FlowStatus pop(T& out, bool copy_old = true) {
    if (latest_only_) {
      if (latest_.load(std::memory_order_relaxed) & kFresh) {
        front_ = latest_.exchange(front_, std::memory_order_acq_rel) & kIndexMask;
        has_front_ = true;
        out = slots_[front_].value;
        return FlowStatus::NewData;
      }
      if (!has_front_) return FlowStatus::NoData;
      if (copy_old) out = slots_[front_].value;
      return FlowStatus::OldData;
    }
    for (;;) {
      std::uint64_t head = head_.load(std::memory_order_acquire);
      const std::uint64_t tail = tail_.load(std::memory_order_acquire);
      if (head == tail) {
        if (reader_last_ == kNone) return FlowStatus::NoData;
        if (copy_old) out = slots_[reader_last_].value;
        return FlowStatus::OldData;
      }
      const std::uint32_t slot = queue_[head % capacity_].load(std::memory_order_relaxed);
      if (head_.compare_exchange_weak(head, head + 1, std::memory_order_acq_rel, std::memory_order_relaxed)) {
        if (reader_last_ != kNone) giveFree(reader_last_);
        reader_last_ = slot;
        out = slots_[slot].value;
        return FlowStatus::NewData;
      }
    }
  }

  /// Number of unread samples (approximate while the writer is active).
  std::size_t unread() const {
    if (latest_only_) return (latest_.load(std::memory_order_acquire) & kFresh) ? 1 : 0;
    return static_cast<std::size_t>(tail_.load(std::memory_order_acquire) - head_.load(std::memory_order_acquire));
  }

 private:
  static constexpr std::uint32_t kNone = UINT32_MAX;
  static constexpr std::uint32_t kFresh = 4;      // triple buffer: the middle slot is unread
  static constexpr std::uint32_t kIndexMask = 3;  // triple buffer: index of the middle slot

  void publish(std::uint64_t tail, std::uint32_t slot) {
    queue_[tail % capacity_].store(slot, std::memory_order_relaxed);
    tail_.store(tail + 1, std::memory_order_release);
  }

  // Free list: the reader gives slots back, the writer takes them (single producer, single
  // consumer).
  std::uint32_t takeFree() {
    const std::uint64_t head = free_head_.load(std::memory_order_relaxed);
    // The slot count guarantees a free slot exists; the loop only waits until the reader's
    // release store of it is visible on this core (acquire pairs with giveFree's release).
    while (free_tail_.load(std::memory_order_acquire) == head) {
    }
    const std::uint32_t slot = free_[head % free_capacity_].load(std::memory_order_relaxed);
    free_head_.store(head + 1, std::memory_order_relaxed);
    return slot;
  }
  void giveFree(std::uint32_t slot) {
    const std::uint64_t tail = free_tail_.load(std::memory_order_relaxed);
    free_[tail % free_capacity_].store(slot, std::memory_order_relaxed);
    free_tail_.store(tail + 1, std::memory_order_release);
  }

  // Each slot on its own cache line(s), so the writer filling one never invalidates the line
  // the reader is copying from.
  struct alignas(64) Slot {
    T value;
  };

  const std::size_t capacity_;
  const bool overwrite_;
  const bool latest_only_;
  const std::size_t free_capacity_;
  std::vector<Slot> slots_;
  std::unique_ptr<std::atomic<std::uint32_t>[]> queue_;
  std::unique_ptr<std::atomic<std::uint32_t>[]> free_;
  alignas(64) std::atomic<std::uint64_t> head_{0};
  alignas(64) std::atomic<std::uint64_t> tail_{0};
  alignas(64) std::atomic<std::uint64_t> free_head_{0};  // written by the writer
  alignas(64) std::atomic<std::uint64_t> free_tail_{0};  // written by the reader
  alignas(64) std::uint32_t writer_spare_ = 0;  // writer thread only
  std::uint32_t back_ = 2;                      // triple buffer, writer thread only
  alignas(64) std::uint32_t reader_last_ = kNone;  // reader thread only
  std::uint32_t front_ = 0;                        // triple buffer, reader thread only
  bool has_front_ = false;                         // triple buffer, reader thread only
  alignas(64) std::atomic<std::uint32_t> latest_{1};  // triple buffer: middle slot index | kFresh
};

}  // namespace cobra::core
