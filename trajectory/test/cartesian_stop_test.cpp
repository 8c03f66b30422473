// CartesianStop: from any point of a moving Cartesian trajectory (blends included) to rest in the
// stop time, continuous in pose, twist and acceleration where it starts, on SO(3), with twist and
// acceleration the derivatives of pose and twist; invalid input refused with a message.

#include "cobra/trajectory/cartesian_stop.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "cobra/test_support/test_support.hpp"
#include "cobra/trajectory/cartesian.hpp"
#include "rotation_checks.hpp"

namespace {

using cobra::test_support::messageOf;
using cobra::trajectory::CartesianLimits;
using cobra::trajectory::CartesianStop;
using cobra::trajectory::CartesianTrajectory;
using cobra::trajectory::test::rotationError;
using cobra::trajectory::test::smallRotationVector;

constexpr int kStops = 300;  // random stop instants on random moving paths

TEST(CartesianStop, StartsWhereTheMotionIsAndEndsAtRest) {
  std::mt19937 rng(41);
  std::uniform_real_distribution<double> angle(-M_PI, M_PI), position(-0.5, 0.5), unit(0.0, 1.0);
  constexpr double h = 1e-5;
  for (int n = 0; n < kStops; ++n) {
    std::vector<KDL::Frame> path;
    for (int k = 0; k < 4; ++k)
      path.emplace_back(KDL::Rotation::RPY(angle(rng), angle(rng) / 2, angle(rng)),
                        KDL::Vector(position(rng), position(rng), position(rng)));
    const CartesianTrajectory moving(path, CartesianLimits{0.2, 0.8, 0.3, 0.4}, 5);
    const double when = moving.duration() * unit(rng);
    KDL::Frame pose;
    KDL::Twist twist, acceleration;
    moving.evaluate(when, 0, pose, twist, acceleration);
    const double stop_time = 0.1 + unit(rng);
    const CartesianStop stop(pose, twist, acceleration, stop_time);
    ASSERT_EQ(stop.duration(), stop_time);

    KDL::Frame p0;
    KDL::Twist v0, a0;
    stop.evaluate(0.0, p0, v0, a0);
    ASSERT_TRUE(KDL::Equal(p0, pose, 1e-12));
    ASSERT_TRUE(KDL::Equal(v0, twist, 1e-12));
    ASSERT_TRUE(KDL::Equal(a0, acceleration, 1e-9));

    KDL::Frame rest, after;
    KDL::Twist v1, a1, v2, a2;
    stop.evaluate(stop_time, rest, v1, a1);
    ASSERT_TRUE(KDL::Equal(v1, KDL::Twist::Zero(), 1e-9));
    ASSERT_TRUE(KDL::Equal(a1, KDL::Twist::Zero(), 1e-9));
    stop.evaluate(stop_time + 1.0, after, v2, a2);
    ASSERT_TRUE(KDL::Equal(after, rest, 1e-15));
    ASSERT_EQ(v2.vel.Norm() + v2.rot.Norm(), 0.0);

    for (int j = 1; j < 50; ++j) {
      const double t = stop_time * j / 50.0;
      KDL::Frame here, minus, plus;
      KDL::Twist v, a, v_minus, v_plus, unused;
      stop.evaluate(t, here, v, a);
      stop.evaluate(t - h, minus, v_minus, unused);
      stop.evaluate(t + h, plus, v_plus, unused);
      ASSERT_LT(rotationError(here.M), 1e-12);
      ASSERT_LT((smallRotationVector(plus.M * minus.M.Inverse()) / (2 * h) - v.rot).Norm(), 1e-6) << "t " << t;
      ASSERT_LT(((plus.p - minus.p) / (2 * h) - v.vel).Norm(), 1e-6);
      ASSERT_LT(((v_plus.rot - v_minus.rot) / (2 * h) - a.rot).Norm(), 1e-5) << "t " << t;
      ASSERT_LT(((v_plus.vel - v_minus.vel) / (2 * h) - a.vel).Norm(), 1e-5);
    }
  }
}

TEST(CartesianStop, FromRestItStaysPut) {
  const KDL::Frame pose(KDL::Rotation::RPY(0.3, 0.2, 0.1), KDL::Vector(0.1, 0.2, 0.3));
  const CartesianStop stop(pose, KDL::Twist::Zero(), KDL::Twist::Zero(), 0.5);
  KDL::Frame p;
  KDL::Twist v;
  stop.evaluate(0.25, p, v);
  EXPECT_TRUE(KDL::Equal(p, pose, 1e-15));
  EXPECT_EQ(v.vel.Norm() + v.rot.Norm(), 0.0);
}

TEST(CartesianStop, InvalidInputThrowsWithAMessageNamingIt) {
  const KDL::Frame f = KDL::Frame::Identity();
  const KDL::Twist zero = KDL::Twist::Zero();
  EXPECT_CONTAINS(messageOf([&] { CartesianStop(f, zero, zero, 0.0); }),
                  "CartesianStop: stop time is 0 s, expected a finite value > 0");
  KDL::Twist bad = zero;
  bad.rot.y(std::numeric_limits<double>::infinity());
  EXPECT_CONTAINS(messageOf([&] { CartesianStop(f, bad, zero, 1.0); }),
                  "CartesianStop: angular velocity component 1 is inf, expected a finite number");
  bad = zero;
  bad.vel.z(std::nan(""));
  EXPECT_CONTAINS(messageOf([&] { CartesianStop(f, zero, bad, 1.0); }), "linear acceleration component 2 is nan");
}

}  // namespace
