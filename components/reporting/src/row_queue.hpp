#pragma once
// Internal to the Reporter: the bounded queue of formatted CSV rows between the update (one
// producer) and the file writer thread (one consumer).

#include <atomic>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <string_view>
#include <vector>

#include "cobra/core/spsc_ring.hpp"

namespace cobra::components::reporting_detail {

/// Single-producer single-consumer queue of text rows of at most `rowBytes()` bytes, in slots of
/// one block allocated by the constructor. The rows travel as slot numbers through cobra's one
/// SPSC ring (`core/spsc_ring.hpp`), as the `buffer(n)` connection's values do: `filled_` carries
/// a formatted slot (and its length) to the writer, `free_` carries it back once written. A row
/// is thus formatted in place and never copied, and no slot is read while it is being written.
///
/// The producer side never blocks and never allocates: when no slot is free (the writer is
/// behind) `beginRow` returns nullptr and the caller counts a dropped row. The consumer sleeps
/// between batches and is woken early (one futex syscall by the producer) only when the queue is
/// half full, so a steady producer rarely makes a syscall.
class RowQueue {
 public:
  /// @param rows capacity in rows (>= 1, below 2^32); @param row_bytes room for one row, newline
  /// included. Throws std::length_error when `rows` has no slot number.
  RowQueue(std::size_t rows, std::size_t row_bytes);
  RowQueue(const RowQueue&) = delete;
  RowQueue& operator=(const RowQueue&) = delete;

  std::size_t rowBytes() const { return row_bytes_; }
  std::size_t capacity() const { return rows_; }

  /// Producer: where to format the next row (`rowBytes()` bytes), or nullptr when full. The slot
  /// stays the producer's until `commitRow`; calling `beginRow` again before it returns the same one.
  char* beginRow() noexcept;
  /// Producer: publishes the row begun last, `length` bytes long (at most `rowBytes()`).
  void commitRow(std::size_t length) noexcept;

  /// Consumer: the oldest row, or false when the queue is empty. The same row until `pop`.
  bool front(std::string_view& row) noexcept;
  /// Consumer: releases the row `front` gave (its slot becomes free for the producer).
  void pop() noexcept;
  /// Consumer: sleeps until the queue is half full, `wake` is called, or `timeout` passes;
  /// returns at once when `stop` is set (set it, then call `wake`, to stop the consumer).
  void waitForRows(std::chrono::nanoseconds timeout, const std::atomic<bool>& stop) noexcept;
  /// Wakes the consumer now.
  void wake() noexcept;
  /// True while the consumer is in `waitForRows` (for tests: a producer must then wake it).
  bool consumerWaiting() const noexcept { return sleeping_.load(std::memory_order_seq_cst); }

 private:
  /// A formatted row: its slot and its length in bytes.
  struct Row {
    std::uint32_t slot;
    std::size_t length;
  };
  static constexpr std::uint32_t kNone = UINT32_MAX;

  char* slot(std::uint32_t index) noexcept { return storage_.data() + index * row_bytes_; }

  const std::size_t rows_;
  const std::size_t row_bytes_;
  std::vector<char> storage_;
  core::SpscRing<Row> filled_;             // producer -> consumer: rows to write
  core::SpscRing<std::uint32_t> free_;     // consumer -> producer: slots written
  std::uint32_t producing_ = kNone;        // producer's: the slot begun and not committed
  Row consuming_{kNone, 0};                // consumer's: the row `front` gave and not popped
  // Rows committed (the producer's count, a seq_cst read-modify-write) and taken (the consumer's):
  // the pair the no-lost-wake-up argument is made on (commitRow, waitForRows), since the rings'
  // own orders are acquire/release only and fences are not modelled by ThreadSanitizer.
  alignas(64) std::atomic<std::uint64_t> committed_{0};
  std::uint64_t taken_ = 0;
  // Futex word: changed (then woken) to interrupt the consumer's sleep.
  alignas(64) std::atomic<std::uint32_t> wake_count_{0};
  std::atomic<bool> sleeping_{false};
};

}  // namespace cobra::components::reporting_detail
