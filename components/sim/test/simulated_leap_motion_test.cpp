// The simulated Leap Motion's scripted hands (six DoF: position and orientation) read through
// LeapMotionDriver: the hands appear only when scripted_hands is set, move to a new scripted pose
// as a hand moves (not in one step), a hand's port wins over its script, and the update allocates
// nothing.
#include "cobra/components/sim/simulated_leap_motion.hpp"

#include <gtest/gtest.h>

#include "cobra/components/drivers/leap_motion_driver.hpp"
#include "cobra/core/lockstep_clock.hpp"
#include "cobra/test_support/counting_new.hpp"
#include "cobra/test_support/test_support.hpp"

namespace cobra::components {
namespace {

using namespace std::chrono_literals;

struct Rig {
  SimulatedLeapMotion tracker{"LeapSim"};
  LeapMotionDriver leap{"Leap"};
  core::LockstepClock clock;
  core::OutputPort<KDL::Frame> left{"left", "", "m"};
  core::InputPort<KDL::Frame> right_pose{"rp", "", "m"}, left_pose{"lp", "", "m"};

  explicit Rig(bool scripted) {
    tracker.setProperty("noise", 0.0);
    tracker.setProperty("scripted_hands", scripted);
    leap.setProperty("device", "sim:LeapSim");
    clock.add(tracker, 1ms);
    clock.add(leap, 1ms);
    core::connectPorts(left, tracker.port("leftHand"));
    core::connectPorts(leap.port("measRightPose"), right_pose);
    core::connectPorts(leap.port("measLeftPose"), left_pose);
    EXPECT_TRUE(tracker.configure()) << tracker.lastError();
    EXPECT_TRUE(leap.configure()) << leap.lastError();
    EXPECT_TRUE(tracker.start());
    EXPECT_TRUE(leap.start());
  }
};

TEST(SimulatedLeapMotion, WithoutScriptedHandsNoHandIsAboveTheDevice) {
  Rig rig(false);
  rig.clock.advance(500ms);
  KDL::Frame f;
  EXPECT_EQ(rig.right_pose.read(f), core::FlowStatus::NoData);
  EXPECT_EQ(rig.left_pose.read(f), core::FlowStatus::NoData);
}

TEST(SimulatedLeapMotion, AScriptedHandAppearsThenMovesAndTurnsToItsNewPoseAsAHandDoes) {
  Rig rig(true);
  rig.clock.advance(200ms);
  KDL::Frame f;
  ASSERT_NE(rig.right_pose.read(f), core::FlowStatus::NoData);
  EXPECT_TRUE(KDL::Equal(f, KDL::Frame(KDL::Vector(0.05, 0, 0.2)), 1e-9));  // the default scripted pose
  const KDL::Frame turned(KDL::Rotation::RPY(0.2, -0.1, 0.35), KDL::Vector(0.03, 0.01, 0.22));
  rig.tracker.setProperty("right_hand", turned);
  rig.clock.advance(20ms);
  ASSERT_NE(rig.right_pose.read(f), core::FlowStatus::NoData);
  // 20 ms into a 0.1 s first-order motion: between a tenth and a half of the way, in both parts.
  const double moved = (f.p - KDL::Vector(0.05, 0, 0.2)).Norm() / (turned.p - KDL::Vector(0.05, 0, 0.2)).Norm();
  const double turned_share = f.M.GetRot().Norm() / turned.M.GetRot().Norm();
  EXPECT_GT(moved, 0.1);
  EXPECT_LT(moved, 0.5);
  EXPECT_GT(turned_share, 0.1);
  EXPECT_LT(turned_share, 0.5);
  rig.clock.advance(2000ms);
  ASSERT_NE(rig.right_pose.read(f), core::FlowStatus::NoData);
  EXPECT_TRUE(KDL::Equal(f, turned, 1e-6));
}

TEST(SimulatedLeapMotion, AHandsPortWinsOverItsScript) {
  Rig rig(true);
  const KDL::Frame hand(KDL::Rotation::RotZ(0.5), KDL::Vector(-0.02, 0.02, 0.15));
  rig.left.write(hand);
  rig.clock.advance(200ms);
  KDL::Frame f;
  ASSERT_NE(rig.left_pose.read(f), core::FlowStatus::NoData);
  EXPECT_TRUE(KDL::Equal(f, hand, 1e-9));
}

TEST(SimulatedLeapMotion, TheUpdateHookAllocatesNothing) {
  Rig rig(true);
  rig.clock.advance(10ms);
  rig.tracker.setProperty("right_hand", KDL::Frame(KDL::Rotation::RotX(0.3), KDL::Vector(0, 0, 0.2)));
  EXPECT_EQ(cobra::test_support::allocationsDuring([&] {
              for (int ms = 0; ms < 300; ++ms) rig.clock.advance(1ms);  // the hand moving and turning
            }),
            0);
}

}  // namespace
}  // namespace cobra::components
