#pragma once
// Internal to the Reporter: the bounded queue of formatted CSV rows between the update (one
// producer) and the file writer thread (one consumer).

#include <atomic>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <string_view>
#include <vector>

namespace cobra::components::reporting_detail {

/// Single-producer single-consumer queue of text rows of at most `rowBytes()` bytes, all in one
/// block allocated by the constructor. The producer side never blocks and never allocates; the
/// consumer sleeps between batches and is woken early (one futex syscall by the producer) only
/// when the queue is half full, so a steady producer rarely makes a syscall.
class RowQueue {
 public:
  /// @param rows capacity in rows (>= 1); @param row_bytes room for one row, newline included.
  RowQueue(std::size_t rows, std::size_t row_bytes);
  RowQueue(const RowQueue&) = delete;
  RowQueue& operator=(const RowQueue&) = delete;

  std::size_t rowBytes() const { return row_bytes_; }
  std::size_t capacity() const { return rows_; }

  /// Producer: where to format the next row (`rowBytes()` bytes), or nullptr when full.
  char* beginRow() noexcept;
  /// Producer: publishes the row begun last, `length` bytes long.
  void commitRow(std::size_t length) noexcept;

  /// Consumer: the oldest row, or false when the queue is empty.
  bool front(std::string_view& row) const noexcept;
  /// Consumer: releases the row `front` gave.
  void pop() noexcept;
  /// Consumer: sleeps until the queue is half full, `wake` is called, or `timeout` passes;
  /// returns at once when `stop` is set (set it, then call `wake`, to stop the consumer).
  void waitForRows(std::chrono::nanoseconds timeout, const std::atomic<bool>& stop) noexcept;
  /// Wakes the consumer now.
  void wake() noexcept;

 private:
  std::size_t size() const noexcept;

  const std::size_t rows_;
  const std::size_t row_bytes_;
  std::vector<char> storage_;
  std::vector<std::size_t> lengths_;
  alignas(64) std::atomic<std::uint64_t> head_{0};  // written by the consumer
  alignas(64) std::atomic<std::uint64_t> tail_{0};  // written by the producer
  // Futex word: changed (then woken) to interrupt the consumer's sleep.
  alignas(64) std::atomic<std::uint32_t> wake_count_{0};
  std::atomic<bool> sleeping_{false};
};

}  // namespace cobra::components::reporting_detail
