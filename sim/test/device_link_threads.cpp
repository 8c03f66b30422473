// The two sides of a simulated device on two threads (label concurrency, run under
// ThreadSanitizer by `./do test --tsan`): values cross whole and in order, the host never sees a
// torn value, and detach waits for the host calls in progress so the world's clock is never
// called after it returns.

#include <gtest/gtest.h>

#include <array>
#include <atomic>
#include <thread>

#include "cobra/sim/device_link.hpp"

namespace {

using cobra::sim::DeviceLink;
using cobra::sim::LinkTime;
using cobra::sim::SpscQueue;
using cobra::sim::StampedMailbox;

TEST(DeviceLinkThreads, QueueAndMailboxCarryWholeValuesInOrder) {
  constexpr int kCount = 50000;
  SpscQueue<int, 64> queue;
  StampedMailbox<std::array<int, 8>> box;  // every element equal: a torn read would show
  std::thread world([&] {
    for (int i = 1; i <= kCount; ++i) {
      while (!queue.push(i)) std::this_thread::yield();
      std::array<int, 8> value;
      value.fill(i);
      box.write(value, i);
    }
  });
  int expected = 1, last_seen = 0;
  while (expected <= kCount) {
    int v = 0;
    if (queue.front(v)) {
      ASSERT_EQ(v, expected);
      queue.pop();
      ++expected;
    }
    if (const std::array<int, 8>* seen = box.newest(LinkTime{})) {
      for (int x : *seen) ASSERT_EQ(x, (*seen)[0]);
      ASSERT_GE((*seen)[0], last_seen);  // never older than what was seen before
      last_seen = (*seen)[0];
    }
  }
  world.join();
}

TEST(DeviceLinkThreads, DetachWaitsForHostCallsInProgress) {
  for (int round = 0; round < 50; ++round) {
    DeviceLink link;
    std::atomic<bool> detached{false}, started{false};
    std::atomic<int> clock_calls_after{0};
    link.attach([&] {
      if (detached.load()) clock_calls_after.fetch_add(1);
      return std::int64_t{0};
    });
    std::thread host([&] {
      for (int i = 0; i < 2000; ++i) {
        const DeviceLink::Access access(link);
        started = true;
      }
    });
    while (!started.load()) std::this_thread::yield();  // detach while the host is calling
    link.detach();
    detached = true;
    host.join();
    EXPECT_EQ(clock_calls_after.load(), 0);
    EXPECT_FALSE(DeviceLink::Access(link).up());
  }
}

}  // namespace
