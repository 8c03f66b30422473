// Unit tests of core::SpscRing (spsc_ring.hpp): FIFO order, full and empty, eviction, a seeded
// random comparison with a std::deque model, a producer and a consumer on two threads, and no
// allocation by push and pop.

#include "cobra/core/spsc_ring.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <deque>
#include <random>
#include <thread>

#include "cobra/test_support/counting_new.hpp"

namespace cobra::core {
namespace {

TEST(SpscRing, ItemsComeOutInOrderAndAFullRingRefusesTheNext) {
  SpscRing<int> ring(3);
  EXPECT_EQ(ring.capacity(), 3U);
  int item = -1;
  EXPECT_FALSE(ring.pop(item));
  EXPECT_EQ(item, -1) << "an empty ring leaves the item untouched";
  EXPECT_TRUE(ring.push(1));
  EXPECT_TRUE(ring.push(2));
  EXPECT_TRUE(ring.push(3));
  EXPECT_FALSE(ring.push(4)) << "full";
  EXPECT_EQ(ring.size(), 3U);
  for (int expected : {1, 2, 3}) {
    ASSERT_TRUE(ring.pop(item));
    EXPECT_EQ(item, expected);
  }
  EXPECT_TRUE(ring.empty());
  EXPECT_TRUE(ring.push(5)) << "room again, across the wrap";
  ASSERT_TRUE(ring.pop(item));
  EXPECT_EQ(item, 5);
}

TEST(SpscRing, AnEvictingRingDropsTheOldestItemAndSaysWhich) {
  SpscRing<std::uint32_t, RingOverflow::EvictOldest> ring(2);
  std::uint32_t evicted = 0;
  EXPECT_FALSE(ring.pushEvicting(10, evicted));
  EXPECT_FALSE(ring.pushEvicting(11, evicted));
  EXPECT_TRUE(ring.pushEvicting(12, evicted));
  EXPECT_EQ(evicted, 10U);
  EXPECT_FALSE(ring.push(13)) << "push still refuses when full";
  std::uint32_t item = 0;
  ASSERT_TRUE(ring.pop(item));
  EXPECT_EQ(item, 11U);
  ASSERT_TRUE(ring.pop(item));
  EXPECT_EQ(item, 12U);
  EXPECT_FALSE(ring.pop(item));
}

// 20,000 random operations per seed (5 seeds) against std::deque: the same items come out, in
// the same order, the same pushes are refused and the same items evicted.
TEST(SpscRing, MatchesADequeModelOverSeededRandomOperations) {
  for (unsigned seed = 1; seed <= 5; ++seed) {
    std::mt19937 random(seed);
    const std::size_t capacity = 1 + random() % 7;
    SpscRing<std::uint32_t, RingOverflow::EvictOldest> ring(capacity);
    std::deque<std::uint32_t> model;
    for (std::uint32_t op = 0; op < 20000; ++op) {
      switch (random() % 3) {
        case 0: {
          const bool room = model.size() < capacity;
          ASSERT_EQ(ring.push(op), room) << "seed " << seed << ", operation " << op;
          if (room) model.push_back(op);
          break;
        }
        case 1: {
          std::uint32_t evicted = 0;
          const bool full = model.size() == capacity;
          ASSERT_EQ(ring.pushEvicting(op, evicted), full) << "seed " << seed << ", operation " << op;
          if (full) {
            ASSERT_EQ(evicted, model.front());
            model.pop_front();
          }
          model.push_back(op);
          break;
        }
        default: {
          std::uint32_t item = 0;
          ASSERT_EQ(ring.pop(item), !model.empty()) << "seed " << seed << ", operation " << op;
          if (!model.empty()) {
            ASSERT_EQ(item, model.front());
            model.pop_front();
          }
        }
      }
      ASSERT_EQ(ring.size(), model.size());
    }
  }
}

// A producer pushes 1..200,000 while a consumer pops: a refusing ring delivers every item once,
// in order; an evicting ring delivers an increasing subsequence ending with the last item.
TEST(SpscRing, AProducerAndAConsumerOnTwoThreadsKeepTheOrder) {
  constexpr std::uint32_t kItems = 200000;
  {
    SpscRing<std::uint32_t> ring(16);
    std::thread producer([&] {
      for (std::uint32_t v = 1; v <= kItems; ++v)
        while (!ring.push(v)) std::this_thread::yield();
    });
    std::uint32_t expected = 1, item = 0, wrong = 0;
    while (expected <= kItems)
      if (ring.pop(item)) wrong += item != expected++;
    producer.join();
    EXPECT_EQ(wrong, 0U);
  }
  {
    SpscRing<std::uint32_t, RingOverflow::EvictOldest> ring(4);
    std::thread producer([&] {
      std::uint32_t evicted = 0;
      for (std::uint32_t v = 1; v <= kItems; ++v) (void)ring.pushEvicting(v, evicted);
    });
    std::uint32_t last = 0, item = 0, older = 0;
    while (last < kItems)
      if (ring.pop(item)) {
        older += item <= last;
        last = item;
      }
    producer.join();
    EXPECT_EQ(older, 0U);
  }
}

TEST(SpscRing, PushAndPopAllocateNothing) {
  SpscRing<std::uint64_t> ring(8);
  SpscRing<std::uint32_t, RingOverflow::EvictOldest> evicting(8);
  const long allocations = test_support::allocationsDuring([&] {
    std::uint64_t item = 0;
    std::uint32_t index = 0, evicted = 0;
    for (std::uint32_t i = 0; i < 1000; ++i) {
      (void)ring.push(i);
      (void)evicting.pushEvicting(i, evicted);
      if (i % 3 == 0) {
        (void)ring.pop(item);
        (void)evicting.pop(index);
      }
    }
  });
  EXPECT_EQ(allocations, 0);
}

}  // namespace
}  // namespace cobra::core
