// CartesianTrajectory: orientation stays a rotation, follows each geodesic with the angle of the
// timing law (cross-checked with KDL's RotationalInterpolation_SingleAxis), rounds inner corners
// continuously, twists are the derivatives of the poses, arms are synchronised, and invalid input
// is refused with a message naming it.

#include "cobra/trajectory/cartesian.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include <kdl/rotational_interpolation_sa.hpp>

#include "cobra/test_support/test_support.hpp"
#include "rotation_checks.hpp"

namespace {

using cobra::test_support::messageOf;
using cobra::trajectory::CartesianLimits;
using cobra::trajectory::CartesianTrajectory;
using cobra::trajectory::State;
using cobra::trajectory::test::angleBetween;
using cobra::trajectory::test::rotationError;
using cobra::trajectory::test::smallRotationVector;

constexpr int kRandomPaths = 60;   // random Cartesian paths per property test
constexpr int kSamples = 1500;     // evaluation times per path

const CartesianLimits kLimits{0.2, 0.8, 0.3, 0.4};

KDL::Frame randomFrame(std::mt19937& rng) {
  std::uniform_real_distribution<double> angle(-M_PI, M_PI), position(-0.5, 0.5);
  return KDL::Frame(KDL::Rotation::RPY(angle(rng), angle(rng) / 2, angle(rng)),
                    KDL::Vector(position(rng), position(rng), position(rng)));
}

std::vector<KDL::Frame> randomPath(std::mt19937& rng) {
  std::uniform_int_distribution<int> count(2, 7);
  std::vector<KDL::Frame> path;
  const int n = count(rng);
  for (int k = 0; k < n; ++k) path.push_back(randomFrame(rng));
  return path;
}

TEST(CartesianTrajectory, OneSegmentIsKdlsSingleAxisInterpolationDrivenByTheTimingLaw) {
  const KDL::Frame start(KDL::Rotation::RPY(0.1, -0.4, 0.3), KDL::Vector(0.1, 0.2, 0.3));
  const KDL::Frame end(KDL::Rotation::RPY(1.2, 0.5, -2.0), KDL::Vector(0.4, -0.1, 0.35));
  const CartesianTrajectory traj({start, end}, kLimits, 5);
  KDL::RotationalInterpolation_SingleAxis kdl;
  kdl.SetStartEnd(start.M, end.M);
  for (int j = 0; j <= 400; ++j) {
    const double t = traj.duration() * j / 400.0;
    KDL::Frame pose;
    KDL::Twist twist;
    traj.evaluate(t, 0, pose, twist);
    const State s = traj.axes().axis(3).at(t);
    ASSERT_LT(angleBetween(pose.M, kdl.Pos(s.position)), 1e-12) << "t = " << t;
    ASSERT_LT((twist.rot - kdl.Vel(s.position, s.velocity)).Norm(), 1e-12) << "t = " << t;
    // The angle from the start is the timing law's s(t): proportional, on the geodesic.
    ASSERT_NEAR(angleBetween(start.M, pose.M), s.position, 1e-9);
  }
  KDL::Frame pose;
  KDL::Twist twist;
  traj.evaluate(traj.duration(), 0, pose, twist);
  EXPECT_TRUE(KDL::Equal(pose, end, 1e-12));
  EXPECT_NEAR(traj.axes().axis(3).at(traj.duration()).position, kdl.Angle(), 1e-12);
}

TEST(CartesianTrajectory, StaysARotationAndFollowsEachGeodesicOutsideInnerBlends) {
  std::mt19937 rng(31);
  for (int n = 0; n < kRandomPaths; ++n) {
    const auto path = randomPath(rng);
    const CartesianTrajectory traj(path, kLimits, 2 + n % 4);
    const auto times = traj.waypointTimes();
    const double half = kLimits.angular_acceleration_time / 2;
    for (int j = 0; j <= kSamples; ++j) {
      const double t = traj.duration() * j / kSamples;
      KDL::Frame pose;
      KDL::Twist twist;
      traj.evaluate(t, 0, pose, twist);
      ASSERT_LT(rotationError(pose.M), 1e-12);
      std::size_t k = 0;
      while (k + 2 < times.size() && t >= times[k + 1]) ++k;
      const bool in_inner_blend = (k >= 1 && t - times[k] < half) || (k + 2 < times.size() && times[k + 1] - t < half);
      if (in_inner_blend) continue;
      // Geodesic k: R_k^-1 R(t) is a rotation about u_k by s(t) - s_k, s_k the sum of earlier angles.
      KDL::Vector axis;
      double s_k = 0.0;
      for (std::size_t i = 0; i < k; ++i) s_k += (path[i].M.Inverse() * path[i + 1].M).GetRotAngle(axis);
      const double s = traj.axes().axis(3).at(t).position - s_k;
      const double theta_k = (path[k].M.Inverse() * path[k + 1].M).GetRotAngle(axis);
      ASSERT_LT(angleBetween(path[k].M * KDL::Rotation::Rot2(axis, 0.0), pose.M * KDL::Rotation::Rot2(axis, -s)), 1e-9)
          << "segment " << k << " t " << t;
      ASSERT_GE(s, -1e-9);
      ASSERT_LE(s, theta_k + 1e-9);
    }
  }
}

TEST(CartesianTrajectory, TwistIsTheDerivativeOfThePoseAndBothAreContinuous) {
  std::mt19937 rng(32);
  constexpr double h = 1e-6;
  for (int n = 0; n < kRandomPaths; ++n) {
    const auto path = randomPath(rng);
    const CartesianTrajectory traj(path, kLimits, 2 + n % 4);
    KDL::Frame previous_pose = path.front();
    KDL::Twist previous_twist = KDL::Twist::Zero();
    const double dt = traj.duration() / kSamples;
    for (int j = 1; j < kSamples; ++j) {
      const double t = dt * j;
      KDL::Frame minus, plus, pose;
      KDL::Twist twist, unused;
      traj.evaluate(t - h, 0, minus, unused);
      traj.evaluate(t + h, 0, plus, unused);
      traj.evaluate(t, 0, pose, twist);
      const KDL::Vector omega = smallRotationVector(plus.M * minus.M.Inverse()) / (2 * h);
      const KDL::Vector velocity = (plus.p - minus.p) / (2 * h);
      ASSERT_LT((omega - twist.rot).Norm(), 1e-5) << "t " << t;
      ASSERT_LT((velocity - twist.vel).Norm(), 1e-5) << "t " << t;
      // Continuity between samples: bounded by the speed limits (no jumps at joints or blends).
      ASSERT_LE(angleBetween(previous_pose.M, pose.M), kLimits.max_angular_velocity * dt * 1.001 + 1e-12);
      ASSERT_LE((pose.p - previous_pose.p).Norm(), std::sqrt(3.0) * kLimits.max_linear_velocity * dt * 1.001 + 1e-12);
      ASSERT_LE((twist.rot - previous_twist.rot).Norm(), 20.0 * dt / kLimits.angular_acceleration_time) << "t " << t;
      previous_pose = pose;
      previous_twist = twist;
    }
  }
}

TEST(CartesianTrajectory, AccelerationIsTheDerivativeOfTheTwist) {
  // Orders 4 and 5 keep acceleration continuous; its derivative jumps where polynomial pieces
  // meet, so the central difference skips instants within 2 h of a piece boundary of any axis.
  std::mt19937 rng(35);
  constexpr double h = 1e-5;
  for (int n = 0; n < kRandomPaths; ++n) {
    const auto path = randomPath(rng);
    const CartesianTrajectory traj(path, kLimits, 4 + n % 2);
    std::vector<double> joints;
    for (std::size_t i = 0; i < traj.axes().axisCount(); ++i)
      for (const auto& piece : traj.axes().axis(i).segments()) joints.push_back(piece.start_time);
    for (int j = 1; j < kSamples; ++j) {
      const double t = traj.duration() * j / kSamples;
      if (std::any_of(joints.begin(), joints.end(), [&](double joint) { return std::abs(joint - t) < 2 * h; })) continue;
      KDL::Frame pose;
      KDL::Twist minus, plus, twist, acceleration, unused;
      traj.evaluate(t - h, 0, pose, minus, unused);
      traj.evaluate(t + h, 0, pose, plus, unused);
      traj.evaluate(t, 0, pose, twist, acceleration);
      ASSERT_LT(((plus.rot - minus.rot) / (2 * h) - acceleration.rot).Norm(), 1e-6) << "t " << t;
      ASSERT_LT(((plus.vel - minus.vel) / (2 * h) - acceleration.vel).Norm(), 1e-6) << "t " << t;
    }
  }
}

TEST(CartesianTrajectory, RespectsTheSpeedLimits) {
  std::mt19937 rng(33);
  for (int n = 0; n < kRandomPaths; ++n) {
    const CartesianTrajectory traj(randomPath(rng), kLimits, 5);
    for (int j = 0; j <= kSamples; ++j) {
      KDL::Frame pose;
      KDL::Twist twist;
      traj.evaluate(traj.duration() * j / kSamples, 0, pose, twist);
      ASSERT_LE(twist.rot.Norm(), kLimits.max_angular_velocity * (1 + 1e-9));
      for (int c = 0; c < 3; ++c) ASSERT_LE(std::abs(twist.vel(c)), kLimits.max_linear_velocity * (1 + 1e-9));
    }
  }
}

TEST(CartesianTrajectory, ArmsAreSynchronisedAndTheEndsAreHeldAtRest) {
  std::mt19937 rng(34);
  std::vector<std::vector<KDL::Frame>> waypoints;
  for (int k = 0; k < 4; ++k) waypoints.push_back({randomFrame(rng), randomFrame(rng)});
  waypoints[2][1] = waypoints[1][1];  // arm 1 pauses for a segment: it still waits for arm 0
  const CartesianTrajectory traj(waypoints, kLimits, 4);
  ASSERT_EQ(traj.armCount(), 2u);
  ASSERT_EQ(traj.waypointTimes().size(), 4u);
  std::vector<KDL::Frame> poses(2);
  std::vector<KDL::Twist> twists(2);
  for (double t : {-1.0, 0.0}) {
    traj.evaluate(t, poses, twists);
    for (std::size_t a = 0; a < 2; ++a) {
      EXPECT_TRUE(KDL::Equal(poses[a], waypoints[0][a], 1e-12)) << a;
      EXPECT_TRUE(KDL::Equal(twists[a], KDL::Twist::Zero(), 1e-12)) << a;
    }
  }
  for (double t : {traj.duration(), traj.duration() + 5.0}) {
    traj.evaluate(t, poses, twists);
    for (std::size_t a = 0; a < 2; ++a) {
      EXPECT_TRUE(KDL::Equal(poses[a], waypoints[3][a], 1e-9)) << a;
      EXPECT_TRUE(KDL::Equal(twists[a], KDL::Twist::Zero(), 1e-9)) << a;
    }
  }
  // Arm 1 is still between its waypoints 1 and 2 at the middle of segment 1, away from the blends.
  const double middle = (traj.waypointTimes()[1] + traj.waypointTimes()[2]) / 2;
  traj.evaluate(middle, poses, twists);
  EXPECT_TRUE(KDL::Equal(poses[1], waypoints[1][1], 1e-12));
}

TEST(CartesianTrajectory, DegenerateSegmentsStillInterpolate) {
  // A pause (same frame twice), a half turn (axis chosen by KDL) and a tiny rotation.
  const KDL::Frame a(KDL::Rotation::RPY(0.2, 0.1, 0.0), KDL::Vector(0.0, 0.0, 0.2));
  const KDL::Frame half_turn(a.M * KDL::Rotation::RotZ(M_PI), KDL::Vector(0.1, 0.0, 0.2));
  const KDL::Frame tiny(half_turn.M * KDL::Rotation::RotX(1e-7), KDL::Vector(0.1, 0.05, 0.2));
  const std::vector<KDL::Frame> path{a, a, half_turn, tiny, tiny};
  const CartesianTrajectory traj(path, kLimits, 5);
  for (int j = 0; j <= kSamples; ++j) {
    KDL::Frame pose;
    KDL::Twist twist;
    traj.evaluate(traj.duration() * j / kSamples, 0, pose, twist);
    ASSERT_LT(rotationError(pose.M), 1e-12);
    ASSERT_TRUE(std::isfinite(twist.rot.Norm()));
    ASSERT_LE(twist.rot.Norm(), kLimits.max_angular_velocity * (1 + 1e-9));
  }
  KDL::Frame pose;
  KDL::Twist twist;
  // The pause: nothing turns until the blend into the half turn starts, T_a / 2 before t_1.
  traj.evaluate(traj.waypointTimes()[1] - kLimits.angular_acceleration_time / 2, 0, pose, twist);
  EXPECT_LT(angleBetween(pose.M, a.M), 1e-12);
  EXPECT_LT(twist.rot.Norm(), 1e-12);
  traj.evaluate(traj.waypointTimes()[1], 0, pose, twist);
  EXPECT_GT(angleBetween(pose.M, a.M), 1e-3);
  traj.evaluate(traj.duration(), 0, pose, twist);
  EXPECT_LT(angleBetween(pose.M, tiny.M), 1e-12);
  EXPECT_LT((pose.p - tiny.p).Norm(), 1e-12);
}

TEST(CartesianTrajectory, InvalidInputThrowsWithAMessageNamingIt) {
  const KDL::Frame f = KDL::Frame::Identity();
  EXPECT_CONTAINS(messageOf([&] { CartesianTrajectory(std::vector<KDL::Frame>{f}, kLimits); }),
                  "CartesianTrajectory: the path has 1 waypoint(s), expected at least 2");
  EXPECT_CONTAINS(messageOf([&] { CartesianTrajectory({{f, f}, {f, f}, {f}}, kLimits); }),
                  "CartesianTrajectory: waypoint 2 has 1 arms, expected 2 (as waypoint 0)");
  KDL::Frame sheared = f;
  sheared.M(0, 1) = 0.2;
  EXPECT_CONTAINS(messageOf([&] { CartesianTrajectory(std::vector<KDL::Frame>{f, sheared}, kLimits); }),
                  "waypoint 1 arm 0 has a rotation that is not a proper orthonormal matrix (|R^T R - I| = 0.2)");
  KDL::Frame mirrored = f;
  mirrored.M(2, 2) = -1.0;
  EXPECT_CONTAINS(messageOf([&] { CartesianTrajectory(std::vector<KDL::Frame>{mirrored, f}, kLimits); }),
                  "waypoint 0 arm 0 has a rotation that is not a proper orthonormal matrix");
  KDL::Frame far = f;
  far.p.y(std::nan(""));
  EXPECT_CONTAINS(messageOf([&] { CartesianTrajectory(std::vector<KDL::Frame>{f, far}, kLimits); }),
                  "waypoint 1 arm 0 has a position that is not finite");
  CartesianLimits bad = kLimits;
  bad.max_angular_velocity = 0.0;
  EXPECT_CONTAINS(messageOf([&] { CartesianTrajectory(std::vector<KDL::Frame>{f, f}, bad); }),
                  "CartesianTrajectory: max_angular_velocity is 0 rad/s, expected a finite value > 0");
  bad = kLimits;
  bad.linear_acceleration_time = -0.1;
  EXPECT_CONTAINS(messageOf([&] { CartesianTrajectory(std::vector<KDL::Frame>{f, f}, bad); }),
                  "linear_acceleration_time is -0.1 s");
  EXPECT_CONTAINS(messageOf([&] { CartesianTrajectory(std::vector<KDL::Frame>{f, f}, kLimits, 1); }),
                  "CartesianTrajectory: blend order 1 is out of range, expected 2 to 5");
}

}  // namespace
