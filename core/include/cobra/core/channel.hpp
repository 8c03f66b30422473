#pragma once
/// @file
/// The lock-free storage of one connection (one writer thread, one reader thread).

#include <atomic>
#include <cstdint>
#include <memory>
#include <vector>

#include "cobra/core/conn_policy.hpp"
#include "cobra/core/spsc_ring.hpp"
#include "cobra/core/triple_buffer.hpp"

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
/// The `data` policy (latest value only) is a `TripleBuffer` (`core/triple_buffer.hpp`): one
/// shared word per transfer keeps the cross-core traffic minimal, which matters because most
/// connections in a control loop are `data`.
///
/// `buffer(n)` and `circular(n)`: samples live in n + 3 preallocated slots that are
/// copy-assigned, never reallocated: once the slots have the size of the data (see
/// `OutputPort::setDataSample`), push and pop allocate nothing. Slot ownership moves between the
/// writer, the queue and the reader through two `SpscRing`s of slot indices
/// (`core/spsc_ring.hpp`), so a value is never read while it is being written (no torn values,
/// whatever T is): the queue (writer to reader; in circular mode the writer may take the oldest
/// sample back to overwrite it) and the free list (reader to writer). Slots: n in the queue, 2
/// held by the reader (the last value and, briefly, the next one), 1 held by the writer.
template <class T>
class Channel final : public ChannelBase {
 public:
  Channel(ConnPolicy policy, PortBase& writer, PortBase& reader, const T& sample)
      : ChannelBase(policy, writer, reader),
        overwrite_(policy.kind != ConnPolicy::Kind::Buffer),
        latest_only_(policy.kind == ConnPolicy::Kind::Data) {
    if (latest_only_) {
      latest_ = std::make_unique<TripleBuffer<T>>(sample);
      return;
    }
    const std::size_t capacity = policy.size < 1 ? 1 : policy.size;
    slots_.assign(capacity + 3, Slot{sample});
    queue_ = std::make_unique<SpscRing<std::uint32_t, RingOverflow::EvictOldest>>(capacity);
    free_ = std::make_unique<SpscRing<std::uint32_t>>(capacity + 3);
    // Slot 0 is the writer's spare; slots 1 .. n+2 start on the free list.
    for (std::uint32_t i = 1; i < slots_.size(); ++i) (void)free_->push(i);
  }

  /// Writer side. Real-time safe: no allocation once slots are sized, no lock, no throw
  /// (unless T's copy assignment throws, which the built-in types do not).
  WriteStatus push(const T& value) {
    if (latest_only_) {
      latest_->write(value);
      return WriteStatus::Written;
    }
    if (!overwrite_ && queue_->size() >= queue_->capacity()) return WriteStatus::Dropped;
    const std::uint32_t slot = writer_spare_;
    slots_[slot].value = value;
    std::uint32_t oldest = 0;
    if (overwrite_ && queue_->pushEvicting(slot, oldest)) {
      writer_spare_ = oldest;  // circular and full: the oldest sample's slot is reused
      return WriteStatus::Written;
    }
    if (!overwrite_) (void)queue_->push(slot);  // only the reader empties the queue: there is room
    writer_spare_ = takeFree();
    return WriteStatus::Written;
  }

  /// Reader side. Copies the oldest unread sample into `out` (NewData); when there is none,
  /// copies the last sample read again if `copy_old` (OldData), or returns NoData when nothing
  /// was ever read. Real-time safe like push.
  FlowStatus pop(T& out, bool copy_old = true) {
    if (latest_only_) {
      if (latest_->update()) {
        has_front_ = true;
        out = latest_->front();
        return FlowStatus::NewData;
      }
      if (!has_front_) return FlowStatus::NoData;
      if (copy_old) out = latest_->front();
      return FlowStatus::OldData;
    }
    std::uint32_t slot = 0;
    if (queue_->pop(slot)) {
      if (reader_last_ != kNone) (void)free_->push(reader_last_);
      reader_last_ = slot;
      out = slots_[slot].value;
      return FlowStatus::NewData;
    }
    if (reader_last_ == kNone) return FlowStatus::NoData;
    if (copy_old) out = slots_[reader_last_].value;
    return FlowStatus::OldData;
  }

  /// Number of unread samples (approximate while the writer is active).
  std::size_t unread() const {
    if (latest_only_) return latest_->hasUnread() ? 1 : 0;
    return queue_->size();
  }

 private:
  static constexpr std::uint32_t kNone = UINT32_MAX;

  std::uint32_t takeFree() {
    // The slot count guarantees a free slot exists; the loop only waits until the reader's
    // release of it is visible on this core.
    std::uint32_t slot = 0;
    while (!free_->pop(slot)) {
    }
    return slot;
  }

  // Each slot on its own cache line(s), so the writer filling one never invalidates the line
  // the reader is copying from.
  struct alignas(64) Slot {
    T value;
  };

  const bool overwrite_;
  const bool latest_only_;
  std::unique_ptr<TripleBuffer<T>> latest_;  // data policy
  std::vector<Slot> slots_;                  // buffer and circular policies
  std::unique_ptr<SpscRing<std::uint32_t, RingOverflow::EvictOldest>> queue_;
  std::unique_ptr<SpscRing<std::uint32_t>> free_;
  alignas(64) std::uint32_t writer_spare_ = 0;     // writer thread only
  alignas(64) std::uint32_t reader_last_ = kNone;  // reader thread only
  bool has_front_ = false;                         // data policy, reader thread only
};

}  // namespace cobra::core
