#include "cobra/script/pool_allocator.hpp"

#include <algorithm>
#include <bit>
#include <cstring>
#include <new>

namespace cobra::script {

namespace {
constexpr std::align_val_t kArenaAlign{64};
}  // namespace

void PoolAllocator::ArenaDelete::operator()(std::byte* p) const { ::operator delete(p, kArenaAlign); }

PoolAllocator::PoolAllocator(std::size_t bytes)
    : arena_(static_cast<std::byte*>(::operator new(std::max(bytes / kAlign * kAlign, kAlign), kArenaAlign))),
      capacity_(std::max(bytes / kAlign * kAlign, kAlign)) {}

std::size_t PoolAllocator::classOf(std::size_t size) {
  if (size <= kSmallClasses * kAlign) return size == 0 ? 0 : (size + kAlign - 1) / kAlign - 1;
  // Power-of-two classes: 512 B is class 16.
  const auto log2 = static_cast<std::size_t>(std::bit_width(size - 1));
  return kSmallClasses + (log2 - 9);
}

std::size_t PoolAllocator::classSize(std::size_t cls) {
  if (cls < kSmallClasses) return (cls + 1) * kAlign;
  return std::size_t{1} << (cls - kSmallClasses + 9);
}

bool PoolAllocator::owns(const void* block) const {
  const auto* p = static_cast<const std::byte*>(block);
  return p >= arena_.get() && p < arena_.get() + capacity_;
}

void PoolAllocator::push(std::byte* block, std::size_t cls) noexcept {
  auto* node = reinterpret_cast<FreeBlock*>(block);
  node->next = free_[cls];
  free_[cls] = node;
}

void PoolAllocator::release(std::byte* block, std::size_t bytes) noexcept {
  while (bytes > 0) {
    // A remainder of at most 256 B is one small class; above that, cut the largest power of two.
    const std::size_t piece = bytes <= kSmallClasses * kAlign ? bytes : std::bit_floor(bytes);
    push(block, classOf(piece));
    block += piece;
    bytes -= piece;
  }
}

void* PoolAllocator::allocate(std::size_t size) noexcept {
  const std::size_t cls = classOf(size);
  if (cls >= kClasses) {
    ++failures_;
    return nullptr;
  }
  const std::size_t bytes = classSize(cls);
  std::byte* block = nullptr;
  if (FreeBlock* head = free_[cls]) {
    free_[cls] = head->next;
    block = reinterpret_cast<std::byte*>(head);
  } else if (capacity_ - bump_ >= bytes) {
    block = arena_.get() + bump_;
    bump_ += bytes;
  } else {
    for (std::size_t larger = cls + 1; larger < kClasses && block == nullptr; ++larger) {
      if (FreeBlock* spare = free_[larger]) {
        free_[larger] = spare->next;
        block = reinterpret_cast<std::byte*>(spare);
        release(block + bytes, classSize(larger) - bytes);
      }
    }
    if (block == nullptr) {
      ++failures_;
      return nullptr;
    }
  }
  in_use_ += bytes;
  if (in_use_ > peak_) peak_ = in_use_;
  return block;
}

void PoolAllocator::deallocate(void* block, std::size_t size) noexcept {
  if (block == nullptr) return;
  const std::size_t cls = classOf(size);
  push(static_cast<std::byte*>(block), cls);
  in_use_ -= classSize(cls);
}

void* PoolAllocator::reallocate(void* block, std::size_t old_size, std::size_t new_size) noexcept {
  if (block == nullptr) return new_size == 0 ? nullptr : allocate(new_size);
  if (new_size == 0) {
    deallocate(block, old_size);
    return nullptr;
  }
  const std::size_t old_bytes = classSize(classOf(old_size));
  const std::size_t new_cls = classOf(new_size);
  if (new_cls >= kClasses) {
    ++failures_;
    return nullptr;
  }
  const std::size_t new_bytes = classSize(new_cls);
  if (new_bytes == old_bytes) return block;
  if (new_bytes < old_bytes) {
    release(static_cast<std::byte*>(block) + new_bytes, old_bytes - new_bytes);
    in_use_ -= old_bytes - new_bytes;
    return block;
  }
  void* grown = allocate(new_size);
  if (grown == nullptr) return nullptr;
  std::memcpy(grown, block, old_size);
  deallocate(block, old_size);
  return grown;
}

void* PoolAllocator::luaAlloc(void* pool, void* block, std::size_t old_size, std::size_t new_size) noexcept {
  // Lua passes a type tag instead of a size when block is nullptr.
  return static_cast<PoolAllocator*>(pool)->reallocate(block, block == nullptr ? 0 : old_size, new_size);
}

}  // namespace cobra::script
