// The triple buffer between the run's thread and the server's (studio/include/cobra/studio/
// triple_buffer.hpp): the reader only ever sees whole values, newest first, never older ones.

#include <gtest/gtest.h>

#include <thread>
#include <vector>

#include "cobra/studio/triple_buffer.hpp"

namespace cobra::studio {
namespace {

TEST(TripleBuffer, TheReaderTakesTheNewestValueOnceAndKeepsItUntilANewerOne) {
  TripleBuffer<int> buffer(0);
  EXPECT_FALSE(buffer.update());
  buffer.back() = 1;
  buffer.publish();
  buffer.back() = 2;
  buffer.publish();
  ASSERT_TRUE(buffer.update());
  EXPECT_EQ(buffer.front(), 2);
  EXPECT_FALSE(buffer.update());
  EXPECT_EQ(buffer.front(), 2);
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

}  // namespace
}  // namespace cobra::studio
