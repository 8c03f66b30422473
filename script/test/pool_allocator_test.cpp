// PoolAllocator: alignment, reuse, splitting, in-place shrinking, exhaustion, and a seeded
// random test (20000 operations) against a model that checks blocks never overlap.

#include "cobra/script/pool_allocator.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <map>
#include <random>

namespace cobra::script {
namespace {

TEST(PoolAllocator, BlocksAreAlignedAndInsideTheArena) {
  PoolAllocator pool(64 * 1024);
  for (std::size_t size : {1u, 7u, 16u, 17u, 100u, 256u, 257u, 1000u, 5000u}) {
    void* p = pool.allocate(size);
    ASSERT_NE(p, nullptr) << size;
    EXPECT_EQ(reinterpret_cast<std::uintptr_t>(p) % 16, 0u) << size;
    EXPECT_TRUE(pool.owns(p));
    std::memset(p, 0xab, size);
  }
  EXPECT_FALSE(pool.owns(&pool));
}

TEST(PoolAllocator, FreedBlockIsReusedForTheSameClass) {
  PoolAllocator pool(4096);
  void* a = pool.allocate(40);
  pool.deallocate(a, 40);
  EXPECT_EQ(pool.allocate(48), a);  // 40 and 48 are both the 48-byte class
  EXPECT_EQ(pool.inUse(), 48u);
}

TEST(PoolAllocator, ExhaustionReturnsNullAndCountsIt) {
  PoolAllocator pool(1024);
  EXPECT_NE(pool.allocate(1024), nullptr);
  EXPECT_EQ(pool.allocate(16), nullptr);
  EXPECT_EQ(pool.failures(), 1u);
  EXPECT_EQ(pool.allocate(std::size_t{1} << 50), nullptr);  // beyond every class
}

TEST(PoolAllocator, LargerFreeBlockIsSplitWhenTheArenaIsUsedUp) {
  PoolAllocator pool(2048);
  void* big = pool.allocate(2048);
  ASSERT_NE(big, nullptr);
  pool.deallocate(big, 2048);
  // The bump region is empty: these come from splitting the free 2 KiB block.
  void* a = pool.allocate(100);
  void* b = pool.allocate(512);
  void* c = pool.allocate(1024);
  EXPECT_EQ(a, big);
  EXPECT_NE(b, nullptr);
  EXPECT_NE(c, nullptr);
  EXPECT_EQ(pool.inUse(), 112u + 512u + 1024u);
}

TEST(PoolAllocator, ShrinkingStaysInPlaceAndFreesTheTail) {
  PoolAllocator pool(4096);
  auto* p = static_cast<char*>(pool.allocate(4096));
  ASSERT_NE(p, nullptr);
  std::memcpy(p, "hello", 6);
  EXPECT_EQ(pool.reallocate(p, 4096, 100), p);
  EXPECT_STREQ(p, "hello");
  EXPECT_EQ(pool.inUse(), 112u);
  EXPECT_NE(pool.allocate(2048), nullptr);  // from the freed tail
}

TEST(PoolAllocator, GrowingCopiesAndFailsWithoutTouchingTheOldBlock) {
  PoolAllocator pool(1024);
  auto* p = static_cast<char*>(pool.allocate(16));
  std::memcpy(p, "abcdefghijklmno", 16);
  auto* q = static_cast<char*>(pool.reallocate(p, 16, 200));
  ASSERT_NE(q, nullptr);
  EXPECT_STREQ(q, "abcdefghijklmno");
  EXPECT_EQ(pool.reallocate(q, 200, 4096), nullptr);
  EXPECT_STREQ(q, "abcdefghijklmno");
}

TEST(PoolAllocator, LuaAllocFreesWithZeroSizeAndIgnoresTypeTags) {
  PoolAllocator pool(1024);
  void* p = PoolAllocator::luaAlloc(&pool, nullptr, 5 /* LUA_TTABLE tag, not a size */, 64);
  ASSERT_NE(p, nullptr);
  EXPECT_EQ(pool.inUse(), 64u);
  EXPECT_EQ(PoolAllocator::luaAlloc(&pool, p, 64, 0), nullptr);
  EXPECT_EQ(pool.inUse(), 0u);
}

TEST(PoolAllocator, RandomOperationsNeverOverlapAndKeepTheirContents) {
  PoolAllocator pool(256 * 1024);
  std::mt19937 rng(12345);
  std::map<char*, std::size_t> live;  // block -> requested size; each block filled with a tag byte
  std::map<char*, unsigned char> tag;
  auto place = [&](char* p, std::size_t size, unsigned char t) {
    ASSERT_EQ(live.count(p), 0u);
    auto next = live.lower_bound(p);
    if (next != live.end()) {
      ASSERT_LE(p + size, next->first);
    }
    if (next != live.begin()) {
      ASSERT_LE(std::prev(next)->first + std::prev(next)->second, p);
    }
    std::memset(p, t, size);
    live[p] = size;
    tag[p] = t;
  };
  auto check = [&](char* p, std::size_t size) {
    for (std::size_t i = 0; i < size; ++i) ASSERT_EQ(static_cast<unsigned char>(p[i]), tag[p]);
  };
  for (int step = 0; step < 20000; ++step) {
    const int op = static_cast<int>(rng() % 3);
    const std::size_t size = 1 + (rng() % 4 == 0 ? rng() % 8192 : rng() % 300);
    if (op == 0 || live.empty()) {
      auto* p = static_cast<char*>(pool.allocate(size));
      if (p == nullptr) continue;
      place(p, size, static_cast<unsigned char>(rng()));
    } else {
      auto it = std::next(live.begin(), static_cast<long>(rng() % live.size()));
      char* p = it->first;
      check(p, it->second);
      if (op == 1) {
        pool.deallocate(p, it->second);
        live.erase(it);
        tag.erase(p);
      } else {
        const std::size_t old = it->second;
        auto* q = static_cast<char*>(pool.reallocate(p, old, size));
        if (q == nullptr) continue;
        const unsigned char t = tag[p];
        live.erase(it);
        tag.erase(p);
        for (std::size_t i = 0; i < std::min(old, size); ++i) ASSERT_EQ(static_cast<unsigned char>(q[i]), t);
        place(q, size, t);
      }
    }
  }
  EXPECT_LE(pool.peak(), pool.capacity());
}

}  // namespace
}  // namespace cobra::script
