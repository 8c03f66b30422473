#include "row_queue.hpp"

#include <linux/futex.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <ctime>

namespace cobra::components::reporting_detail {
namespace {

static_assert(sizeof(std::atomic<std::uint32_t>) == sizeof(std::uint32_t) &&
                  std::atomic<std::uint32_t>::is_always_lock_free,
              "the futex word must be a plain 32-bit integer");

std::uint32_t* futexWord(std::atomic<std::uint32_t>& word) { return reinterpret_cast<std::uint32_t*>(&word); }

void futexWake(std::atomic<std::uint32_t>& word) noexcept {
  syscall(SYS_futex, futexWord(word), FUTEX_WAKE_PRIVATE, 1, nullptr, nullptr, 0);
}

/// Sleeps while `word` still holds `expected`, at most `timeout` (spurious wake-ups are fine).
void futexWait(std::atomic<std::uint32_t>& word, std::uint32_t expected, std::chrono::nanoseconds timeout) noexcept {
  timespec relative{};
  relative.tv_sec = static_cast<std::time_t>(timeout.count() / 1'000'000'000);
  relative.tv_nsec = static_cast<long>(timeout.count() % 1'000'000'000);
  syscall(SYS_futex, futexWord(word), FUTEX_WAIT_PRIVATE, expected, &relative, nullptr, 0);
}

}  // namespace

RowQueue::RowQueue(std::size_t rows, std::size_t row_bytes)
    : rows_(rows == 0 ? 1 : rows), row_bytes_(row_bytes), storage_(rows_ * row_bytes_), lengths_(rows_, 0) {}

std::size_t RowQueue::size() const noexcept {
  return static_cast<std::size_t>(tail_.load(std::memory_order_seq_cst) - head_.load(std::memory_order_acquire));
}

char* RowQueue::beginRow() noexcept {
  const std::uint64_t tail = tail_.load(std::memory_order_relaxed);
  if (tail - head_.load(std::memory_order_acquire) >= rows_) return nullptr;
  return storage_.data() + (tail % rows_) * row_bytes_;
}

void RowQueue::commitRow(std::size_t length) noexcept {
  const std::uint64_t tail = tail_.load(std::memory_order_relaxed);
  lengths_[tail % rows_] = length;
  // seq_cst store, then seq_cst load of sleeping_: with the consumer's store of sleeping_ then
  // load of tail_ (waitForRows), one of the two sides sees the other, so no wake-up is lost.
  tail_.store(tail + 1, std::memory_order_seq_cst);
  if (2 * (tail + 1 - head_.load(std::memory_order_acquire)) >= rows_ &&
      sleeping_.load(std::memory_order_seq_cst)) {
    wake();
  }
}

bool RowQueue::front(std::string_view& row) const noexcept {
  const std::uint64_t head = head_.load(std::memory_order_relaxed);
  if (tail_.load(std::memory_order_acquire) == head) return false;
  row = std::string_view(storage_.data() + (head % rows_) * row_bytes_, lengths_[head % rows_]);
  return true;
}

void RowQueue::pop() noexcept { head_.store(head_.load(std::memory_order_relaxed) + 1, std::memory_order_release); }

void RowQueue::waitForRows(std::chrono::nanoseconds timeout, const std::atomic<bool>& stop) noexcept {
  sleeping_.store(true, std::memory_order_seq_cst);
  // Read the futex word before looking at the queue: a wake() after this read changes the word,
  // so futexWait returns at once instead of sleeping through it.
  const std::uint32_t seen = wake_count_.load(std::memory_order_seq_cst);
  if (2 * size() < rows_ && !stop.load(std::memory_order_seq_cst)) futexWait(wake_count_, seen, timeout);
  sleeping_.store(false, std::memory_order_relaxed);
}

void RowQueue::wake() noexcept {
  wake_count_.fetch_add(1, std::memory_order_seq_cst);
  futexWake(wake_count_);
}

}  // namespace cobra::components::reporting_detail
