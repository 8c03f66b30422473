#pragma once
/// @file
/// A single-writer, many-reader sequence lock for small trivially copyable values, usable in
/// memory shared between processes (it holds only lock-free atomics, no pointers). The writer
/// never waits; a reader retries a bounded number of times and reports failure instead of
/// spinning, so both sides are real-time safe. The value is stored as atomic 64-bit words so that
/// a reader overlapping a write is a retry, never a data race. No fences (ThreadSanitizer cannot
/// check them): each word is stored with release and loaded with acquire, so a reader that sees
/// any word of a write in progress also sees that write's odd sequence number when it checks
/// the sequence again (Boehm, "Can seqlocks get along with programming language memory
/// models?", 2012). On x86 these are plain moves.

#include <array>
#include <atomic>
#include <bit>
#include <cstdint>
#include <cstring>
#include <type_traits>

namespace cobra::bridges {

template <class T>
class Seqlock {
  static_assert(std::is_trivially_copyable_v<T>, "cobra: Seqlock<T> needs a trivially copyable T");
  static_assert(std::atomic<std::uint64_t>::is_always_lock_free, "cobra: Seqlock needs lock-free 64-bit atomics");
  static constexpr std::size_t kWords = (sizeof(T) + 7) / 8;

 public:
  /// Publishes `value`. Only one thread (or process) may write a given Seqlock.
  void write(const T& value) noexcept {
    std::array<std::uint64_t, kWords> words{};
    std::memcpy(words.data(), &value, sizeof(T));
    const std::uint64_t s = sequence_.load(std::memory_order_relaxed);
    sequence_.store(s + 1, std::memory_order_relaxed);  // odd: write in progress
    // Release: the odd sequence above is visible to whoever reads one of these words.
    for (std::size_t i = 0; i < kWords; ++i) words_[i].store(words[i], std::memory_order_release);
    sequence_.store(s + 2, std::memory_order_release);
  }

  /// Copies the last published value into `out` and returns its version (number of writes so
  /// far, >= 1), or 0 when nothing was written yet or `attempts` reads all overlapped a write
  /// (then `out` is unchanged).
  std::uint64_t read(T& out, int attempts = 8) const noexcept {
    for (int a = 0; a < attempts; ++a) {
      const std::uint64_t s1 = sequence_.load(std::memory_order_acquire);
      if (s1 == 0) return 0;
      if (s1 & 1U) continue;
      std::array<std::uint64_t, kWords> words;
      // Acquire: the sequence load below cannot move above these, and sees the odd number of a
      // write whose word was read.
      for (std::size_t i = 0; i < kWords; ++i) words[i] = words_[i].load(std::memory_order_acquire);
      if (sequence_.load(std::memory_order_relaxed) == s1) {
        std::memcpy(static_cast<void*>(&out), words.data(), sizeof(T));
        return s1 / 2;
      }
    }
    return 0;
  }

  /// Version of the last completed write (0: none); cheap check for news.
  std::uint64_t version() const noexcept { return sequence_.load(std::memory_order_acquire) / 2; }

 private:
  std::atomic<std::uint64_t> sequence_{0};
  std::array<std::atomic<std::uint64_t>, kWords> words_{};
};

}  // namespace cobra::bridges
