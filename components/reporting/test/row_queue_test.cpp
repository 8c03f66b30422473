// The Reporter's row queue (src/row_queue.hpp): rows come out whole and in order, a full queue
// refuses the next row (the Reporter counts it dropped) instead of blocking or allocating, and a
// half-full queue wakes the sleeping writer. A counting operator new proves the producer and the
// consumer allocate nothing once constructed.

#include "../src/row_queue.hpp"

#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <thread>

#include "cobra/test_support/counting_new.hpp"

namespace cobra::components::reporting_detail {
namespace {

using namespace std::chrono_literals;

void produce(RowQueue& queue, const std::string& text) {
  char* row = queue.beginRow();
  ASSERT_NE(row, nullptr) << "no room for \"" << text << "\"";
  ASSERT_LE(text.size(), queue.rowBytes());
  std::memcpy(row, text.data(), text.size());
  queue.commitRow(text.size());
}

std::string consume(RowQueue& queue) {
  std::string_view row;
  if (!queue.front(row)) return "<empty>";
  std::string text(row);
  queue.pop();
  return text;
}

TEST(RowQueue, RowsComeOutWholeInOrderAndAFullQueueRefusesTheNextUntilOneIsWritten) {
  RowQueue queue(3, 8);
  EXPECT_EQ(queue.capacity(), 3U);
  EXPECT_EQ(consume(queue), "<empty>");
  produce(queue, "a,1\n");
  produce(queue, "bb,22\n");
  produce(queue, "c\n");
  EXPECT_EQ(queue.beginRow(), nullptr) << "a full queue must refuse, not wait";
  std::string_view row;
  ASSERT_TRUE(queue.front(row));
  EXPECT_EQ(row, "a,1\n");
  ASSERT_TRUE(queue.front(row)) << "front gives the same row until pop";
  EXPECT_EQ(row, "a,1\n");
  EXPECT_EQ(queue.beginRow(), nullptr) << "the row being written is not free yet";
  queue.pop();
  produce(queue, "dddd,4\n");
  EXPECT_EQ(consume(queue), "bb,22\n");
  EXPECT_EQ(consume(queue), "c\n");
  EXPECT_EQ(consume(queue), "dddd,4\n");
  EXPECT_EQ(consume(queue), "<empty>");
}

TEST(RowQueue, ABegunRowIsTheSameSlotUntilCommitted) {
  RowQueue queue(2, 4);
  char* first = queue.beginRow();
  ASSERT_NE(first, nullptr);
  EXPECT_EQ(queue.beginRow(), first);  // e.g. an update that gave up formatting its row
  std::memcpy(first, "x\n", 2);
  queue.commitRow(2);
  EXPECT_EQ(consume(queue), "x\n");
}

TEST(RowQueue, AWriterAsleepIsWokenWhenTheQueueIsHalfFull) {
  RowQueue queue(4, 4);
  std::atomic<bool> stop{false};
  constexpr auto kTimeout = 60s;
  std::chrono::steady_clock::duration waited{};
  std::thread writer([&] {
    const auto start = std::chrono::steady_clock::now();
    queue.waitForRows(kTimeout, stop);
    waited = std::chrono::steady_clock::now() - start;
  });
  produce(queue, "1\n");  // a quarter full: the writer may sleep on
  while (!queue.consumerWaiting()) std::this_thread::yield();
  produce(queue, "2\n");  // half full: wakes the writer
  writer.join();
  // Not a timing check: unwoken, the wait lasts its whole timeout (a minute).
  EXPECT_LT(waited, kTimeout) << "the writer slept through the producer's half-full queue";
  EXPECT_EQ(consume(queue), "1\n");
}

TEST(RowQueue, ASteadyProducerAndTheWriterThreadLoseAndReorderNoRow) {
  constexpr int kRows = 20000;
  RowQueue queue(16, 16);
  std::atomic<bool> stop{false};
  std::vector<std::string> written;
  std::thread writer([&] {
    for (;;) {
      const bool stopping = stop.load();
      std::string_view row;
      while (queue.front(row)) {
        written.emplace_back(row);
        queue.pop();
      }
      if (stopping) break;
      queue.waitForRows(1ms, stop);
    }
  });
  int dropped = 0;
  std::vector<std::string> committed;
  for (int i = 0; i < kRows; ++i) {
    char* row = queue.beginRow();
    if (row == nullptr) {
      ++dropped;
      continue;
    }
    const std::string text = std::to_string(i) + "\n";
    std::memcpy(row, text.data(), text.size());
    queue.commitRow(text.size());
    committed.push_back(text);
  }
  stop = true;
  queue.wake();
  writer.join();
  EXPECT_EQ(written, committed);
  EXPECT_EQ(static_cast<int>(committed.size()) + dropped, kRows);
}

TEST(RowQueue, ProducingAndConsumingAllocateNothing) {
  const long at_construction = test_support::newCalls();
  RowQueue queue(8, 32);
  EXPECT_GT(test_support::newCalls() - at_construction, 0) << "the counter must see the slots being allocated";
  int dropped = 0;
  const long allocations = test_support::allocationsDuring([&] {
    std::string_view row;
    for (int i = 0; i < 1000; ++i) {
      if (char* slot = queue.beginRow()) {
        slot[0] = 'r';
        queue.commitRow(1);
      } else {
        ++dropped;
      }
      if (i % 3 == 0 && queue.front(row)) queue.pop();
    }
  });
  EXPECT_EQ(allocations, 0);
  EXPECT_GT(dropped, 0) << "the loop must also reach the full queue";
}

}  // namespace
}  // namespace cobra::components::reporting_detail
