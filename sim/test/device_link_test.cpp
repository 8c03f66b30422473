// DeviceLink, StampedMailbox, SpscQueue: the ordering rule (a value is seen only at a later time
// than its stamp) holds whichever side runs first in an instant; without a clock everything is
// seen at once; a detached link is down for the host; the queues keep order and bounds. (The two
// sides on two threads: device_link_threads.cpp, label concurrency.)

#include "cobra/sim/device_link.hpp"

#include <gtest/gtest.h>

#include "cobra/sim/leap_motion_device.hpp"

namespace {

using cobra::sim::DeviceLink;
using cobra::sim::LinkTime;
using cobra::sim::SpscQueue;
using cobra::sim::StampedMailbox;

TEST(StampedMailbox, TheReaderSeesTheValueOfEarlierInstantsWhicheverSideRunsFirst) {
  // Instants 1..5; the writer writes 10·t at each. Reading at t gives 10·(t-1) in both orders.
  for (bool writer_first : {true, false}) {
    StampedMailbox<int> box;
    std::vector<int> seen;
    for (std::int64_t t = 1; t <= 5; ++t) {
      const LinkTime time{true, t};
      if (writer_first) box.write(static_cast<int>(10 * t), t);
      const int* v = box.newest(time);
      seen.push_back(v ? *v : -1);
      if (!writer_first) box.write(static_cast<int>(10 * t), t);
    }
    EXPECT_EQ(seen, (std::vector<int>{-1, 10, 20, 30, 40})) << (writer_first ? "writer first" : "reader first");
  }
}

TEST(StampedMailbox, ASecondWriteInTheSameInstantReplacesTheFirstAndUnclockedReadersSeeAll) {
  StampedMailbox<int> box;
  box.write(1, 1);
  box.write(2, 2);
  box.write(3, 2);
  EXPECT_EQ(*box.newest({true, 2}), 1);  // the newest before instant 2
  EXPECT_EQ(*box.newest({true, 3}), 3);
  EXPECT_EQ(*box.newest({}), 3);  // no clock: at once
  box.write(4, 3);
  EXPECT_EQ(*box.newest({}), 4);
}

TEST(DeviceLink, ClockedDetachedAndDirect) {
  DeviceLink link;
  {
    DeviceLink::Access a(link);
    EXPECT_TRUE(a.up());
    EXPECT_FALSE(a.time().clocked);
  }
  std::int64_t now = 42;
  link.attach([&] { return now; });
  EXPECT_EQ(link.worldTime().now, 42);
  {
    DeviceLink::Access a(link);
    EXPECT_TRUE(a.up());
    EXPECT_TRUE(a.time().visible(41));
    EXPECT_FALSE(a.time().visible(42));
  }
  link.detach();
  DeviceLink::Access a(link);
  EXPECT_FALSE(a.up());
}

TEST(SpscQueue, KeepsOrderAndRefusesWhenFull) {
  SpscQueue<int, 3> q;
  EXPECT_TRUE(q.push(1));
  EXPECT_TRUE(q.push(2));
  EXPECT_TRUE(q.push(3));
  EXPECT_FALSE(q.push(4));
  int v = 0;
  for (int expected : {1, 2, 3}) {
    ASSERT_TRUE(q.front(v));
    EXPECT_EQ(v, expected);
    q.pop();
  }
  EXPECT_FALSE(q.front(v));
}

TEST(LeapMotionDevice, TheHostTakesEachFrameOnceFromTheWorldsPreviousSteps) {
  cobra::sim::HandTrackerModel model;
  model.position_noise = 0.0;
  cobra::sim::LeapMotionDevice device(model, 1);
  std::int64_t now = 0;
  device.link().attach([&] { return now; });
  const KDL::Frame hand(KDL::Vector(0.0, 0.0, 0.2));
  cobra::fieldbus::HandFrame frame;
  int taken = 0;
  for (int ms = 0; ms < 100; ++ms) {  // 1 ms steps: a frame every 5 ms
    now = ms * 1'000'000;
    if (device.takeFrame(frame)) {
      ++taken;
      EXPECT_TRUE(frame.right.valid);
      EXPECT_FALSE(frame.left.valid);
    }
    device.step(1e-3, true, hand, false, KDL::Frame::Identity());
  }
  // 20 frames fell due in the 100 steps; the last one, produced at the last step, is not seen yet.
  EXPECT_EQ(device.tracker().frame().id, 20U);
  EXPECT_EQ(taken, 19);
  EXPECT_FALSE(device.takeFrame(frame));  // the same instant still
  now += 1'000'000;
  EXPECT_TRUE(device.takeFrame(frame));
  EXPECT_EQ(frame.id, 20U);
  EXPECT_FALSE(device.takeFrame(frame));  // once
}

}  // namespace
