// MultiPointLinearTrajBlends: the thesis' eq. 3.13 for one segment, exact end points, inner lines
// through the waypoints, continuity at every joint up to each blend order's guaranteed derivative
// (seeded random property test), velocity bounds inside blends, and the messages of invalid input.

#include "cobra/trajectory/multi_point.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "cobra/test_support/test_support.hpp"

namespace {

using cobra::test_support::messageOf;
using cobra::trajectory::MultiPointInterpolation;
using cobra::trajectory::MultiPointLinearTrajBlends;
using cobra::trajectory::State;

constexpr int kRandomPaths = 200;  // per blend order in the property tests

struct RandomPath {
  std::vector<double> waypoints;
  std::vector<double> durations;
  double acceleration_time;
};

RandomPath randomPath(std::mt19937& rng) {
  std::uniform_int_distribution<int> count(2, 9);
  std::uniform_real_distribution<double> position(-1.0, 1.0), unit(0.0, 1.0);
  RandomPath p;
  p.acceleration_time = 0.05 + 0.5 * unit(rng);
  const int n = count(rng);
  for (int k = 0; k < n; ++k) p.waypoints.push_back(position(rng));
  const std::size_t segments = p.waypoints.size() - 1;
  for (std::size_t k = 0; k < segments; ++k)
    p.durations.push_back(MultiPointLinearTrajBlends::minimumSegmentDuration(k, segments, p.acceleration_time) +
                          (unit(rng) < 0.2 ? 0.0 : 2.0 * unit(rng)));  // some segments with no linear part
  return p;
}

TEST(MultiPointLinearTrajBlends, OneSegmentWithParabolicBlendsIsTheThesisEquation3_13) {
  const double q0 = 0.5, q1 = 2.5, t1 = 3.0, ta = 0.6;
  const double vv = (q1 - q0) / (t1 - ta);  // eq. 3.10 with b0 on the line through both ends
  const MultiPointLinearTrajBlends traj(std::vector{q0, q1}, std::vector{t1}, ta, 2);
  ASSERT_EQ(traj.segmentVelocities().size(), 1u);
  EXPECT_NEAR(traj.segmentVelocities()[0], vv, 1e-12);
  for (int i = 0; i <= 300; ++i) {
    const double t = t1 * i / 300.0;
    double expected = 0.0;
    if (t < ta) expected = q0 + vv / (2 * ta) * t * t;
    else if (t < t1 - ta) expected = q0 + vv * (t - ta / 2);
    else expected = q1 - vv / (2 * ta) * (t1 - t) * (t1 - t);
    ASSERT_NEAR(traj.at(t).position, expected, 1e-12) << "t = " << t;
  }
  // eq. 3.8: a2 = v_v / (2 T_a), so the acceleration of the first phase is v_v / T_a.
  EXPECT_NEAR(traj.at(ta / 2).acceleration, vv / ta, 1e-12);
  EXPECT_NEAR(traj.at(t1 - ta / 2).acceleration, -vv / ta, 1e-12);
}

TEST(MultiPointLinearTrajBlends, StartsAndEndsExactlyAtRestAndInnerLinesPassThroughTheWaypoints) {
  std::mt19937 rng(11);
  for (int order = 2; order <= 5; ++order) {
    for (int i = 0; i < kRandomPaths; ++i) {
      const RandomPath p = randomPath(rng);
      const MultiPointLinearTrajBlends traj(p.waypoints, p.durations, p.acceleration_time, order);
      const State start = traj.at(0.0);
      const State end = traj.at(traj.duration());
      ASSERT_NEAR(start.position, p.waypoints.front(), 1e-12);
      ASSERT_NEAR(end.position, p.waypoints.back(), 1e-9);
      ASSERT_NEAR(start.velocity, 0.0, 1e-12);
      ASSERT_NEAR(end.velocity, 0.0, 1e-9);
      ASSERT_EQ(traj.waypointCount(), p.waypoints.size());
      // Each inner waypoint's incoming and outgoing lines meet at (t_k, q_k): extrapolate both lines
      // from the middle of their linear parts.
      const auto times = traj.waypointTimes();
      const auto v = traj.segmentVelocities();
      for (std::size_t k = 1; k + 1 < p.waypoints.size(); ++k) {
        const double ta = p.acceleration_time;
        const double in_end = times[k] - ta / 2, out_start = times[k] + ta / 2;
        const double in_t = std::max(in_end - 1e-3, times[k - 1] + (k == 1 ? ta : ta / 2));
        const double out_t = std::min(out_start + 1e-3, times[k + 1] - (k + 2 == p.waypoints.size() ? ta : ta / 2));
        ASSERT_NEAR(traj.at(in_t).position + v[k - 1] * (times[k] - in_t), p.waypoints[k], 1e-9) << "waypoint " << k;
        ASSERT_NEAR(traj.at(out_t).position - v[k] * (out_t - times[k]), p.waypoints[k], 1e-9) << "waypoint " << k;
      }
    }
  }
}

TEST(MultiPointLinearTrajBlends, IsContinuousAtEveryJointUpToTheGuaranteedDerivative) {
  std::mt19937 rng(12);
  for (int order = 2; order <= 5; ++order) {
    const bool c2 = order >= 4;
    for (int i = 0; i < kRandomPaths; ++i) {
      const RandomPath p = randomPath(rng);
      const MultiPointLinearTrajBlends traj(p.waypoints, p.durations, p.acceleration_time, order);
      const auto segments = traj.segments();
      for (std::size_t s = 1; s < segments.size(); ++s) {
        const auto& previous = segments[s - 1];
        ASSERT_NEAR(previous.start_time + previous.polynomial.duration(), segments[s].start_time, 1e-12);
        const State left = previous.polynomial.at(previous.polynomial.duration());
        const State right = segments[s].polynomial.at(0.0);
        ASSERT_NEAR(left.position, right.position, 1e-10) << "order " << order << " joint " << s;
        ASSERT_NEAR(left.velocity, right.velocity, 1e-9) << "order " << order << " joint " << s;
        if (c2) {
          ASSERT_NEAR(left.acceleration, right.acceleration, 1e-7) << "order " << order << " joint " << s;
        }
      }
    }
  }
}

TEST(MultiPointLinearTrajBlends, ParabolicBlendsDoJumpInAccelerationSoTheC2CheckIsMeaningful) {
  const MultiPointLinearTrajBlends traj(std::vector{0.0, 1.0, 0.0}, std::vector{2.0, 2.0}, 0.4, 2);
  const auto& first = traj.segments()[0].polynomial;
  EXPECT_GT(std::abs(first.at(first.duration()).acceleration), 1.0);
}

TEST(MultiPointLinearTrajBlends, BlendOrdersPairUpAsTheHeaderSays) {
  // With both lines meeting at the blend centre, the cubic blend is the parabola and the quintic is
  // the quartic: the extra end conditions already hold.
  std::mt19937 rng(14);
  for (int i = 0; i < kRandomPaths; ++i) {
    const RandomPath p = randomPath(rng);
    const MultiPointLinearTrajBlends o2(p.waypoints, p.durations, p.acceleration_time, 2);
    const MultiPointLinearTrajBlends o3(p.waypoints, p.durations, p.acceleration_time, 3);
    const MultiPointLinearTrajBlends o4(p.waypoints, p.durations, p.acceleration_time, 4);
    const MultiPointLinearTrajBlends o5(p.waypoints, p.durations, p.acceleration_time, 5);
    for (int j = 0; j <= 200; ++j) {
      const double t = o2.duration() * j / 200.0;
      ASSERT_NEAR(o2.at(t).position, o3.at(t).position, 1e-9);
      ASSERT_NEAR(o4.at(t).position, o5.at(t).position, 1e-9);
      ASSERT_NEAR(o4.at(t).acceleration, o5.at(t).acceleration, 1e-6);
    }
  }
}

TEST(MultiPointLinearTrajBlends, BlendVelocitiesStayBetweenTheirLineVelocities) {
  std::mt19937 rng(13);
  for (int order = 2; order <= 5; ++order) {
    for (int i = 0; i < kRandomPaths; ++i) {
      const RandomPath p = randomPath(rng);
      const MultiPointLinearTrajBlends traj(p.waypoints, p.durations, p.acceleration_time, order);
      double peak = 0.0;
      for (double v : traj.segmentVelocities()) peak = std::max(peak, std::abs(v));
      for (int j = 0; j <= 2000; ++j) ASSERT_LE(std::abs(traj.at(traj.duration() * j / 2000.0).velocity), peak * (1 + 1e-9));
    }
  }
}

TEST(MultiPointLinearTrajBlends, InvalidInputThrowsWithAMessageNamingIt) {
  const auto make = [](std::vector<double> q, std::vector<double> d, double ta, int order) {
    return [=] { MultiPointLinearTrajBlends(q, d, ta, order); };
  };
  EXPECT_CONTAINS(messageOf(make({1.0}, {}, 0.1, 5)),
                  "MultiPointLinearTrajBlends: the path has 1 waypoint(s), expected at least 2");
  EXPECT_CONTAINS(messageOf(make({0, 1, 2}, {1.0}, 0.1, 5)), "3 waypoints need 2 segment durations, got 1");
  EXPECT_CONTAINS(messageOf(make({0, 1}, {1.0}, 0.1, 1)), "blend order 1 is out of range, expected 2 to 5");
  EXPECT_CONTAINS(messageOf(make({0, 1}, {1.0}, 0.1, 6)), "blend order 6 is out of range");
  EXPECT_CONTAINS(messageOf(make({0, 1}, {1.0}, 0.0, 5)), "acceleration time is 0 s, expected a finite value > 0");
  EXPECT_CONTAINS(messageOf(make({0, std::nan(""), 1}, {1.0, 1.0}, 0.1, 5)), "waypoint 1 is nan, expected a finite");
  EXPECT_CONTAINS(messageOf(make({0, 1, 2}, {1.0, -1.0}, 0.1, 5)), "duration of segment 1 is -1 s");
  EXPECT_CONTAINS(messageOf(make({0, 1, 2, 3}, {1.0, 0.3, 1.0}, 0.5, 5)),
                  "segment 1 lasts 0.3 s but its blends take 0.5 s (acceleration time 0.5 s); lengthen the segment to "
                  "at least 0.5 s or shorten the acceleration time");
  EXPECT_CONTAINS(messageOf(make({0, 1}, {0.9}, 0.5, 5)), "segment 0 lasts 0.9 s but its blends take 1 s");
  EXPECT_CONTAINS(messageOf(make({0, 1, 2}, {0.7, 1.0}, 0.5, 5)), "segment 0 lasts 0.7 s but its blends take 0.75 s");
  // Exactly the minimum is accepted: blends touch, no linear part.
  EXPECT_EQ(messageOf(make({0, 1}, {1.0}, 0.5, 5)), "(no error)");
}

TEST(MultiPointInterpolation, PassesThroughEveryWaypointWithTheOrdersContinuity) {
  std::mt19937 rng(15);
  for (int order : {3, 5, 7}) {
    for (int i = 0; i < kRandomPaths; ++i) {
      const RandomPath p = randomPath(rng);
      const MultiPointInterpolation traj(p.waypoints, p.durations, order);
      const auto times = traj.waypointTimes();
      ASSERT_EQ(traj.segments().size(), p.waypoints.size() - 1);
      for (std::size_t k = 0; k < p.waypoints.size(); ++k) {
        const State s = traj.at(times[k]);
        ASSERT_NEAR(s.position, p.waypoints[k], 1e-12) << "order " << order << " waypoint " << k;
        ASSERT_NEAR(s.velocity, traj.waypointVelocities()[k], 1e-9);
      }
      for (std::size_t s = 1; s < traj.segments().size(); ++s) {
        const auto& left_poly = traj.segments()[s - 1].polynomial;
        const State left = left_poly.at(left_poly.duration());
        const State right = traj.segments()[s].polynomial.at(0.0);
        ASSERT_NEAR(left.velocity, right.velocity, 1e-9);
        if (order >= 5) {
          ASSERT_NEAR(left.acceleration, right.acceleration, 1e-7);
        }
        if (order == 7) {
          ASSERT_NEAR(left.jerk, right.jerk, 1e-5);
        }
      }
    }
  }
}

TEST(MultiPointInterpolation, WaypointVelocitiesFollowTheSlopeHeuristic) {
  // Slopes 1, 1, -2, -1: the rising pair averages, the turn stops, the falling pair averages.
  const std::vector<double> q{0.0, 1.0, 2.0, 0.0, -1.0};
  const MultiPointInterpolation traj(q, std::vector{1.0, 1.0, 1.0, 1.0}, 3);
  const auto v = traj.waypointVelocities();
  ASSERT_EQ(v.size(), 5u);
  EXPECT_EQ(v[0], 0.0);
  EXPECT_DOUBLE_EQ(v[1], 1.0);
  EXPECT_EQ(v[2], 0.0);
  EXPECT_DOUBLE_EQ(v[3], -1.5);
  EXPECT_EQ(v[4], 0.0);
  EXPECT_CONTAINS(messageOf([&] { MultiPointInterpolation(q, std::vector{1.0, 1.0, 1.0, 1.0}, 4); }),
                  "MultiPointInterpolation: order 4 is not supported, expected 3, 5 or 7");
  EXPECT_CONTAINS(messageOf([&] { MultiPointInterpolation(q, std::vector{1.0, 1.0, 0.0, 1.0}, 5); }),
                  "MultiPointInterpolation: duration of segment 2 is 0 s");
}

}  // namespace
