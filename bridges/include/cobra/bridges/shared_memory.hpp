#pragma once
/// @file
/// A POSIX shared memory segment (shm_open + mmap) holding one block of lock-free atomics, so that
/// a bridge component and a stand-alone server process (or a server thread of the same process)
/// exchange data without locks or system calls on the real-time path. Opening is not real-time.

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <type_traits>

namespace cobra::bridges {

/// Maps `size` bytes of the segment `name` ("/name", POSIX rules: one leading slash, no other),
/// creating it (zero-filled) when absent. Two mappings of one segment see the same bytes.
class SharedSegment {
 public:
  /// @throws std::runtime_error "shared memory '/x': <what failed>: <strerror>", or when the
  /// segment exists with another size.
  SharedSegment(const std::string& name, std::size_t size);
  ~SharedSegment();
  SharedSegment(const SharedSegment&) = delete;
  SharedSegment& operator=(const SharedSegment&) = delete;

  void* data() const noexcept { return data_; }
  const std::string& name() const noexcept { return name_; }
  /// Removes the name (the memory lives on until the last mapping goes). False when absent.
  static bool unlink(const std::string& name) noexcept;

 private:
  std::string name_;
  std::size_t size_;
  void* data_ = nullptr;
};

/// A typed view of a segment holding a `Block`. A freshly created segment is zero-filled, which
/// must be a valid initial state of `Block` (atomics and Seqlocks at zero: "nothing yet"). The
/// first word of `Block` must be `std::atomic<std::uint64_t> layout`: it is set to
/// `Block::kLayoutTag` by the first user and checked by every other one, so that two programs
/// built with different layouts refuse to talk.
template <class Block>
class SharedBlock {
  static_assert(std::is_standard_layout_v<Block>, "cobra: a shared block must be standard layout");

 public:
  /// @throws std::runtime_error as SharedSegment, or "shared memory '/x' holds another layout".
  explicit SharedBlock(const std::string& name) : segment_(name, sizeof(Block)) {
    block_ = static_cast<Block*>(segment_.data());
    std::uint64_t expected = 0;
    if (!block_->layout.compare_exchange_strong(expected, Block::kLayoutTag) && expected != Block::kLayoutTag)
      throw std::runtime_error("shared memory '" + name + "' holds another layout (tag " + std::to_string(expected) +
                               ", expected " + std::to_string(Block::kLayoutTag) +
                               "): the server and the bridge were built from different versions");
  }
  Block& operator*() const noexcept { return *block_; }
  Block* operator->() const noexcept { return block_; }
  const std::string& name() const noexcept { return segment_.name(); }

 private:
  SharedSegment segment_;
  Block* block_ = nullptr;
};

}  // namespace cobra::bridges
