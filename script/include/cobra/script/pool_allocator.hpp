#pragma once
/// @file
/// A bounded, real-time pool allocator for Lua states: every block comes from one arena reserved
/// up front, so Lua code running in an activity never calls the system allocator.

#include <array>
#include <cstddef>
#include <memory>

namespace cobra::script {

/// Fixed arena + segregated free lists + bump region, made to be a `lua_Alloc`.
///
/// Design. Lua tells the allocator the size of every block it frees or resizes, so blocks
/// carry no header. Sizes are rounded up to a *size class*: multiples of 16 bytes up to 256 B
/// (16 classes), then powers of two (512 B, 1 KiB, ...). Each class has a LIFO free list
/// threaded through the free blocks themselves. An allocation takes, in order:
///  1. the head of its class's free list;
///  2. fresh memory from the bump region (the never-used tail of the arena);
///  3. a block of the smallest larger non-empty class, split: the front serves the request and
///     the rest is cut into power-of-two pieces (every multiple of 16 is a sum of class sizes)
///     that go to their free lists.
/// Shrinking a block keeps it in place and frees its tail the same way, so it never fails;
/// growing it within its class keeps it in place.
///
/// Cost. O(number of classes) = O(48) worst case per call (step 3 scans the classes; splitting
/// pushes at most one piece per class); no locks, no system calls, no loops over blocks.
///
/// Worst case. Freed blocks are never merged back, so memory fragmented into small classes
/// cannot serve a later large request: a state whose live data never exceeds L bytes may still
/// need more than L from the arena (power-of-two rounding alone wastes up to half of a large
/// block). Size the pool with headroom, about twice the peak live Lua memory; when the arena
/// is exhausted the allocation fails, Lua raises "not enough memory" (after an emergency
/// garbage collection), and cobra reports it as a clear error. Nothing ever falls back to the
/// system allocator.
///
/// Not thread-safe: one Lua state, used by one thread at a time, owns one pool.
class PoolAllocator {
 public:
  /// Reserves `bytes` (rounded down to a multiple of 16, at least 16) from the system now.
  /// @throws std::bad_alloc when the system cannot provide them.
  explicit PoolAllocator(std::size_t bytes);
  PoolAllocator(const PoolAllocator&) = delete;
  PoolAllocator& operator=(const PoolAllocator&) = delete;

  /// A block of at least `size` bytes aligned to 16, or nullptr when the arena cannot serve it.
  void* allocate(std::size_t size) noexcept;
  /// Returns `block`, allocated with `size`, to the pool. nullptr is ignored.
  void deallocate(void* block, std::size_t size) noexcept;
  /// Resizes `block` (allocated with `old_size`) as `lua_Alloc` does: nullptr when it cannot
  /// grow it (the old block is then untouched); shrinking never fails.
  void* reallocate(void* block, std::size_t old_size, std::size_t new_size) noexcept;

  /// The function to give `lua_newstate`, with `this` as its user data.
  static void* luaAlloc(void* pool, void* block, std::size_t old_size, std::size_t new_size) noexcept;

  /// Arena size in bytes.
  std::size_t capacity() const { return capacity_; }
  /// Bytes handed out and not yet returned (after rounding to size classes).
  std::size_t inUse() const { return in_use_; }
  /// Most bytes ever in use at once.
  std::size_t peak() const { return peak_; }
  /// Allocations refused because the arena was exhausted.
  std::size_t failures() const { return failures_; }
  /// True when `block` lies inside the arena.
  bool owns(const void* block) const;

 private:
  struct FreeBlock {
    FreeBlock* next;
  };
  static constexpr std::size_t kAlign = 16;
  static constexpr std::size_t kSmallClasses = 16;  // 16, 32, ..., 256 bytes
  static constexpr std::size_t kClasses = 48;       // then 512 B .. 2^(9+31) B

  static std::size_t classOf(std::size_t size);
  static std::size_t classSize(std::size_t cls);
  /// Puts [block, block + bytes) on free lists, cut into class-sized pieces (bytes % 16 == 0).
  void release(std::byte* block, std::size_t bytes) noexcept;
  void push(std::byte* block, std::size_t cls) noexcept;

  struct ArenaDelete {
    void operator()(std::byte* p) const;
  };
  std::unique_ptr<std::byte, ArenaDelete> arena_;
  std::size_t capacity_;
  std::size_t bump_ = 0;  // offset of the never-used tail
  std::array<FreeBlock*, kClasses> free_{};
  std::size_t in_use_ = 0;
  std::size_t peak_ = 0;
  std::size_t failures_ = 0;
};

}  // namespace cobra::script
