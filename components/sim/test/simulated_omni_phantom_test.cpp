// The simulated Phantom Omni: the scripted hand moves the stylus, the commanded force is rendered
// (saturated at 3.3 N), buttons and the origin offset reach the outputs.
#include "cobra/components/sim/simulated_omni_phantom.hpp"

#include <gtest/gtest.h>

#include <algorithm>

#include "cobra/core/core.hpp"
#include "cobra/test_support/counting_new.hpp"
#include "cobra/test_support/test_support.hpp"

namespace cobra::components {
namespace {

using namespace std::chrono_literals;

struct Rig {
  SimulatedOmniPhantom omni{"omni"};
  core::LockstepClock clock;
  core::OutputPort<KDL::Frame> hand{"hand", "", "m"};
  core::OutputPort<KDL::Wrench> force{"force", "", "N"};
  core::OutputPort<int> held{"held", "", "1"};
  core::InputPort<KDL::Frame> pose{"pose", "", "m"};
  core::InputPort<KDL::Twist> twist{"twist", "", "m/s"};
  core::InputPort<int> buttons{"buttons", "", "1"};
  core::InputPort<double> dissipated{"dissipated", "", "W"};

  explicit Rig(const KDL::Frame& offset) {
    omni.setProperty("origin_pose_offset", offset);
    clock.add(omni, 1ms);
    core::connectPorts(hand, omni.port("handTarget"));
    core::connectPorts(force, omni.port("desWrench"));
    core::connectPorts(held, omni.port("handButtons"));
    core::connectPorts(omni.port("measCartPose"), pose);
    core::connectPorts(omni.port("measTwist"), twist);
    core::connectPorts(omni.port("statusButtons"), buttons);
    core::connectPorts(omni.port("dissipatedPower"), dissipated);
    EXPECT_TRUE(omni.configure()) << omni.lastError();
    EXPECT_TRUE(omni.start());
  }
  KDL::Frame measured() {
    KDL::Frame f;
    EXPECT_NE(pose.read(f), core::FlowStatus::NoData);
    return f;
  }
};

TEST(SimulatedOmniPhantom, TheHandMovesTheStylusInTheOffsetFrame) {
  const KDL::Frame offset(KDL::Rotation::RotZ(1.5707963267948966), KDL::Vector(1.0, 2.0, 0.5));
  Rig rig(offset);
  rig.clock.advance(1ms);
  EXPECT_TRUE(KDL::Equal(rig.measured(), offset, 1e-9));  // the stylus starts at the device origin
  const KDL::Frame target = offset * KDL::Frame(KDL::Vector(0.03, -0.02, 0.01));
  rig.hand.write(target);
  rig.held.write(0b01);
  double largest_power = 0.0;  // W
  for (int ms = 0; ms < 2000; ++ms) {
    rig.clock.advance(1ms);
    double p = 0.0;
    ASSERT_NE(rig.dissipated.read(p), core::FlowStatus::NoData);
    largest_power = std::max(largest_power, p);
  }
  // The stylus travels 3.7 cm in a fraction of a second against 0.26 N of backdrive friction.
  EXPECT_GT(largest_power, 0.26 * 0.02);
  const KDL::Frame at = rig.measured();
  EXPECT_LT((at.p - target.p).Norm(), 0.001);
  EXPECT_TRUE(KDL::Equal(at.M, offset.M, 1e-12));
  KDL::Twist v;
  ASSERT_NE(rig.twist.read(v), core::FlowStatus::NoData);
  EXPECT_LT(v.vel.Norm(), 0.01);
  double power = -1.0;
  ASSERT_NE(rig.dissipated.read(power), core::FlowStatus::NoData);
  EXPECT_LE(power, 0.26 * 0.01);  // at rest: friction (0.26 N) times a speed below 1 cm/s
  int b = -1;
  ASSERT_NE(rig.buttons.read(b), core::FlowStatus::NoData);
  EXPECT_EQ(b, 1);
}

// Six DoF: the passive gimbal measures how the hand turns the stylus; the turn is a motion (the
// wrist's 0.05 s time constant), reported in the twist's angular part, frame O axes.
TEST(SimulatedOmniPhantom, TheHandTurnsTheStylusAndTheTwistCarriesTheTurn) {
  const KDL::Frame offset(KDL::Rotation::RotZ(1.5707963267948966), KDL::Vector(1.0, 2.0, 0.5));
  Rig rig(offset);
  rig.clock.advance(1ms);
  const KDL::Rotation turned = KDL::Rotation::RotX(0.3) * KDL::Rotation::RotY(-0.2);  // frame D
  rig.hand.write(offset * KDL::Frame(turned, KDL::Vector(0.01, 0, 0)));
  rig.clock.advance(1ms);
  KDL::Twist v;
  ASSERT_NE(rig.twist.read(v), core::FlowStatus::NoData);
  // The first step turns by 1/50 of the way (1 ms / 0.05 s) about the turn's axis, in O's axes.
  const KDL::Vector axis = offset.M * turned.GetRot();
  EXPECT_NEAR(KDL::dot(v.rot, axis) / axis.Norm(), axis.Norm() / 50.0 / 0.001, 0.05 * axis.Norm() / 0.05);
  EXPECT_GT(KDL::dot(v.rot, axis), 0.0);
  const KDL::Rotation early = rig.measured().M;
  EXPECT_GT((offset.M * turned * early.Inverse()).GetRot().Norm(), 0.3);  // not there at once
  for (int ms = 0; ms < 1000; ++ms) rig.clock.advance(1ms);
  EXPECT_TRUE(KDL::Equal(rig.measured().M, offset.M * turned, 1e-6));
  ASSERT_NE(rig.twist.read(v), core::FlowStatus::NoData);
  EXPECT_LT(v.rot.Norm(), 1e-6);
}

// A fault script moves and turns the hand through the hand_motion property (frame D, from the
// initial position) while nothing is connected to handTarget.
TEST(SimulatedOmniPhantom, TheHandMotionPropertyMovesAndTurnsTheStylus) {
  const KDL::Frame offset(KDL::Vector(0.1, 0, 0.2));
  SimulatedOmniPhantom omni("omni");
  core::LockstepClock clock;
  core::InputPort<KDL::Frame> pose{"pose", "", "m"};
  omni.setProperty("origin_pose_offset", offset);
  omni.setProperty("initial_position", KDL::Vector(0, 0.01, 0));
  clock.add(omni, 1ms);
  core::connectPorts(omni.port("measCartPose"), pose);
  ASSERT_TRUE(omni.configure()) << omni.lastError();
  ASSERT_TRUE(omni.start());
  const KDL::Frame motion(KDL::Rotation::RotZ(0.4), KDL::Vector(0.02, 0, -0.01));
  omni.setProperty("hand_motion", motion);
  for (int ms = 0; ms < 3000; ++ms) clock.advance(1ms);
  KDL::Frame at;
  ASSERT_NE(pose.read(at), core::FlowStatus::NoData);
  EXPECT_LT((at.p - offset * KDL::Vector(0.02, 0.01, -0.01)).Norm(), 0.001);
  EXPECT_TRUE(KDL::Equal(at.M, KDL::Rotation::RotZ(0.4), 1e-6));
}

TEST(SimulatedOmniPhantom, ACommandedForcePushesTheHandBackUpToTheDeviceMaximum) {
  Rig rig(KDL::Frame::Identity());
  // The hand holds the origin (400 N/m); 2 N along x moves it by about 2 / 400 m.
  rig.force.write(KDL::Wrench(KDL::Vector(2.0, 0, 0), KDL::Vector(0, 0, 1.0)));
  for (int ms = 0; ms < 3000; ++ms) rig.clock.advance(1ms);
  const double x2 = rig.measured().p.x();
  EXPECT_NEAR(x2, 2.0 / 400.0, 0.001);
  // 10 N asked: the device renders its 3.3 N maximum.
  rig.force.write(KDL::Wrench(KDL::Vector(10.0, 0, 0), KDL::Vector::Zero()));
  for (int ms = 0; ms < 3000; ++ms) rig.clock.advance(1ms);
  EXPECT_NEAR(rig.measured().p.x(), 3.3 / 400.0, 0.001);
}

TEST(SimulatedOmniPhantom, TheUpdateHookAllocatesNothing) {
  Rig rig(KDL::Frame(KDL::Vector(0.1, 0, 0)));
  rig.hand.write(KDL::Frame(KDL::Vector(0.12, 0.01, 0)));
  rig.force.write(KDL::Wrench(KDL::Vector(1.0, 0, 0), KDL::Vector::Zero()));
  rig.held.write(2);
  rig.clock.advance(1ms);
  EXPECT_EQ(cobra::test_support::allocationsDuring([&] {
              for (int ms = 0; ms < 500; ++ms) {
                rig.hand.write(KDL::Frame(KDL::Rotation::RotX(1e-3 * ms), KDL::Vector(0.12, 0.01 - 1e-5 * ms, 0)));
                rig.force.write(KDL::Wrench(KDL::Vector(1.0, 0, 0), KDL::Vector::Zero()));
                rig.held.write(ms % 4);
                rig.clock.advance(1ms);
              }
            }),
            0);
  EXPECT_EQ(rig.omni.state(), core::State::Running);
}

TEST(SimulatedOmniPhantom, AnInitialPositionOutsideTheWorkspaceIsRefused) {
  SimulatedOmniPhantom omni("omni");
  omni.setProperty("initial_position", KDL::Vector(0.5, 0, 0));
  const core::Result r = omni.configure();
  EXPECT_FALSE(r);
  EXPECT_CONTAINS(r.message, "component 'omni': property initial_position: ");
}

}  // namespace
}  // namespace cobra::components
