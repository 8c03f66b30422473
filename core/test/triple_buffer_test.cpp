// Unit tests of core::TripleBuffer (triple_buffer.hpp): the reader takes the newest value once
// and keeps it, a concurrent reader sees only whole values in order, and nothing allocates after
// construction.

#include "cobra/core/triple_buffer.hpp"

#include <gtest/gtest.h>

#include <random>
#include <thread>
#include <vector>

#include "cobra/test_support/counting_new.hpp"

namespace cobra::core {
namespace {

TEST(TripleBuffer, TheReaderTakesTheNewestValueOnceAndKeepsItUntilANewerOne) {
  TripleBuffer<int> buffer(0);
  EXPECT_FALSE(buffer.update());
  EXPECT_EQ(buffer.front(), 0) << "the constructor's value";
  buffer.back() = 1;
  buffer.publish();
  EXPECT_TRUE(buffer.hasUnread());
  buffer.write(2);
  ASSERT_TRUE(buffer.update());
  EXPECT_EQ(buffer.front(), 2);
  EXPECT_FALSE(buffer.hasUnread());
  EXPECT_FALSE(buffer.update());
  EXPECT_EQ(buffer.front(), 2);
}

// 20,000 random writes and reads per seed (5 seeds), one thread: a read after writes gives the
// last value written, a read without one gives nothing new and keeps the value.
TEST(TripleBuffer, ReadsGiveTheLastValueWrittenOverSeededRandomOperations) {
  for (unsigned seed = 1; seed <= 5; ++seed) {
    std::mt19937 random(seed);
    TripleBuffer<int> buffer(-1);
    int last_written = -1, last_read = -1;
    bool unread = false;
    for (int op = 0; op < 20000; ++op) {
      if (random() % 2 == 0) {
        buffer.write(op);
        last_written = op;
        unread = true;
      } else {
        ASSERT_EQ(buffer.update(), unread) << "seed " << seed << ", operation " << op;
        if (unread) last_read = last_written;
        unread = false;
        ASSERT_EQ(buffer.front(), last_read) << "seed " << seed << ", operation " << op;
      }
    }
  }
}

// 200,000 values of 64 equal numbers published by one thread while another takes them: every
// value taken is whole (all 64 numbers equal) and newer than the one before.
TEST(TripleBuffer, AConcurrentReaderSeesOnlyWholeValuesInOrder) {
  constexpr long kValues = 200000;
  TripleBuffer<std::vector<long>> buffer(std::vector<long>(64, 0));
  std::thread writer([&] {
    for (long v = 1; v <= kValues; ++v) {
      std::vector<long>& back = buffer.back();
      for (long& x : back) x = v;
      buffer.publish();
    }
  });
  long last = 0, torn = 0, older = 0, taken = 0;
  while (last < kValues) {
    if (!buffer.update()) continue;
    const std::vector<long>& value = buffer.front();
    for (const long x : value) torn += x != value[0];
    older += value[0] <= last;
    last = value[0];
    ++taken;
  }
  writer.join();
  EXPECT_EQ(torn, 0);
  EXPECT_EQ(older, 0);
  EXPECT_GT(taken, 0);
}

TEST(TripleBuffer, WritingAndReadingAllocateNothingOnceSized) {
  TripleBuffer<std::vector<double>> buffer(std::vector<double>(32, 0.0));
  const std::vector<double> value(32, 1.5);
  const long allocations = test_support::allocationsDuring([&] {
    for (int i = 0; i < 1000; ++i) {
      buffer.write(value);  // same size: assignment reuses the buffer's storage
      if (i % 3 == 0) (void)buffer.update();
    }
  });
  EXPECT_EQ(allocations, 0);
  EXPECT_EQ(buffer.front()[0], 1.5);
}

}  // namespace
}  // namespace cobra::core
