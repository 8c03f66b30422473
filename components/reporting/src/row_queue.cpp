#include "row_queue.hpp"

#include <linux/futex.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <ctime>
#include <stdexcept>
#include <string>

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

std::size_t checkedRows(std::size_t rows) {
  if (rows >= UINT32_MAX) throw std::length_error("Reporter row queue: " + std::to_string(rows) + " rows; expected fewer than 2^32 - 1");
  return rows == 0 ? 1 : rows;
}

}  // namespace

RowQueue::RowQueue(std::size_t rows, std::size_t row_bytes)
    : rows_(checkedRows(rows)), row_bytes_(row_bytes), storage_(rows_ * row_bytes_), filled_(rows_), free_(rows_) {
  // Every slot starts free. Each ring holds all rows_ slots, so neither push below ever fails.
  for (std::uint32_t i = 0; i < rows_; ++i) (void)free_.push(i);
}

char* RowQueue::beginRow() noexcept {
  if (producing_ == kNone && !free_.pop(producing_)) return nullptr;  // pop left producing_ as it was
  return slot(producing_);
}

void RowQueue::commitRow(std::size_t length) noexcept {
  (void)filled_.push(Row{producing_, length});
  producing_ = kNone;
  // Dekker's pattern on two seq_cst variables: the count of committed rows (this read-modify-write,
  // then the load of sleeping_) against waitForRows (the store of sleeping_, then the load of the
  // count). In the single order of seq_cst operations one side sees the other, so no wake-up is
  // lost. (A fence would do on the ring's own tail, but ThreadSanitizer does not model fences.)
  committed_.fetch_add(1, std::memory_order_seq_cst);
  if (2 * filled_.size() >= rows_ && sleeping_.load(std::memory_order_seq_cst)) wake();
}

bool RowQueue::front(std::string_view& row) noexcept {
  if (consuming_.slot == kNone) {
    if (!filled_.pop(consuming_)) return false;
    ++taken_;
  }
  row = std::string_view(slot(consuming_.slot), consuming_.length);
  return true;
}

void RowQueue::pop() noexcept {
  if (consuming_.slot == kNone) return;
  (void)free_.push(consuming_.slot);
  consuming_.slot = kNone;
}

void RowQueue::waitForRows(std::chrono::nanoseconds timeout, const std::atomic<bool>& stop) noexcept {
  sleeping_.store(true, std::memory_order_seq_cst);  // pairs with commitRow's (see there)
  // Read the futex word before looking at the queue: a wake() after this read changes the word,
  // so futexWait returns at once instead of sleeping through it.
  const std::uint32_t seen = wake_count_.load(std::memory_order_acquire);
  const std::uint64_t waiting_rows = committed_.load(std::memory_order_seq_cst) - taken_;
  if (2 * waiting_rows < rows_ && !stop.load(std::memory_order_seq_cst)) futexWait(wake_count_, seen, timeout);
  sleeping_.store(false, std::memory_order_relaxed);
}

void RowQueue::wake() noexcept {
  wake_count_.fetch_add(1, std::memory_order_seq_cst);
  futexWake(wake_count_);
}

}  // namespace cobra::components::reporting_detail
