// The queue that carries the DdsLink's events from foreign threads to its own step
// (dds/src/event_queue.hpp): every event once, in each producer's order, none lost while there
// is room; a full queue refuses and counts; push and pop allocate nothing.
#include "event_queue.hpp"

#include <gtest/gtest.h>

#include <string>
#include <thread>
#include <vector>

#include "cobra/test_support/counting_new.hpp"

namespace cobra::dds::detail {
namespace {

core::Event numbered(int producer, long sequence) {
  core::Event e;
  e.name.assign("e_" + std::to_string(producer));
  e.source.assign("producer " + std::to_string(producer));
  e.stamp = std::chrono::nanoseconds(sequence);
  return e;
}

TEST(EventQueue, FourProducersAndOneConsumerPassEveryEventOnceInEachProducersOrder) {
  constexpr int kProducers = 4;
  constexpr long kEach = 20000;
  EventQueue<64> queue;  // small: producers often find it full and retry
  std::vector<std::thread> producers;
  for (int p = 0; p < kProducers; ++p)
    producers.emplace_back([&queue, p] {
      for (long k = 0; k < kEach; ++k)
        while (!queue.push(numbered(p, k))) std::this_thread::yield();
    });
  std::vector<long> next(kProducers, 0);
  long received = 0;
  core::Event e;
  while (received < kProducers * kEach) {
    if (!queue.pop(e)) {
      std::this_thread::yield();
      continue;
    }
    const int p = e.name.str().back() - '0';
    ASSERT_GE(p, 0);
    ASSERT_LT(p, kProducers);
    ASSERT_EQ(e.source.str(), "producer " + std::to_string(p));
    ASSERT_EQ(e.stamp.count(), next[p]) << "producer " << p << "'s events out of order, lost or twice";
    ++next[p];
    ++received;
  }
  for (auto& t : producers) t.join();
  EXPECT_FALSE(queue.pop(e)) << "nothing more than what was pushed";
  for (int p = 0; p < kProducers; ++p) EXPECT_EQ(next[p], kEach);
}

TEST(EventQueue, AFullQueueRefusesAndCountsAndFreesRoomAsItIsRead) {
  EventQueue<4> queue;
  for (long k = 0; k < 4; ++k) EXPECT_TRUE(queue.push(numbered(0, k)));
  EXPECT_FALSE(queue.push(numbered(0, 4)));
  EXPECT_EQ(queue.dropped(), 1U);
  core::Event e;
  ASSERT_TRUE(queue.pop(e));
  EXPECT_EQ(e.stamp.count(), 0);
  EXPECT_TRUE(queue.push(numbered(0, 5)));
  for (long expected : {1, 2, 3, 5}) {
    ASSERT_TRUE(queue.pop(e));
    EXPECT_EQ(e.stamp.count(), expected);
  }
  EXPECT_FALSE(queue.pop(e));
  EXPECT_EQ(queue.dropped(), 1U);
}

TEST(EventQueue, PushAndPopAllocateNothing) {
  EventQueue<8> queue;
  const core::Event event = numbered(1, 7);
  core::Event out;
  EXPECT_EQ(cobra::test_support::allocationsDuring([&] {
              for (int k = 0; k < 100; ++k) {
                queue.push(event);
                queue.pop(out);
              }
            }),
            0);
  EXPECT_EQ(out, event);
}

}  // namespace
}  // namespace cobra::dds::detail
