// The impaired link between master and slave: constant delay, jitter, loss, no reordering seen by
// the receiver, seeded, allocation-free after construction, and bad parameters named.
#include "cobra/control/link_impairment.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "cobra/test_support/counting_new.hpp"

namespace cobra::control {
namespace {

constexpr double kDt = 1e-3;  // s: a 1 kHz loop sends and receives once per period

TEST(LinkImpairment, WithoutImpairmentASampleArrivesAtOnce) {
  LinkImpairment<int> link({});
  int out = -1;
  EXPECT_FALSE(link.receive(0.0, out));
  EXPECT_TRUE(link.send(0.0, 7));
  EXPECT_TRUE(link.receive(0.0, out));
  EXPECT_EQ(out, 7);
  EXPECT_FALSE(link.receive(0.001, out));  // nothing new
  EXPECT_EQ(out, 7);
}

TEST(LinkImpairment, AConstantDelayHoldsEverySampleForThatLong) {
  LinkImpairment<int> link({.delay = 0.05});
  int out = -1;
  for (int i = 0; i < 1000; ++i) {
    const double t = i * kDt;
    ASSERT_TRUE(link.send(t, i));
    const bool got = link.receive(t, out);
    if (i < 50) {
      EXPECT_FALSE(got) << "at step " << i;
    } else {
      ASSERT_TRUE(got) << "at step " << i;
      EXPECT_EQ(out, i - 50);  // the sample sent 50 ms (50 periods) before
      EXPECT_NEAR(t - link.deliveredSendTime(), 0.05, 1e-9);
    }
  }
  EXPECT_EQ(link.lost(), 0u);
  EXPECT_EQ(link.discardedLate(), 0u);
}

TEST(LinkImpairment, TheLossShareMatchesTheParameterOver1e5Samples) {
  for (const double loss : {0.0, 0.05, 0.2, 0.5}) {
    LinkImpairment<int> link({.loss = loss, .seed = 42});
    int received = 0, out = 0;
    constexpr int kSamples = 100000;
    for (int i = 0; i < kSamples; ++i) {
      link.send(i * kDt, i);
      if (link.receive(i * kDt, out)) ++received;
    }
    // Binomial: sd = sqrt(n p (1-p)) <= 158 samples; 1000 is more than 6 sd.
    EXPECT_NEAR(static_cast<double>(link.lost()), loss * kSamples, 1000.0) << "loss " << loss;
    EXPECT_EQ(static_cast<std::uint64_t>(received) + link.lost(), static_cast<std::uint64_t>(kSamples));
  }
}

TEST(LinkImpairment, JitteredDelaysStayInTheirWindowAndTheReceiverNeverSeesAnOlderSample) {
  LinkImpairment<int> link({.delay = 0.02, .jitter = 0.03, .loss = 0.1, .seed = 7});
  int out = -1, previous = -1;
  double shortest = 1e9, longest = -1e9;
  for (int i = 0; i < 100000; ++i) {
    const double t = i * kDt;
    link.send(t, i);
    if (link.receive(t, out)) {
      ASSERT_GT(out, previous) << "reordered at step " << i;
      previous = out;
      const double age = t - link.deliveredSendTime();
      shortest = std::min(shortest, age);
      longest = std::max(longest, age);
    }
  }
  EXPECT_GE(shortest, 0.02 - 1e-9);
  EXPECT_LE(longest, 0.05 + 1e-9);
  EXPECT_LT(shortest, 0.022);  // the window is used: the shortest and longest draws occur
  EXPECT_GT(longest, 0.04);  // rarer: a long draw is usually overtaken
  EXPECT_GT(link.discardedLate(), 1000u);  // jitter of 30 periods overtakes many samples
}

TEST(LinkImpairment, TheSameSeedGivesTheSameArrivalsAndAnotherSeedOthers) {
  auto run = [](std::uint64_t seed) {
    LinkImpairment<int> link({.delay = 0.01, .jitter = 0.02, .loss = 0.2, .seed = seed});
    std::vector<int> seen;
    int out = 0;
    for (int i = 0; i < 5000; ++i) {
      link.send(i * kDt, i);
      if (link.receive(i * kDt, out)) seen.push_back(out);
    }
    return seen;
  };
  EXPECT_EQ(run(3), run(3));
  EXPECT_NE(run(3), run(4));
}

TEST(LinkImpairment, AFullBufferRefusesAndCountsTheSample) {
  LinkImpairment<int> link({.delay = 1.0, .capacity = 3});
  EXPECT_TRUE(link.send(0.0, 1));
  EXPECT_TRUE(link.send(0.1, 2));
  EXPECT_TRUE(link.send(0.2, 3));
  EXPECT_FALSE(link.send(0.3, 4));
  EXPECT_EQ(link.overflowed(), 1u);
  EXPECT_EQ(link.lost(), 0u);
  int out = 0;
  ASSERT_TRUE(link.receive(1.15, out));  // samples 1 and 2 arrived: the newer is delivered
  EXPECT_EQ(out, 2);
  EXPECT_EQ(link.inFlight(), 1u);
  EXPECT_TRUE(link.send(1.15, 5));
  EXPECT_FALSE(link.send(1.0, 6)) << "a send back in time is refused";
}

TEST(LinkImpairment, SendAndReceiveAllocateNothing) {
  LinkImpairment<std::vector<double>::size_type> link({.delay = 0.05, .jitter = 0.02, .loss = 0.1});
  std::size_t out = 0;
  const long calls = test_support::allocationsDuring([&] {
    for (std::size_t i = 0; i < 20000; ++i) {
      link.send(static_cast<double>(i) * kDt, i);
      link.receive(static_cast<double>(i) * kDt, out);
    }
  });
  EXPECT_EQ(calls, 0);
  EXPECT_GT(out, 19000u);
}

TEST(LinkImpairment, BadParametersNameTheParameterAndTheRule) {
  auto message = [](LinkImpairmentParameters p) {
    try {
      LinkImpairment<int> link(p);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no exception");
  };
  EXPECT_EQ(message({.delay = -0.1}), "LinkImpairment: delay must be >= 0 (s), got -0.100000");
  EXPECT_EQ(message({.jitter = NAN}), "LinkImpairment: jitter must be >= 0 (s), got nan");
  EXPECT_EQ(message({.loss = 1.5}), "LinkImpairment: loss must be in [0, 1] (share of samples), got 1.500000");
  EXPECT_EQ(message({.capacity = 0}), "LinkImpairment: capacity must be >= 1 (samples in flight), got 0.000000");
}

}  // namespace
}  // namespace cobra::control
