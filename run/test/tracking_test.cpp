// TrackingMonitor (run/tracking.hpp) on made-up samples: tracking error over the samples that
// count, time above 5 mm, the joint-jump episodes, the largest command step.

#include "cobra/run/tracking.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "cobra/test_support/test_support.hpp"

namespace cobra::run {
namespace {

constexpr double kPi = 3.14159265358979323846;

KDL::JntArray joints(std::initializer_list<double> values) {
  KDL::JntArray q(static_cast<unsigned>(values.size()));
  unsigned i = 0;
  for (double v : values) q(i++) = v;
  return q;
}

TEST(TrackingMonitor, MeasuresPositionInMillimetresAndOrientationInDegreesOverTheSamplesThatCount) {
  TrackingMonitor m("I-SUR needle", {}, 0.001);
  const KDL::Frame commanded(KDL::Rotation::RotX(0.3), KDL::Vector(0.1, 0.2, 0.3));
  // 3 mm and 2 deg off while counting, then 50 mm and 10 deg off while not (teleoperation).
  for (int i = 0; i < 100; ++i)
    m.step(0.001 * i, true, "root.Moving", commanded,
           KDL::Frame(commanded.M * KDL::Rotation::RotY(2.0 * kPi / 180.0), commanded.p + KDL::Vector(0, 0.003, 0)),
           nullptr);
  for (int i = 100; i < 200; ++i)
    m.step(0.001 * i, false, "root.Teleoperation", commanded,
           KDL::Frame(commanded.M * KDL::Rotation::RotZ(10.0 * kPi / 180.0), commanded.p + KDL::Vector(0.05, 0, 0)),
           nullptr);
  const TrackingFigures& f = m.figures();
  EXPECT_NEAR(f.position_mm.value, 3.0, 1e-9);
  EXPECT_NEAR(f.orientation_deg.value, 2.0, 1e-9);
  EXPECT_EQ(f.position_mm.state, "root.Moving");
  EXPECT_NEAR(f.seconds_sampled, 0.1, 1e-9);
  EXPECT_EQ(f.seconds_above_5mm, 0.0);
  // The plots' window sees every sample, counted or not.
  const auto [mm, deg] = m.takeWindowMaximum();
  EXPECT_NEAR(mm, 50.0, 1e-9);
  EXPECT_NEAR(deg, 10.0, 1e-9);
  EXPECT_TRUE(std::isnan(m.takeWindowMaximum().first));
}

TEST(TrackingMonitor, CountsTheTimeAboveFiveMillimetresAndKeepsWhenTheWorstHappened) {
  TrackingMonitor m("UR5 probe", {}, 0.001);
  const KDL::Frame commanded;
  for (int i = 0; i < 1000; ++i) {
    const double off = i >= 400 && i < 650 ? 0.006 + 1e-5 * (i == 500) : 0.001;
    m.step(0.001 * i, true, i == 500 ? "root.MoveToSkin.Approach.Moving" : "root.Idle", commanded,
           KDL::Frame(KDL::Vector(off, 0, 0)), nullptr);
  }
  EXPECT_NEAR(m.figures().seconds_above_5mm, 0.25, 1e-9);
  EXPECT_NEAR(m.figures().position_mm.value, 6.01, 1e-9);
  EXPECT_NEAR(m.figures().position_mm.at, 0.5, 1e-12);
  EXPECT_EQ(m.figures().position_mm.state, "root.MoveToSkin.Approach.Moving");
}

TEST(TrackingMonitor, AJointAtItsVelocityLimitIsAJumpEpisodeUntilItCalmsDown) {
  // Two joints, 1 rad/s and 0.1 m/s: 1 mrad and 0.1 mm per 1 ms step at the limit.
  TrackingMonitor m("robot", {1.0, 0.1}, 0.001);
  const KDL::Frame pose;
  double q0 = 0.0, q1 = 0.0;
  auto move = [&](int steps, double speed0, double speed1, bool counts = true) {
    for (int i = 0; i < steps; ++i) {
      q0 += speed0 * 0.001;
      q1 += speed1 * 0.001;
      const KDL::JntArray q = joints({q0, q1});
      m.step(0.0, counts, "root.Moving", pose, pose, &q);
    }
  };
  move(100, 0.9, 0.09);  // 90 % of the limits: a fast but followed motion
  EXPECT_EQ(m.figures().joint_jumps, 0);
  EXPECT_NEAR(m.figures().joint_speed.value, 0.9, 1e-6);
  move(50, 0.2, 0.1);   // joint 2 at its limit: one episode however long
  move(50, 0.2, 0.02);  // calm
  move(1, 5.0, 0.0);    // a jump beyond the limit: a second one
  move(20, 0.0, 0.0);
  move(30, 1.0, 0.0, false);  // not counted (teleoperation)
  EXPECT_EQ(m.figures().joint_jumps, 2);
  EXPECT_NEAR(m.figures().joint_speed.value, 5.0, 1e-6);
  EXPECT_CONTAINS(m.figures().joint_jump_log, "joint 2 at 100 % of its velocity limit (root.Moving)");
  EXPECT_CONTAINS(m.figures().joint_jump_log, "joint 1 at 500 %");
}

// On the wall clock the runner's samples may come several periods apart (its thread starved):
// a joint at 90 % of its limit is not a jump for having moved three periods' worth in one sample.
TEST(TrackingMonitor, AJointSpeedIsTakenOverTheTimeBetweenLateSamples) {
  TrackingMonitor m("robot", {1.0}, 0.001);
  const KDL::Frame pose;
  double q = 0.0, t = 0.0;
  for (int i = 0; i < 100; ++i) {
    const double interval = i % 2 == 0 ? 0.001 : 0.003;  // s: on time, then late
    t += interval;
    q += 0.9 * interval;
    const KDL::JntArray joints_now = joints({q});
    m.step(t, true, "root.Moving", pose, pose, &joints_now);
  }
  EXPECT_EQ(m.figures().joint_jumps, 0) << m.figures().joint_jump_log;
  EXPECT_NEAR(m.figures().joint_speed.value, 0.9, 1e-6);
  t += 0.003;
  q += 3 * 0.003;  // 3 rad/s over a late sample: a jump all the same
  const KDL::JntArray jumped = joints({q});
  m.step(t, true, "root.Moving", pose, pose, &jumped);
  EXPECT_EQ(m.figures().joint_jumps, 1);
}

// On the wall clock a sample's joints may be a robot period old: a stale sample then a fresh one
// show two periods of motion in one. With that skew declared, a joint at 90 % of its limit is no
// jump; a jump five times beyond the limit still is.
TEST(TrackingMonitor, AStaleSampleOnTheWallClockIsNoJump) {
  TrackingMonitor m("robot", {1.0}, 0.001);
  m.setSampleSkew(0.001);
  const KDL::Frame pose;
  double q = 0.0, t = 0.0;
  for (int i = 1; i <= 100; ++i) {
    t += 0.001;
    q += 0.9 * (i % 2 == 0 ? 0.002 : 0.0);  // every other sample stale: the motion shows in the next
    const KDL::JntArray joints_now = joints({q});
    m.step(t, true, "root.Moving", pose, pose, &joints_now);
  }
  EXPECT_EQ(m.figures().joint_jumps, 0) << m.figures().joint_jump_log;
  t += 0.001;
  q += 5.0 * 0.002;
  const KDL::JntArray jumped = joints({q});
  m.step(t, true, "root.Moving", pose, pose, &jumped);
  EXPECT_EQ(m.figures().joint_jumps, 1);
}

TEST(TrackingMonitor, KeepsTheLargestJumpOfTheCommandBetweenTwoSamplesCountedOrNot) {
  TrackingMonitor m("tool", {}, 0.001);
  for (int i = 0; i < 10; ++i)
    m.step(0.001 * i, i < 5, "root.Moving", KDL::Frame(KDL::Vector(0.0001 * i + (i >= 7 ? 0.002 : 0.0), 0, 0)),
           KDL::Frame(), nullptr);
  EXPECT_NEAR(m.figures().max_command_step, 0.0021, 1e-12);  // the step into sample 7, not counted
  EXPECT_NEAR(m.figures().max_command_step_at, 0.007, 1e-12);
}

// The orientation error is the angle of commanded⁻¹·measured: against KDL's GetRotAngle on 2,000
// seeded random rotation pairs (seed 15), a third of them 1e-5..1e-3 rad apart and a third
// 1e-5..1e-3 rad short of a half turn (KDL rounds angles within ~1e-6 rad of 0 or π to them).
TEST(TrackingMonitor, OrientationErrorIsTheAngleOfTheRelativeRotation) {
  std::mt19937_64 rng(15);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  auto randomAxis = [&] {
    KDL::Vector v(unit(rng), unit(rng), unit(rng));
    while (v.Norm() < 0.1) v = KDL::Vector(unit(rng), unit(rng), unit(rng));
    v.Normalize();
    return v;
  };
  for (int i = 0; i < 2000; ++i) {
    const KDL::Rotation a = KDL::Rotation::Rot(randomAxis(), kPi * unit(rng));
    const double small = 1e-5 + 0.99e-3 * std::abs(unit(rng));
    const double angle = i % 3 == 0 ? small : i % 3 == 1 ? kPi - small : kPi * std::abs(unit(rng));
    const KDL::Rotation b = a * KDL::Rotation::Rot(randomAxis(), angle);
    KDL::Vector axis;
    const double expected_deg = 180.0 / kPi * (a.Inverse() * b).GetRotAngle(axis);
    TrackingMonitor m("arm", {}, 0.001);
    m.step(0.0, true, "root.Moving", KDL::Frame(a), KDL::Frame(b), nullptr);
    EXPECT_NEAR(m.figures().orientation_deg.value, expected_deg, 1e-6) << "pair " << i;
  }
}

}  // namespace
}  // namespace cobra::run
