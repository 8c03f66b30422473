// LeapMotionDriver on the lockstep clock, on the simulated tracker of a SimulatedLeapMotion
// component found through its `device` property: 200 fps frames, positions clamped to the
// interaction box, then scaled, then expressed through the workspace offset; hands lost and found
// with events and the last valid pose kept; each hand's twist, differenced and filtered; no
// allocation; messages of bad properties.

#include "cobra/components/drivers/leap_motion_driver.hpp"

#include <gtest/gtest.h>

#include "cobra/components/sim/simulated_leap_motion.hpp"
#include "cobra/core/lockstep_clock.hpp"
#include "cobra/test_support/counting_new.hpp"
#include "cobra/test_support/test_support.hpp"

#include <cmath>
#include <cstdio>

namespace cobra::components {
namespace {

using namespace std::chrono_literals;

struct Bench {
  SimulatedLeapMotion tracker{"LeapSim"};
  LeapMotionDriver leap{"Leap"};
  core::LockstepClock clock;
  core::InputPort<core::Event> events{"events", "", ""};
  core::OutputPort<KDL::Frame> right{"right", "", "m"}, left{"left", "", "m"};
  core::InputPort<KDL::Frame> right_pose{"rp", "", "m"}, left_pose{"lp", "", "m"};
  core::InputPort<KDL::Frame> right_frames{"rf", "", "m"};

  core::InputPort<KDL::Twist> right_twist{"rt", "", "m/s, rad/s"}, left_twist{"lt", "", "m/s, rad/s"};

  explicit Bench(double scale = 1.0, const KDL::Frame& offset = KDL::Frame::Identity(), double noise = 0.0,
                 double filter_time = 0.05) {
    tracker.setProperty("noise", noise);
    leap.setProperty("twist_filter_time", filter_time);
    leap.setProperty("device", "sim:LeapSim");
    leap.setProperty("workspace_scale", scale);
    leap.setProperty("workspace_offset", offset);
    leap.setProperty("interaction_box", std::vector<double>{-0.1, -0.05, 0.1, 0.1, 0.05, 0.3});
    clock.add(tracker, 1ms);
    clock.add(leap, 1ms);
    core::connectPorts(leap.port("events"), events, core::ConnPolicy::buffer(64));
    core::connectPorts(right, tracker.port("rightHand"));
    core::connectPorts(left, tracker.port("leftHand"));
    core::connectPorts(leap.port("measRightPose"), right_pose);
    core::connectPorts(leap.port("measLeftPose"), left_pose);
    core::connectPorts(leap.port("measRightPose"), right_frames, core::ConnPolicy::buffer(1024));
    core::connectPorts(leap.port("measRightTwist"), right_twist);
    core::connectPorts(leap.port("measLeftTwist"), left_twist);
    EXPECT_TRUE(tracker.configure());
    EXPECT_TRUE(leap.configure());
    EXPECT_TRUE(tracker.start());
    EXPECT_TRUE(leap.start());
  }
  std::vector<std::string> takeEvents() {
    std::vector<std::string> names;
    core::Event e;
    while (events.read(e) == core::FlowStatus::NewData) names.push_back(e.name.str());
    return names;
  }
  template <class T>
  T read(core::InputPort<T>& port) {
    T f;
    EXPECT_NE(port.read(f), core::FlowStatus::NoData);
    return f;
  }
};

TEST(LeapMotionDriver, PublishesTwoHundredFramesPerSecondInsideTheBox) {
  Bench b;
  const KDL::Frame hand(KDL::Rotation::RPY(0.1, 0.2, 0.3), KDL::Vector(0.02, -0.01, 0.2));
  b.right.write(hand);
  b.clock.advance(1000ms);
  int frames = 0;
  KDL::Frame f;
  while (b.right_frames.read(f) == core::FlowStatus::NewData) ++frames;
  // The tracker took 200 frames in the second; the driver has those of the steps before the last.
  EXPECT_EQ(frames, 199);
  EXPECT_TRUE(KDL::Equal(b.read(b.right_pose), hand, 1e-12));  // inside the box, no noise: unchanged
  EXPECT_EQ(b.takeEvents(), (std::vector<std::string>{"e_right_hand_found"}));
  EXPECT_EQ(b.left_pose.read(f), core::FlowStatus::NoData);  // no left hand yet
}

TEST(LeapMotionDriver, ClampsToTheBoxThenScalesThenOffsets) {
  const KDL::Frame offset(KDL::Rotation::RotZ(M_PI / 2), KDL::Vector(0.5, 0.0, -0.1));
  Bench b(2.0, offset);
  // Outside the box in x and z (but inside the field of view): clamped to x = 0.1, z = 0.3.
  const KDL::Frame hand(KDL::Rotation::RotX(0.4), KDL::Vector(0.15, 0.02, 0.35));
  b.left.write(hand);
  b.clock.advance(10ms);
  const KDL::Frame expected = offset * KDL::Frame(hand.M, KDL::Vector(0.1, 0.02, 0.3) * 2.0);
  const KDL::Frame got = b.read(b.left_pose);
  EXPECT_TRUE(KDL::Equal(got, expected, 1e-12)) << got.p.x() << " " << got.p.y() << " " << got.p.z();
  EXPECT_NEAR(got.p.x(), 0.5 - 0.04, 1e-12);  // y 0.02·2 rotated by 90° about z, plus the offset
  EXPECT_NEAR(got.p.y(), 0.2, 1e-12);
  EXPECT_NEAR(got.p.z(), 0.5, 1e-12);
}

TEST(LeapMotionDriver, LostHandsKeepTheLastValidPoseAndRaiseEvents) {
  Bench b;
  const KDL::Frame seen(KDL::Vector(0.0, 0.0, 0.2));
  b.right.write(seen);
  b.left.write(seen);
  b.clock.advance(10ms);
  EXPECT_EQ(b.takeEvents(), (std::vector<std::string>{"e_right_hand_found", "e_left_hand_found"}));
  b.right.write(KDL::Frame(KDL::Vector(0.0, 0.0, 0.8)));  // above the field of view
  b.clock.advance(10ms);
  EXPECT_EQ(b.takeEvents(), (std::vector<std::string>{"e_right_hand_lost"}));
  EXPECT_TRUE(KDL::Equal(b.read(b.right_pose), seen, 1e-12));
  b.clock.advance(50ms);
  EXPECT_TRUE(b.takeEvents().empty());
  b.right.write(KDL::Frame(KDL::Vector(0.01, 0.0, 0.25)));
  b.clock.advance(10ms);
  EXPECT_EQ(b.takeEvents(), (std::vector<std::string>{"e_right_hand_found"}));
  EXPECT_NEAR(b.read(b.right_pose).p.z(), 0.25, 1e-12);
  EXPECT_EQ(cobra::test_support::allocationsDuring([&] {
              for (int i = 0; i < 100; ++i) {
                b.right.write(KDL::Frame(KDL::Vector(0.0005 * i, 0.0, 0.2)));
                b.clock.advance(1ms);
              }
            }),
            0);
}

// The hand moves at 0.1 m/s along x and 0.1 m/s down while it turns at 0.5 rad/s about z, for
// 0.4 s (8 filter time constants): the twist is the hand's, in the published frame.
TEST(LeapMotionDriver, TheTwistIsTheHandsVelocityInThePublishedFrame) {
  const KDL::Frame offset(KDL::Rotation::RotX(M_PI / 2), KDL::Vector(0.3, 0.0, 0.0));
  Bench b(2.0, offset);
  KDL::Twist t;
  bool first_seen = false;
  for (int i = 0; i <= 400; ++i) {
    const double s = 0.001 * i;
    b.right.write(KDL::Frame(KDL::Rotation::RotZ(0.5 * s), KDL::Vector(-0.02 + 0.1 * s, 0.0, 0.25 - 0.1 * s)));
    b.clock.advance(1ms);
    if (!first_seen && b.right_twist.read(t) == core::FlowStatus::NewData) {
      first_seen = true;
      EXPECT_TRUE(KDL::Equal(t, KDL::Twist::Zero(), 1e-12));  // its first frame: no previous pose
    }
  }
  EXPECT_TRUE(first_seen);
  t = b.read(b.right_twist);
  // In the published frame: scaled by 2, then turned by the offset's 90 degrees about x (device
  // z -> published -y, device y -> published z).
  const KDL::Twist expected = offset.M * KDL::Twist(KDL::Vector(0.2, 0.0, -0.2), KDL::Vector(0.0, 0.0, 0.5));
  EXPECT_TRUE(KDL::Equal(t, expected, 1e-3)) << t.vel.x() << " " << t.vel.y() << " " << t.vel.z() << " / " << t.rot.x()
                                             << " " << t.rot.y() << " " << t.rot.z();
  // Lost (out of the field of view): zero at once, the last pose kept.
  b.right.write(KDL::Frame(KDL::Vector(0.0, 0.0, 0.8)));
  b.clock.advance(10ms);
  EXPECT_TRUE(KDL::Equal(b.read(b.right_twist), KDL::Twist::Zero(), 1e-12));
  EXPECT_EQ(b.left_twist.read(t), core::FlowStatus::NoData);  // no left hand
}

/// The root mean square (m/s) of a still right hand's linear twist over 2 s, sampled every 5 ms.
double stillHandTwistRms(double filter_time) {
  Bench b(1.0, KDL::Frame::Identity(), 5e-4, filter_time);
  b.right.write(KDL::Frame(KDL::Vector(0.0, 0.0, 0.2)));
  b.clock.advance(500ms);
  double sum = 0.0;
  int n = 0;
  for (int i = 0; i < 400; ++i) {
    b.clock.advance(5ms);
    const KDL::Twist t = b.read(b.right_twist);
    sum += KDL::dot(t.vel, t.vel);
    ++n;
  }
  return std::sqrt(sum / n);
}

// The tracker's 0.5 mm noise per axis differenced over its 5 ms frames is over 0.1 m/s; the
// default filter (0.05 s) leaves less than a tenth of it.
TEST(LeapMotionDriver, TheTwistFilterTamesTheTrackersNoise) {
  const double raw = stillHandTwistRms(0.0), filtered = stillHandTwistRms(0.05);
  EXPECT_GT(raw, 0.1);
  EXPECT_LT(filtered, raw / 10.0);
  std::printf("still hand's twist rms: %.3f m/s unfiltered, %.3f m/s filtered (0.05 s)\n", raw, filtered);
}

TEST(LeapMotionDriver, BadPropertiesAreRefusedWithTheirName) {
  SimulatedLeapMotion tracker("LeapSim");
  LeapMotionDriver l("Leap");
  core::LockstepClock clock;
  clock.add(tracker, 1ms);
  clock.add(l, 1ms);
  tracker.setProperty("noise", -1.0);
  EXPECT_CONTAINS(tracker.configure().message, "component 'LeapSim': hand tracker: position_noise = -1.000000, expected >= 0 m");
  tracker.setProperty("noise", 0.0);
  ASSERT_TRUE(tracker.configure());
  l.setProperty("interaction_box", std::vector<double>{0, 0, 0, 1, 1});
  EXPECT_CONTAINS(l.configure().message,
                  "component 'Leap': property interaction_box has 5 numbers; give 6: x_min, y_min, z_min, x_max, "
                  "y_max, z_max in m");
  l.setProperty("interaction_box", std::vector<double>{0, 0.2, 0, 1, 0.1, 1});
  EXPECT_CONTAINS(l.configure().message,
                  "property interaction_box: y_min = 0.200000 m must be below y_max = 0.100000 m");
  l.setProperty("interaction_box", std::vector<double>{0, 0, 0, 1, 1, 1});
  l.setProperty("workspace_scale", 0.0);
  EXPECT_CONTAINS(l.configure().message, "property workspace_scale = 0.000000; expected > 0");
  l.setProperty("workspace_scale", 1.0);
  l.setProperty("device", "sim:Leap");
  EXPECT_CONTAINS(l.configure().message,
                  "component 'Leap': property device = 'sim:Leap': no hand tracker backend 'sim:Leap'; backends that "
                  "exist: 'sim:LeapSim' (simulated Leap Motion of component 'LeapSim')");
  l.setProperty("device", "sim:LeapSim");
  l.setProperty("twist_filter_time", -0.01);
  EXPECT_CONTAINS(l.configure().message, "component 'Leap': property twist_filter_time = -0.010000 s; expected >= 0");
  l.setProperty("twist_filter_time", 0.05);
  EXPECT_TRUE(l.configure());
}

}  // namespace
}  // namespace cobra::components
