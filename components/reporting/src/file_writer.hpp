#pragma once
// Internal to the Reporter: the CSV file and the low-priority thread that moves rows from the
// RowQueue into it.

#include <atomic>
#include <chrono>
#include <cstdio>
#include <string>
#include <string_view>
#include <thread>

#include "row_queue.hpp"

namespace cobra::components::reporting_detail {

/// Owns the open file. Not thread-safe itself: one controlling thread calls every method; the
/// writer thread it starts only drains the queue.
class FileWriter {
 public:
  /// Opens (truncates) `path` for writing.
  /// @throws core::Error naming the path and the system's reason.
  explicit FileWriter(const std::string& path);
  /// Stops the thread if needed, then closes the file.
  ~FileWriter();
  FileWriter(const FileWriter&) = delete;
  FileWriter& operator=(const FileWriter&) = delete;

  /// Writes `line` and flushes it (the header, before any thread runs).
  /// @throws core::Error naming the path and the system's reason.
  void writeNow(std::string_view line);
  /// Starts the thread draining `queue` into the file; buffered rows are flushed at least every
  /// `flush_period` (after every batch when zero).
  void start(RowQueue& queue, std::chrono::nanoseconds flush_period);
  /// Tells the thread to write every row still queued, flush and end; joins it. Call after the
  /// producer's last commit.
  void stop();

 private:
  void run(RowQueue& queue, std::chrono::nanoseconds flush_period);
  void reportWriteError() noexcept;

  std::string path_;
  std::FILE* file_ = nullptr;
  RowQueue* queue_ = nullptr;  // the queue the thread drains, while it runs
  std::thread thread_;
  std::atomic<bool> stop_{false};
  bool write_error_reported_ = false;  // writer thread only while it runs
};

}  // namespace cobra::components::reporting_detail
