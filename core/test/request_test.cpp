#include "cobra/core/request.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <thread>

#include "cobra/test_support/counting_new.hpp"

namespace cobra::core {
namespace {

TEST(PendingRequest, AskWakesTheActivityAndIsTakenOnce) {
  SlaveActivity activity;
  PendingRequest request;
  EXPECT_FALSE(request.take());
  request.ask(activity);
  EXPECT_TRUE(activity.triggered());
  EXPECT_TRUE(request.take());
  EXPECT_FALSE(request.take());
}

TEST(PendingRequest, TwoAsksBeforeTheStepAreAnsweredOnceAndClearForgets) {
  SlaveActivity activity;
  PendingRequest request;
  request.ask(activity);
  request.ask(activity);
  EXPECT_TRUE(request.take());
  EXPECT_FALSE(request.take());
  request.ask(activity);
  request.clear();
  EXPECT_FALSE(request.take());
}

TEST(PendingRequest, AskAndTakeAllocateNothing) {
  SlaveActivity activity;
  PendingRequest request;
  EXPECT_EQ(test_support::allocationsDuring([&] {
              for (int i = 0; i < 100; ++i) {
                request.ask(activity);
                (void)request.take();
              }
            }),
            0);
}

// An ask from another thread is never lost: once the asker has finished, the taker has seen
// (through the request's release/acquire) everything written before the last ask.
TEST(PendingRequest, NoAskFromAnotherThreadIsLost) {
  constexpr int kAsks = 20000;
  SlaveActivity activity;
  PendingRequest request;
  std::atomic<int> written{0};
  std::atomic<bool> finished{false};
  std::thread asker([&] {
    for (int i = 1; i <= kAsks; ++i) {
      written.store(i, std::memory_order_relaxed);
      request.ask(activity);
    }
    finished.store(true, std::memory_order_release);
  });
  int seen = 0;
  for (;;) {
    const bool was_finished = finished.load(std::memory_order_acquire);
    if (request.take()) seen = written.load(std::memory_order_relaxed);
    if (was_finished) break;
  }
  asker.join();
  EXPECT_EQ(seen, kAsks);
}

}  // namespace
}  // namespace cobra::core
