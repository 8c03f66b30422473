// TeleoperationClutch on the lockstep clock: nothing before the tool's pose, the tool's pose
// before the device's first sample; at the
// engagement the set-point is the tool's pose (no jump), then the device's motion since then
// (translation scaled, rotation in world axes); a restart engages again; a bad scale is refused
// naming it; updates allocate nothing.
#include "cobra/components/control/teleoperation_clutch.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "cobra/core/core.hpp"
#include "cobra/test_support/counting_new.hpp"
#include "cobra/test_support/test_support.hpp"

namespace cobra::components {
namespace {

using namespace std::chrono_literals;

struct Bench {
  TeleoperationClutch clutch{"RightClutch"};
  core::LockstepClock clock;
  core::OutputPort<KDL::Frame> master{"master", "", "m"}, slave{"slave", "", "m"};
  core::InputPort<KDL::Frame> des{"des", "", "m"};
  Bench() {
    clock.add(clutch, 1ms);
    core::connectPorts(master, clutch.port("masterPose"));
    core::connectPorts(slave, clutch.port("slavePose"));
    core::connectPorts(clutch.port("desPose"), des);
  }
  void start() {
    ASSERT_TRUE(clutch.configure());
    ASSERT_TRUE(clutch.start());
  }
  void step() { clock.advance(1ms); }
  core::FlowStatus read(KDL::Frame& out) { return des.read(out); }
};

const KDL::Frame kTool(KDL::Rotation::RPY(3.1, 0.1, 0.2), KDL::Vector(0.18, 0.0, 0.12));
const KDL::Frame kDevice(KDL::Rotation::RPY(0.0, 0.3, -0.4), KDL::Vector(0.02, -0.05, 0.1));

TEST(TeleoperationClutch, TheToolFollowsTheDevicesMotionFromWhereBothWereAtTheEngagement) {
  Bench b;
  b.clutch.setProperty("scale", 0.5);
  b.start();
  KDL::Frame out;
  b.master.write(kDevice);
  b.step();
  EXPECT_EQ(b.read(out), core::FlowStatus::NoData);  // no tool pose yet
  b.slave.write(kTool);
  b.step();
  ASSERT_EQ(b.read(out), core::FlowStatus::NewData);
  EXPECT_TRUE(KDL::Equal(out, kTool, 1e-12));  // engaged: no jump
  const KDL::Rotation turn = KDL::Rotation::RotZ(0.25);
  b.master.write(KDL::Frame(turn * kDevice.M, kDevice.p + KDL::Vector(0.01, 0.0, -0.02)));
  b.slave.write(KDL::Frame(kTool.M, kTool.p + KDL::Vector(0.0, 0.0, 0.001)));  // the tool moved meanwhile
  b.step();
  ASSERT_EQ(b.read(out), core::FlowStatus::NewData);
  EXPECT_TRUE(KDL::Equal(out.p, kTool.p + KDL::Vector(0.005, 0.0, -0.01), 1e-12));
  EXPECT_TRUE(KDL::Equal(out.M, turn * kTool.M, 1e-12));
  b.step();
  EXPECT_EQ(b.read(out), core::FlowStatus::OldData);  // nothing new from the device: nothing written

  ASSERT_TRUE(b.clutch.stop());  // a new teleoperation engages again, from where both are now
  ASSERT_TRUE(b.clutch.start());
  b.step();
  ASSERT_EQ(b.read(out), core::FlowStatus::NewData);
  EXPECT_TRUE(KDL::Equal(out.p, kTool.p + KDL::Vector(0.0, 0.0, 0.001), 1e-12));
}

// A device behind a delayed link: until its first sample arrives the set-point is the tool's
// measured pose (a coupling reading it sees no offset); the first sample engages from there.
TEST(TeleoperationClutch, WithoutADeviceSampleTheSetPointIsTheToolsPose) {
  Bench b;
  b.start();
  KDL::Frame out;
  b.slave.write(kTool);
  b.step();
  ASSERT_EQ(b.read(out), core::FlowStatus::NewData);
  EXPECT_TRUE(KDL::Equal(out, kTool, 1e-12));
  const KDL::Frame moved(kTool.M, kTool.p + KDL::Vector(0.0, 0.002, 0.0));
  b.slave.write(moved);
  b.step();
  ASSERT_EQ(b.read(out), core::FlowStatus::NewData);
  EXPECT_TRUE(KDL::Equal(out, moved, 1e-12));
  b.master.write(kDevice);
  b.step();
  ASSERT_EQ(b.read(out), core::FlowStatus::NewData);
  EXPECT_TRUE(KDL::Equal(out, moved, 1e-12));  // engaged where the tool was: no jump
  b.master.write(KDL::Frame(kDevice.M, kDevice.p + KDL::Vector(0.01, 0.0, 0.0)));
  b.step();
  ASSERT_EQ(b.read(out), core::FlowStatus::NewData);
  EXPECT_TRUE(KDL::Equal(out.p, moved.p + KDL::Vector(0.01, 0.0, 0.0), 1e-12));
}

// A noisy tracker: the engagement position is the mean of the samples of the first
// engagement_time.
TEST(TeleoperationClutch, TheEngagementAveragesTheDevicesFirstSamples) {
  Bench b;
  b.clutch.setProperty("engagement_time", 0.003);  // s: 4 samples, 1 ms apart
  b.start();
  KDL::Frame out;
  b.slave.write(kTool);
  const double noise[] = {0.001, -0.0005, 0.0007, -0.0012};  // m, along x: mean 0
  for (int k = 0; k < 4; ++k) {
    b.master.write(KDL::Frame(kDevice.M, kDevice.p + KDL::Vector(noise[k], 0.0, 0.0)));
    b.step();
    ASSERT_EQ(b.read(out), core::FlowStatus::NewData);
    // Averaging, then engaged: the tool's pose at the first sample, though it moved since.
    EXPECT_TRUE(KDL::Equal(out, kTool, 1e-12)) << k;
    b.slave.write(KDL::Frame(kTool.M, kTool.p + KDL::Vector(0.0, 0.0, 0.001 * (k + 1))));
  }
  b.master.write(kDevice);  // the device at the samples' mean
  b.step();
  ASSERT_EQ(b.read(out), core::FlowStatus::NewData);
  EXPECT_TRUE(KDL::Equal(out.p, kTool.p, 1e-12));
  b.master.write(KDL::Frame(kDevice.M, kDevice.p + KDL::Vector(0.002, 0.0, 0.0)));
  b.step();
  ASSERT_EQ(b.read(out), core::FlowStatus::NewData);
  EXPECT_TRUE(KDL::Equal(out.p, kTool.p + KDL::Vector(0.002, 0.0, 0.0), 1e-12));
  b.clutch.setProperty("engagement_time", -0.1);
  ASSERT_TRUE(b.clutch.stop());
  ASSERT_TRUE(b.clutch.cleanup());
  EXPECT_EQ(b.clutch.configure().message,
            "component 'RightClutch': property engagement_time is -0.100000 s; expected a finite value >= 0");
}

// A jittery tracker: with smoothing_time the set-point follows the device's positions through a
// first-order filter stepped by the time between samples.
TEST(TeleoperationClutch, SmoothingFiltersTheDevicesPositions) {
  Bench b;
  b.clutch.setProperty("smoothing_time", 0.01);
  b.start();
  KDL::Frame out;
  b.slave.write(kTool);
  b.master.write(kDevice);
  b.step();  // engaged
  b.master.write(KDL::Frame(kDevice.M, kDevice.p + KDL::Vector(0.0, 0.0, 0.01)));
  b.step();  // 1 ms after the engagement sample: 1 - e^(-0.1) of the way
  ASSERT_EQ(b.read(out), core::FlowStatus::NewData);
  EXPECT_NEAR(out.p.z() - kTool.p.z(), 0.01 * (1.0 - std::exp(-0.1)), 1e-9);
  for (int k = 0; k < 4; ++k) b.step();  // no new sample: nothing written, nothing filtered
  b.master.write(KDL::Frame(kDevice.M, kDevice.p + KDL::Vector(0.0, 0.0, 0.01)));
  b.step();  // 5 ms after the previous sample
  ASSERT_EQ(b.read(out), core::FlowStatus::NewData);
  EXPECT_NEAR(out.p.z() - kTool.p.z(), 0.01 * (1.0 - std::exp(-0.6)), 1e-9);
  b.clutch.setProperty("smoothing_time", -1.0);
  ASSERT_TRUE(b.clutch.stop());
  ASSERT_TRUE(b.clutch.cleanup());
  EXPECT_EQ(b.clutch.configure().message,
            "component 'RightClutch': property smoothing_time is -1.000000 s; expected a finite value >= 0");
}

TEST(TeleoperationClutch, ABadScaleIsRefusedNamingIt) {
  Bench b;
  b.clutch.setProperty("scale", 0.0);
  EXPECT_EQ(b.clutch.configure().message, "component 'RightClutch': property scale is 0.000000; expected a finite value > 0");
}

TEST(TeleoperationClutch, UpdatesAllocateNothing) {
  Bench b;
  b.start();
  b.slave.write(kTool);
  b.master.write(kDevice);
  b.step();
  const long calls = test_support::allocationsDuring([&] {
    for (int i = 0; i < 200; ++i) {
      b.master.write(KDL::Frame(kDevice.M, kDevice.p + KDL::Vector(1e-5 * i, 0.0, 0.0)));
      b.slave.write(kTool);
      b.step();
    }
  });
  EXPECT_EQ(calls, 0);
}

}  // namespace
}  // namespace cobra::components
