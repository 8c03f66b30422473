// OmniPhantomBridge over TCP on 127.0.0.1 against the simulated Omni application, and against a
// raw test server that sends crafted frames.
#include "cobra/bridges/omni_phantom_bridge.hpp"

#include <gtest/gtest.h>

#include <limits>

#include "bridge_test_support.hpp"
#include "cobra/bridges/isur_udp_server.hpp"
#include "cobra/bridges/sim/omni_server.hpp"

namespace cobra::bridges {
namespace {

using namespace std::chrono_literals;
using test::pollUntil;

struct Rig {
  core::LockstepClock clock;
  OmniPhantomBridge bridge{"omni"};
  core::OutputPort<KDL::Wrench> des_wrench{"des_wrench", "", "N"};
  core::InputPort<KDL::Frame> meas_pose{"meas_pose", "", "m"};
  core::InputPort<KDL::Twist> meas_twist{"meas_twist", "", "m/s"};
  core::InputPort<int> buttons{"buttons", "", "1"};
  test::EventLog events{bridge};

  explicit Rig(std::uint16_t port, const KDL::Frame& offset = KDL::Frame::Identity()) {
    clock.add(bridge, 1ms);
    core::connectPorts(des_wrench, bridge.port("desWrench"));
    core::connectPorts(bridge.port("measCartPose"), meas_pose);
    core::connectPorts(bridge.port("measTwist"), meas_twist);
    core::connectPorts(bridge.port("statusButtons"), buttons);
    bridge.setProperty("host_port", static_cast<int>(port));
    bridge.setProperty("origin_pose_offset", offset);
    bridge.setProperty("timeout", 0.05);
    bridge.setProperty("reconnect_period", 0.01);
    const core::Result configured = bridge.configure();
    EXPECT_TRUE(configured) << configured.message;
    EXPECT_TRUE(bridge.start());
  }
  ~Rig() { (void)bridge.stop(); }
  int rejected(const char* reason) { return bridge.call<int>("rejectedCount", std::string(reason)); }
};

TEST(OmniPhantomBridge, FollowsTheSimulatedHandRendersTheWrenchAndReportsButtons) {
  OmniSimServer app(OmniSimServerOptions{});
  app.start();
  // The ports' base frame: the device turned 90° about z and 1 m up.
  const KDL::Frame offset(KDL::Rotation::RotZ(M_PI / 2), KDL::Vector(0, 0, 1));
  Rig rig(app.local().port(), offset);
  app.setHandTarget(KDL::Vector(0.02, 0, 0));
  app.setButtons(1);
  KDL::Frame pose;
  int buttons = 0;
  ASSERT_TRUE(pollUntil(rig.clock, [&] {
    rig.buttons.read(buttons);
    return rig.meas_pose.read(pose) != core::FlowStatus::NoData && buttons == 1 &&
           KDL::Equal(pose.p, KDL::Vector(0, 0.02, 1), 1e-3);  // device x is base y
  })) << pose.p.x() << " " << pose.p.y() << " " << pose.p.z();
  EXPECT_TRUE(KDL::Equal(pose.p, offset * app.position(), 2e-3));
  // A force along base x is device -y.
  rig.des_wrench.write(KDL::Wrench(KDL::Vector(1.0, 0, 0), KDL::Vector::Zero()));
  ASSERT_TRUE(pollUntil(rig.clock, [&] { return KDL::Equal(app.commandedForce(), KDL::Vector(0, -1.0, 0), 1e-12); }));
  EXPECT_EQ(rig.rejected("all"), 0);
  EXPECT_EQ(app.counters().rejected(), 0U);
}

TEST(OmniPhantomBridge, ReconnectsAfterTheApplicationDropsAndRaisesTimeoutThenRestored) {
  OmniSimServer app(OmniSimServerOptions{});
  app.start();
  Rig rig(app.local().port());
  KDL::Frame held;
  // A state accepted AND published before the application falls silent (under load the bridge's
  // step that publishes may come after the one that counted it).
  ASSERT_TRUE(pollUntil(rig.clock, [&] {
    return rig.bridge.call<int>("acceptedCount") > 0 && rig.meas_pose.read(held) != core::FlowStatus::NoData;
  }));
  app.setSending(false);
  ASSERT_TRUE(pollUntil(rig.clock, [&] { return rig.events.last() == "e_comm_timeout"; }));
  EXPECT_NE(rig.meas_pose.read(held), core::FlowStatus::NoData) << "the last valid state is still published";
  app.setSending(true);
  ASSERT_TRUE(pollUntil(rig.clock, [&] { return rig.events.last() == "e_comm_restored"; }));
  app.dropClient();
  ASSERT_TRUE(pollUntil(rig.clock, [&] { return rig.bridge.call<int>("connections") >= 2; }));
  const int before = rig.bridge.call<int>("acceptedCount");
  ASSERT_TRUE(pollUntil(rig.clock, [&] { return rig.bridge.call<int>("acceptedCount") > before; }));
}

// A raw server: accepts the bridge and writes crafted frames into the stream.
struct RawApp {
  TcpListener listener{"127.0.0.1", 0};
  FileDescriptor client;
  std::uint32_t sequence = 0;
  std::vector<std::uint8_t> frame(const omni::State& s, std::uint32_t seq, std::int64_t age_ns = 0) {
    std::vector<std::uint8_t> out(omni::kMaxFrameSize);
    out.resize(omni::encode(s, {seq, static_cast<std::uint64_t>(steadyNanoseconds() - age_ns)}, out));
    return out;
  }
  void send(const std::vector<std::uint8_t>& bytes) {
    ASSERT_EQ(sendAll(client.get(), bytes, 1000), IoResult::Done);
  }
};

TEST(OmniPhantomBridge, CorruptLateAndDelayedFramesAreCountedABrokenHeaderDropsTheConnection) {
  RawApp app;
  Rig rig(app.listener.local().port());
  ASSERT_TRUE(pollUntil(rig.clock, [&] {
    if (!app.client.valid()) app.client = app.listener.accept(0);
    return app.client.valid();
  }));
  omni::State valid;
  valid.position = {0.01, 0.02, 0.03};
  app.send(app.frame(valid, 10));
  KDL::Frame pose;
  ASSERT_TRUE(pollUntil(rig.clock, [&] {
    return rig.meas_pose.read(pose) != core::FlowStatus::NoData &&
           KDL::Equal(pose.p, KDL::Vector(0.01, 0.02, 0.03), 1e-12);
  }));
  omni::State moved = valid;
  moved.position[0] = 0.05;
  auto corrupt = app.frame(moved, 11);
  corrupt[40] ^= 0x02;
  app.send(corrupt);                                  // bad CRC: skipped, stream stays in step
  app.send(app.frame(moved, 10));                     // late
  app.send(app.frame(moved, 12, 1'000'000'000));      // delayed by 1 s
  omni::State nan = moved;
  nan.twist[4] = std::numeric_limits<double>::infinity();
  app.send(app.frame(nan, 13));                       // non-finite
  auto half = app.frame(moved, 14);                   // a frame split in two writes is fine
  app.send(std::vector<std::uint8_t>(half.begin(), half.begin() + 20));
  ASSERT_TRUE(pollUntil(rig.clock, [&] { return rig.rejected("all") == 4; })) << rig.rejected("all");
  EXPECT_EQ(rig.rejected("bad_crc"), 1);
  EXPECT_EQ(rig.rejected("late"), 1);
  EXPECT_EQ(rig.rejected("delayed"), 1);
  EXPECT_EQ(rig.rejected("non_finite"), 1);
  for (int i = 0; i < 5; ++i) rig.clock.advance(1ms);
  ASSERT_NE(rig.meas_pose.read(pose), core::FlowStatus::NoData);
  EXPECT_TRUE(KDL::Equal(pose.p, KDL::Vector(0.01, 0.02, 0.03), 1e-12)) << "last valid state kept";
  app.send(std::vector<std::uint8_t>(half.begin() + 20, half.end()));
  ASSERT_TRUE(pollUntil(rig.clock, [&] {
    return rig.meas_pose.read(pose) != core::FlowStatus::NoData &&
           KDL::Equal(pose.p, KDL::Vector(0.05, 0.02, 0.03), 1e-12);
  }));
  // Garbage where a header should be: frame boundaries are lost, the bridge drops and reconnects.
  app.send(std::vector<std::uint8_t>(30, 0x55));
  ASSERT_TRUE(pollUntil(rig.clock, [&] { return rig.rejected("bad_magic") == 1; }));
  ASSERT_TRUE(pollUntil(rig.clock, [&] {
    FileDescriptor again = app.listener.accept(0);
    if (again.valid()) app.client = std::move(again);
    return rig.bridge.call<int>("connections") == 2;
  }));
}

TEST(OmniPhantomBridge, RefusesToConfigureWithoutAPort) {
  OmniPhantomBridge bridge("omni");
  const core::Result r = bridge.configure();
  ASSERT_FALSE(r);
  EXPECT_NE(r.message.find("host_port is 0"), std::string::npos) << r.message;
}

}  // namespace
}  // namespace cobra::bridges
