// Unit tests of Channel<T> (channel.hpp) used directly, one thread: the data, buffer(n) and
// circular(n) policies, read statuses, and a seeded random comparison with a std::deque model.

#include <gtest/gtest.h>

#include <deque>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "cobra/core/channel.hpp"
#include "cobra/core/port.hpp"

namespace cobra::core {
namespace {

/// The two ports a channel links; the channel only keeps references to them.
struct Ends {
  OutputPort<int> out{"out", "writer end", "1"};
  InputPort<int> in{"in", "reader end", "1"};
};

struct ChannelTest : ::testing::Test {
  Ends ends;
};

TEST_F(ChannelTest, KnowsItsPolicyAndPorts) {
  Channel<int> ch(ConnPolicy::buffer(4), ends.out, ends.in, 0);
  EXPECT_EQ(ch.policy(), ConnPolicy::buffer(4));
  EXPECT_EQ(&ch.writer(), &ends.out);
  EXPECT_EQ(&ch.reader(), &ends.in);
  EXPECT_EQ(ch.unread(), 0U);
}

TEST_F(ChannelTest, NothingWrittenGivesNoDataAndLeavesOutUntouched) {
  Channel<int> ch(ConnPolicy::data(), ends.out, ends.in, 0);
  int out = 42;
  EXPECT_EQ(ch.pop(out), FlowStatus::NoData);
  EXPECT_EQ(out, 42);
  EXPECT_EQ(ch.pop(out, false), FlowStatus::NoData);
  EXPECT_EQ(out, 42);
}

TEST_F(ChannelTest, DataPolicyKeepsOnlyTheLatestValue) {
  Channel<int> ch(ConnPolicy::data(), ends.out, ends.in, 0);
  EXPECT_EQ(ch.push(1), WriteStatus::Written);
  EXPECT_EQ(ch.push(2), WriteStatus::Written);
  EXPECT_EQ(ch.push(3), WriteStatus::Written);
  EXPECT_EQ(ch.unread(), 1U);
  int out = 0;
  EXPECT_EQ(ch.pop(out), FlowStatus::NewData);
  EXPECT_EQ(out, 3);
  EXPECT_EQ(ch.unread(), 0U);
}

TEST_F(ChannelTest, ReadSequenceIsNoDataThenNewDataThenOldData) {
  Channel<int> ch(ConnPolicy::data(), ends.out, ends.in, 0);
  int out = -1;
  EXPECT_EQ(ch.pop(out), FlowStatus::NoData);
  ASSERT_EQ(ch.push(7), WriteStatus::Written);
  EXPECT_EQ(ch.pop(out), FlowStatus::NewData);
  EXPECT_EQ(out, 7);
  out = -1;
  EXPECT_EQ(ch.pop(out), FlowStatus::OldData);
  EXPECT_EQ(out, 7) << "OldData copies the last value again";
  ASSERT_EQ(ch.push(8), WriteStatus::Written);
  EXPECT_EQ(ch.pop(out), FlowStatus::NewData);
  EXPECT_EQ(out, 8);
  EXPECT_EQ(ch.pop(out), FlowStatus::OldData);
  EXPECT_EQ(out, 8);
}

TEST_F(ChannelTest, PopWithoutCopyLeavesOutUntouchedOnOldData) {
  Channel<int> ch(ConnPolicy::data(), ends.out, ends.in, 0);
  ASSERT_EQ(ch.push(5), WriteStatus::Written);
  int out = 0;
  ASSERT_EQ(ch.pop(out), FlowStatus::NewData);
  out = 99;
  EXPECT_EQ(ch.pop(out, false), FlowStatus::OldData);
  EXPECT_EQ(out, 99);
}

TEST_F(ChannelTest, BufferFillsToCapacityThenDropsAndKeepsTheOldest) {
  Channel<int> ch(ConnPolicy::buffer(3), ends.out, ends.in, 0);
  EXPECT_EQ(ch.push(1), WriteStatus::Written);
  EXPECT_EQ(ch.push(2), WriteStatus::Written);
  EXPECT_EQ(ch.push(3), WriteStatus::Written);
  EXPECT_EQ(ch.push(4), WriteStatus::Dropped);
  EXPECT_EQ(ch.push(5), WriteStatus::Dropped);
  EXPECT_EQ(ch.unread(), 3U);
  int out = 0;
  for (int expected : {1, 2, 3}) {
    EXPECT_EQ(ch.pop(out), FlowStatus::NewData);
    EXPECT_EQ(out, expected);
  }
  EXPECT_EQ(ch.pop(out), FlowStatus::OldData);
  EXPECT_EQ(out, 3);
  // Room again after reading.
  EXPECT_EQ(ch.push(6), WriteStatus::Written);
  EXPECT_EQ(ch.pop(out), FlowStatus::NewData);
  EXPECT_EQ(out, 6);
}

TEST_F(ChannelTest, BufferOfOneDropsUntilRead) {
  Channel<int> ch(ConnPolicy::buffer(1), ends.out, ends.in, 0);
  EXPECT_EQ(ch.push(1), WriteStatus::Written);
  EXPECT_EQ(ch.push(2), WriteStatus::Dropped);
  int out = 0;
  EXPECT_EQ(ch.pop(out), FlowStatus::NewData);
  EXPECT_EQ(out, 1);
  EXPECT_EQ(ch.push(3), WriteStatus::Written);
}

TEST_F(ChannelTest, CircularOverwritesTheOldest) {
  Channel<int> ch(ConnPolicy::circular(3), ends.out, ends.in, 0);
  for (int v = 1; v <= 5; ++v) EXPECT_EQ(ch.push(v), WriteStatus::Written);
  EXPECT_EQ(ch.unread(), 3U);
  int out = 0;
  for (int expected : {3, 4, 5}) {
    EXPECT_EQ(ch.pop(out), FlowStatus::NewData);
    EXPECT_EQ(out, expected);
  }
  EXPECT_EQ(ch.pop(out), FlowStatus::OldData);
  EXPECT_EQ(out, 5);
}

TEST_F(ChannelTest, CircularKeepsTheLastValueReadWhileOverwriting) {
  // The value returned as OldData lives in a slot the writer must not reuse.
  Channel<int> ch(ConnPolicy::circular(2), ends.out, ends.in, 0);
  ASSERT_EQ(ch.push(1), WriteStatus::Written);
  int out = 0;
  ASSERT_EQ(ch.pop(out), FlowStatus::NewData);
  for (int v = 10; v < 30; ++v) ASSERT_EQ(ch.push(v), WriteStatus::Written);
  out = 0;
  EXPECT_EQ(ch.pop(out, true), FlowStatus::NewData);
  EXPECT_EQ(out, 28);
  EXPECT_EQ(ch.pop(out, true), FlowStatus::NewData);
  EXPECT_EQ(out, 29);
  out = 0;
  EXPECT_EQ(ch.pop(out, true), FlowStatus::OldData);
  EXPECT_EQ(out, 29);
}

TEST_F(ChannelTest, NonTrivialValuesKeepTheirContent) {
  OutputPort<std::vector<double>> out{"out", "", "1"};
  InputPort<std::vector<double>> in{"in", "", "1"};
  Channel<std::vector<double>> ch(ConnPolicy::buffer(2), out, in, std::vector<double>(6, 0.0));
  ASSERT_EQ(ch.push({1, 2, 3}), WriteStatus::Written);
  ASSERT_EQ(ch.push({4, 5, 6, 7, 8, 9}), WriteStatus::Written);
  std::vector<double> got;
  EXPECT_EQ(ch.pop(got), FlowStatus::NewData);
  EXPECT_EQ(got, (std::vector<double>{1, 2, 3}));
  EXPECT_EQ(ch.pop(got), FlowStatus::NewData);
  EXPECT_EQ(got, (std::vector<double>{4, 5, 6, 7, 8, 9}));
}

TEST(ConnPolicyTest, FactoriesDescribeAndRefuseZero) {
  EXPECT_EQ(ConnPolicy::data().describe(), "data");
  EXPECT_EQ(ConnPolicy::data().size, 1U);
  EXPECT_EQ(ConnPolicy::buffer(8).describe(), "buffer(8)");
  EXPECT_EQ(ConnPolicy::circular(3).describe(), "circular(3)");
  try {
    (void)ConnPolicy::buffer(0);
    FAIL() << "buffer(0) accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("buffer(n) needs n >= 1"), std::string::npos) << e.what();
  }
  EXPECT_THROW((void)ConnPolicy::circular(0), Error);
  EXPECT_EQ(toString(FlowStatus::NoData), "NoData");
  EXPECT_EQ(toString(FlowStatus::OldData), "OldData");
  EXPECT_EQ(toString(FlowStatus::NewData), "NewData");
  EXPECT_EQ(toString(WriteStatus::Written), "Written");
  EXPECT_EQ(toString(WriteStatus::Dropped), "Dropped");
  EXPECT_EQ(toString(WriteStatus::NotConnected), "NotConnected");
}

// --- seeded random property test ----------------------------------------------------------------

/// Independent model of one connection: a deque of unread values plus the last value read.
class ReferenceChannel {
 public:
  explicit ReferenceChannel(ConnPolicy policy) : policy_(policy) {}

  WriteStatus push(int v) {
    if (queue_.size() == policy_.size) {
      if (policy_.kind == ConnPolicy::Kind::Buffer) return WriteStatus::Dropped;
      queue_.pop_front();
    }
    queue_.push_back(v);
    return WriteStatus::Written;
  }

  FlowStatus pop(int& out, bool copy_old) {
    if (!queue_.empty()) {
      last_ = queue_.front();
      queue_.pop_front();
      out = *last_;
      return FlowStatus::NewData;
    }
    if (!last_) return FlowStatus::NoData;
    if (copy_old) out = *last_;
    return FlowStatus::OldData;
  }

  std::size_t unread() const { return queue_.size(); }

 private:
  ConnPolicy policy_;
  std::deque<int> queue_;
  std::optional<int> last_;
};

TEST_F(ChannelTest, RandomPushPopMatchesADequeModelForEveryPolicyAndSize) {
  // 10000 random operations (seed 1234) for each of data, buffer(1..8) and circular(1..8):
  // 170000 operations in all. Pushes are drawn with a varying bias so that runs of full and
  // empty channels both occur.
  constexpr int kOpsPerCase = 10000;
  std::mt19937 rng(1234);
  std::vector<ConnPolicy> policies{ConnPolicy::data()};
  for (std::size_t n = 1; n <= 8; ++n) {
    policies.push_back(ConnPolicy::buffer(n));
    policies.push_back(ConnPolicy::circular(n));
  }
  int next_value = 1;
  for (const ConnPolicy& policy : policies) {
    SCOPED_TRACE(policy.describe());
    Channel<int> ch(policy, ends.out, ends.in, 0);
    ReferenceChannel model(policy);
    std::bernoulli_distribution push_bias(0.5);
    for (int op = 0; op < kOpsPerCase; ++op) {
      if (op % 500 == 0) push_bias = std::bernoulli_distribution(std::uniform_real_distribution<double>(0.1, 0.9)(rng));
      if (push_bias(rng)) {
        const int v = next_value++;
        ASSERT_EQ(ch.push(v), model.push(v)) << "op " << op;
      } else {
        const bool copy_old = rng() % 2 == 0;
        int got = -7;
        int expected = -7;
        ASSERT_EQ(ch.pop(got, copy_old), model.pop(expected, copy_old)) << "op " << op;
        ASSERT_EQ(got, expected) << "op " << op;
      }
      ASSERT_EQ(ch.unread(), model.unread()) << "op " << op;
    }
  }
}

}  // namespace
}  // namespace cobra::core
