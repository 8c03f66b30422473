#include "file_writer.hpp"

#include <pthread.h>
#include <sched.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

#include "cobra/core/error.hpp"

namespace cobra::components::reporting_detail {
namespace {

/// The writer thread must never compete with real-time threads: it inherits its creator's
/// scheduling (SCHED_FIFO when the deployer runs with it), so it drops to SCHED_OTHER, nice 10.
/// Failures are harmless (the thread then keeps its creator's policy) and ignored.
void becomeLowPriority() noexcept {
  sched_param param{};
  param.sched_priority = 0;
  pthread_setschedparam(pthread_self(), SCHED_OTHER, &param);
  setpriority(PRIO_PROCESS, static_cast<id_t>(gettid()), 10);
}

/// Longest sleep of the writer thread between two looks at the queue.
constexpr std::chrono::nanoseconds kMaxSleep = std::chrono::milliseconds(100);

}  // namespace

FileWriter::FileWriter(const std::string& path) : path_(path) {
  file_ = std::fopen(path.c_str(), "w");
  if (file_ == nullptr)
    throw core::Error("cannot open file_path '" + path + "' for writing: " + std::strerror(errno) +
                      "; set file_path to a file in an existing, writable directory");
  // A large buffer: the thread hands rows to stdio, which writes them to the disk in big blocks.
  std::setvbuf(file_, nullptr, _IOFBF, 1 << 16);
}

FileWriter::~FileWriter() {
  stop();
  if (file_ != nullptr) std::fclose(file_);
}

void FileWriter::writeNow(std::string_view line) {
  if (std::fwrite(line.data(), 1, line.size(), file_) != line.size() || std::fflush(file_) != 0)
    throw core::Error("cannot write to file_path '" + path_ + "': " + std::strerror(errno));
}

void FileWriter::start(RowQueue& queue, std::chrono::nanoseconds flush_period) {
  stop();
  stop_.store(false, std::memory_order_seq_cst);
  write_error_reported_ = false;
  queue_ = &queue;
  thread_ = std::thread([this, &queue, flush_period] { run(queue, flush_period); });
}

void FileWriter::stop() {
  if (!thread_.joinable()) return;
  stop_.store(true, std::memory_order_seq_cst);
  // The thread only sleeps in waitForRows; wake it there. (The queue outlives the thread.)
  queue_->wake();
  thread_.join();
  queue_ = nullptr;
}

void FileWriter::reportWriteError() noexcept {
  if (write_error_reported_) return;
  write_error_reported_ = true;
  std::fprintf(stderr, "[cobra] Reporter: writing to '%s' failed: %s; rows are being lost\n", path_.c_str(),
               std::strerror(errno));
}

void FileWriter::run(RowQueue& queue, std::chrono::nanoseconds flush_period) {
  becomeLowPriority();
  using Clock = std::chrono::steady_clock;
  auto last_flush = Clock::now();
  bool unflushed = false;
  const std::chrono::nanoseconds sleep = flush_period.count() > 0 ? std::min(flush_period, kMaxSleep) : kMaxSleep;
  for (;;) {
    // Read before draining: every row committed before the stop request is then written.
    const bool stopping = stop_.load(std::memory_order_seq_cst);
    std::string_view row;
    while (queue.front(row)) {
      if (std::fwrite(row.data(), 1, row.size(), file_) != row.size()) reportWriteError();
      queue.pop();
      unflushed = true;
    }
    if (stopping) break;
    const auto now = Clock::now();
    if (unflushed && now - last_flush >= flush_period) {
      if (std::fflush(file_) != 0) reportWriteError();
      last_flush = now;
      unflushed = false;
    }
    queue.waitForRows(sleep, stop_);
  }
  if (std::fflush(file_) != 0) reportWriteError();
}

}  // namespace cobra::components::reporting_detail
