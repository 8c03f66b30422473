// HandTracker: 200 frames per second, the field of view (pyramid between two heights), Gaussian
// noise of the configured size, hands lost outside the field of view, reproducible for a seed,
// no allocation, parameter errors.

#include "cobra/sim/hand_tracker.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "cobra/test_support/counting_new.hpp"
#include "cobra/test_support/test_support.hpp"

namespace {

using cobra::sim::HandTracker;
using cobra::sim::HandTrackerModel;

TEST(HandTracker, TakesTwoHundredFramesPerSecond) {
  HandTracker tracker(HandTrackerModel{}, 1);
  const KDL::Frame hand(KDL::Vector(0, 0, 0.2));
  int frames = 0;
  for (int i = 0; i < 1000; ++i) frames += tracker.step(1e-3, true, hand, true, hand);
  EXPECT_EQ(frames, 200);
  EXPECT_EQ(tracker.frame().id, 200U);
  for (int i = 0; i < 100; ++i) frames += tracker.step(1e-4, true, hand, true, hand);  // 10 ms in small steps
  EXPECT_EQ(frames, 202);
}

TEST(HandTracker, FieldOfViewIsAPyramidBetweenTwoHeights) {
  HandTracker tracker(HandTrackerModel{}, 1);
  EXPECT_TRUE(tracker.inFieldOfView(KDL::Vector(0, 0, 0.3)));
  EXPECT_FALSE(tracker.inFieldOfView(KDL::Vector(0, 0, 0.01)));  // too close
  EXPECT_FALSE(tracker.inFieldOfView(KDL::Vector(0, 0, 0.7)));   // too far
  const double x_edge = 0.1 * std::tan(75.0 * M_PI / 180.0);     // half of 150°
  EXPECT_TRUE(tracker.inFieldOfView(KDL::Vector(x_edge - 1e-4, 0, 0.1)));
  EXPECT_FALSE(tracker.inFieldOfView(KDL::Vector(x_edge + 1e-4, 0, 0.1)));
  const double y_edge = 0.1 * std::tan(60.0 * M_PI / 180.0);  // half of 120°
  EXPECT_TRUE(tracker.inFieldOfView(KDL::Vector(0, -y_edge + 1e-4, 0.1)));
  EXPECT_FALSE(tracker.inFieldOfView(KDL::Vector(0, -y_edge - 1e-4, 0.1)));
}

TEST(HandTracker, HandsAreLostOutsideTheFieldOfViewOrWhenAbsent) {
  HandTracker tracker(HandTrackerModel{}, 2);
  const KDL::Frame inside(KDL::Rotation::RotZ(0.3), KDL::Vector(0.05, 0.02, 0.25));
  const KDL::Frame outside(KDL::Vector(0.05, 0.02, 0.9));
  ASSERT_TRUE(tracker.step(5e-3, true, inside, false, inside));
  EXPECT_TRUE(tracker.frame().right.valid);
  EXPECT_FALSE(tracker.frame().left.valid);  // absent
  EXPECT_TRUE(tracker.frame().right.pose.M == inside.M);
  ASSERT_TRUE(tracker.step(5e-3, true, outside, true, inside));
  EXPECT_FALSE(tracker.frame().right.valid);
  EXPECT_TRUE(tracker.frame().left.valid);
}

// 20 000 frames of a still hand: the sample standard deviation per axis is the model's noise
// within 3 %, the mean within 4 standard errors; the same seed gives the same frames.
TEST(HandTracker, NoiseHasTheConfiguredSpreadAndIsReproducible) {
  HandTrackerModel model;
  model.position_noise = 1e-3;
  HandTracker a(model, 9), b(model, 9);
  const KDL::Frame hand(KDL::Vector(0.01, -0.02, 0.3));
  double sum[3] = {}, squares[3] = {};
  const int n = 20000;
  for (int i = 0; i < n; ++i) {
    a.step(5e-3, true, hand, true, hand);
    b.step(5e-3, true, hand, true, hand);
    ASSERT_TRUE(a.frame().right.pose == b.frame().right.pose);
    for (int k = 0; k < 3; ++k) {
      const double e = a.frame().right.pose.p[k] - hand.p[k];
      sum[k] += e;
      squares[k] += e * e;
    }
  }
  for (int k = 0; k < 3; ++k) {
    const double mean = sum[k] / n;
    EXPECT_NEAR(mean, 0.0, 4 * 1e-3 / std::sqrt(n));
    EXPECT_NEAR(std::sqrt(squares[k] / n - mean * mean), 1e-3, 3e-5);
  }
  EXPECT_EQ(cobra::test_support::allocationsDuring([&] {
              for (int i = 0; i < 100; ++i) a.step(1e-3, true, hand, true, hand);
            }),
            0);
}

TEST(HandTracker, BadParametersAreNamed) {
  HandTrackerModel model;
  model.max_height = 0.01;
  EXPECT_EQ(cobra::test_support::messageOf([&] { HandTracker t(model); }),
            "hand tracker: max_height = 0.010000, expected > min_height m");
  model = HandTrackerModel{};
  model.fov_x = 4.0;
  EXPECT_CONTAINS(cobra::test_support::messageOf([&] { HandTracker t(model); }),
                  "fov_x = 4.000000, expected in (0, pi) rad");
}

}  // namespace
