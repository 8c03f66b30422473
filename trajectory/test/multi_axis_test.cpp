// MultiAxisTrajectory: synchronisation at every waypoint, velocity limits, the slowest axis setting
// each segment's duration, polynomial and stop constructors, and the messages of invalid input.

#include "cobra/trajectory/multi_axis.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "cobra/test_support/test_support.hpp"

namespace {

using cobra::test_support::messageOf;
using cobra::trajectory::AxisLimits;
using cobra::trajectory::Conditions;
using cobra::trajectory::MultiAxisConditions;
using cobra::trajectory::MultiAxisPath;
using cobra::trajectory::MultiAxisTrajectory;
using cobra::trajectory::MultiPointLinearTrajBlends;
using cobra::trajectory::State;

constexpr int kRandomPaths = 150;  // random multi-axis paths in each property test

struct RandomProblem {
  MultiAxisPath path;
  AxisLimits limits;
};

RandomProblem randomProblem(std::mt19937& rng) {
  std::uniform_int_distribution<int> axes_count(1, 7), waypoint_count(2, 10);
  std::uniform_real_distribution<double> position(-1.0, 1.0), unit(0.0, 1.0);
  RandomProblem p;
  const int axes = axes_count(rng);
  const int waypoints = waypoint_count(rng);
  for (int k = 0; k < waypoints; ++k) {
    std::vector<double> q;
    for (int i = 0; i < axes; ++i) q.push_back(unit(rng) < 0.15 && k > 0 ? p.path.waypoint(k - 1)[i] : position(rng));
    p.path.addWaypoint(q);
  }
  for (int i = 0; i < axes; ++i) {
    p.limits.max_velocity.push_back(0.1 + 2.0 * unit(rng));
    p.limits.acceleration_time.push_back(0.02 + 0.4 * unit(rng));
  }
  return p;
}

/// Axis `i` of `p` alone through the waypoint times `traj` chose: what traj.axis(i) must be.
MultiPointLinearTrajBlends axisAlone(const RandomProblem& p, const MultiAxisTrajectory& traj, std::size_t i, int order) {
  std::vector<double> coordinates, durations;
  for (const auto& waypoint : p.path.waypoints()) coordinates.push_back(waypoint[i]);
  for (std::size_t k = 1; k < traj.waypointTimes().size(); ++k)
    durations.push_back(traj.waypointTimes()[k] - traj.waypointTimes()[k - 1]);
  return MultiPointLinearTrajBlends(coordinates, durations, p.limits.acceleration_time[i], order);
}

TEST(MultiAxisTrajectory, AllAxesShareTheWaypointTimesAndReachTheEndTogether) {
  std::mt19937 rng(21);
  for (int order = 2; order <= 5; ++order) {
    for (int n = 0; n < kRandomPaths; ++n) {
      const RandomProblem p = randomProblem(rng);
      const MultiAxisTrajectory traj(p.path, p.limits, order);
      ASSERT_EQ(traj.axisCount(), p.path.axisCount());
      ASSERT_EQ(traj.waypointTimes().size(), p.path.size());
      ASSERT_EQ(traj.duration(), traj.waypointTimes().back());
      std::vector<State> start(traj.axisCount()), end(traj.axisCount());
      traj.evaluate(0.0, start);
      traj.evaluate(traj.duration(), end);
      for (std::size_t i = 0; i < traj.axisCount(); ++i) {
        // Same time line: every axis is its own multi-point trajectory through the shared waypoint times.
        const MultiPointLinearTrajBlends axis = axisAlone(p, traj, i, order);
        ASSERT_NEAR(axis.duration(), traj.duration(), 1e-12);
        for (int j = 0; j <= 50; ++j) {
          const double t = traj.duration() * j / 50.0;
          ASSERT_NEAR(axis.at(t).position, traj.axis(i).at(t).position, 1e-12);
        }
        // Each axis' inner line passes through its waypoint at the shared t_k (the blend corner).
        const auto v = axis.segmentVelocities();
        for (std::size_t k = 1; k + 1 < p.path.size(); ++k) {
          const double tk = traj.waypointTimes()[k];
          const double ta = p.limits.acceleration_time[i];
          const double before = tk - ta / 2;  // end of the incoming line
          ASSERT_NEAR(axis.at(before).position + v[k - 1] * ta / 2, p.path.waypoint(k)[i], 1e-9)
              << "axis " << i << " waypoint " << k;
        }
        ASSERT_NEAR(start[i].position, p.path.waypoint(0)[i], 1e-12);
        ASSERT_NEAR(end[i].position, p.path.waypoints().back()[i], 1e-9);
        ASSERT_NEAR(end[i].velocity, 0.0, 1e-9);
        if (order >= 4) {  // parabolic blends end with the deceleration of eq. 3.12, not zero
          ASSERT_NEAR(end[i].acceleration, 0.0, 1e-7);
        }
      }
    }
  }
}

TEST(MultiAxisTrajectory, NoAxisExceedsItsMaxVelocityAndTheSlowestAxisReachesIt) {
  std::mt19937 rng(22);
  for (int n = 0; n < kRandomPaths; ++n) {
    const RandomProblem p = randomProblem(rng);
    const MultiAxisTrajectory traj(p.path, p.limits, 5);
    std::vector<State> s(traj.axisCount());
    for (int j = 0; j <= 3000; ++j) {
      traj.evaluate(traj.duration() * j / 3000.0, s);
      for (std::size_t i = 0; i < s.size(); ++i)
        ASSERT_LE(std::abs(s[i].velocity), p.limits.max_velocity[i] * (1 + 1e-9)) << "axis " << i;
    }
    // Every segment is as short as allowed: either some axis cruises at its max velocity on it, or
    // it has the minimum duration the blends need.
    const std::size_t segments = p.path.size() - 1;
    for (std::size_t k = 0; k < segments; ++k) {
      const double duration = traj.waypointTimes()[k + 1] - traj.waypointTimes()[k];
      bool limited = false;
      for (std::size_t i = 0; i < traj.axisCount(); ++i) {
        const MultiPointLinearTrajBlends axis = axisAlone(p, traj, i, 5);
        const double ta = p.limits.acceleration_time[i];
        limited = limited || std::abs(std::abs(axis.segmentVelocities()[k]) - p.limits.max_velocity[i]) < 1e-9 ||
                  std::abs(duration - MultiPointLinearTrajBlends::minimumSegmentDuration(k, segments, ta)) < 1e-12;
      }
      ASSERT_TRUE(limited) << "segment " << k << " is longer than its slowest axis needs";
    }
  }
}

TEST(MultiAxisTrajectory, TheSlowerAxisIsScaledDownToTheFasterOnesDuration) {
  // Axis 0 moves 1 at 1 /s, axis 1 moves 4 at 1 /s: the segment lasts 4 + T_a, and axis 0 moves at
  // 1 / 4 of its limit.
  const MultiAxisPath path({{0.0, 0.0}, {1.0, 4.0}});
  const MultiAxisTrajectory traj(path, AxisLimits{{1.0, 1.0}, {0.5, 0.5}}, 2);
  EXPECT_NEAR(traj.duration(), 4.5, 1e-12);
  std::vector<State> mid(2);
  traj.evaluate(traj.duration() / 2, mid);
  EXPECT_NEAR(mid[0].velocity, 0.25, 1e-12);
  EXPECT_NEAR(mid[1].velocity, 1.0, 1e-12);
}

TEST(MultiAxisTrajectory, EvaluateWritesOnlyAsManyAxesAsTheSpanHolds) {
  const MultiAxisTrajectory traj(MultiAxisPath({{0.0, 0.0, 0.0}, {1.0, 2.0, 3.0}}), AxisLimits{{1, 1, 1}, {0.1, 0.1, 0.1}});
  std::vector<State> two(2);
  traj.evaluate(traj.duration(), two);
  EXPECT_NEAR(two[1].position, 2.0, 1e-12);
  std::vector<State> four(4, State{42.0});
  traj.evaluate(traj.duration(), four);
  EXPECT_NEAR(four[2].position, 3.0, 1e-12);
  EXPECT_EQ(four[3].position, 42.0);
}

TEST(MultiAxisTrajectory, PolynomialPerAxisFromMultiAxisConditions) {
  const MultiAxisConditions conditions({Conditions(State{0.0, 1.0}, State{1.0}), Conditions(2.0, -1.0)});
  const MultiAxisTrajectory traj(5, conditions, 2.0);
  EXPECT_EQ(traj.duration(), 2.0);
  ASSERT_EQ(traj.waypointTimes().size(), 2u);
  std::vector<State> s(2);
  traj.evaluate(0.0, s);
  EXPECT_NEAR(s[0].velocity, 1.0, 1e-12);
  traj.evaluate(2.0, s);
  EXPECT_NEAR(s[0].position, 1.0, 1e-12);
  EXPECT_NEAR(s[1].position, -1.0, 1e-12);
  const std::vector<double> from{0, 1}, to{2, 3};
  EXPECT_EQ(MultiAxisConditions(from, to).axisCount(), 2u);
}

TEST(MultiAxisTrajectory, StopBringsEveryAxisToRestAtTheStopTime) {
  const MultiAxisTrajectory moving(MultiAxisPath({{0.0, 0.0}, {1.0, -2.0}, {3.0, 0.5}}), AxisLimits{{1, 2}, {0.3, 0.2}});
  std::vector<State> now(2);
  moving.evaluate(moving.duration() * 0.4, now);
  ASSERT_GT(std::abs(now[0].velocity) + std::abs(now[1].velocity), 0.1);
  const MultiAxisTrajectory stop = MultiAxisTrajectory::stop(now, 0.25);
  std::vector<State> s(2);
  stop.evaluate(0.0, s);
  for (std::size_t i = 0; i < 2; ++i) {
    EXPECT_NEAR(s[i].position, now[i].position, 1e-12);
    EXPECT_NEAR(s[i].velocity, now[i].velocity, 1e-12);
    EXPECT_NEAR(s[i].acceleration, now[i].acceleration, 1e-9);
  }
  stop.evaluate(0.25, s);
  for (const State& axis : s) {
    EXPECT_NEAR(axis.velocity, 0.0, 1e-12);
    EXPECT_NEAR(axis.acceleration, 0.0, 1e-9);
  }
}

TEST(MultiAxisTrajectory, InvalidInputThrowsWithAMessageNamingIt) {
  const AxisLimits six{std::vector<double>(6, 1.0), std::vector<double>(6, 0.1)};
  const std::vector<double> q6(6, 0.0), q5(5, 0.0);
  EXPECT_CONTAINS(messageOf([&] { MultiAxisTrajectory(MultiAxisPath({q6, q6, q6, q5}), six); }),
                  "MultiAxisTrajectory: waypoint 3 has 5 axes, expected 6 (as waypoint 0)");
  EXPECT_CONTAINS(messageOf([&] { MultiAxisTrajectory(MultiAxisPath({q6}), six); }),
                  "MultiAxisTrajectory: the path has 1 waypoint(s), expected at least 2");
  EXPECT_CONTAINS(messageOf([&] { MultiAxisTrajectory(MultiAxisPath({{}, {}}), six); }),
                  "waypoint 0 has no axes, expected at least 1");
  EXPECT_CONTAINS(messageOf([&] { MultiAxisTrajectory(MultiAxisPath({q5, q5}), six); }),
                  "MultiAxisTrajectory: max_velocity has 6 values, expected 5 (one per axis of the path)");
  AxisLimits bad = six;
  bad.max_velocity[2] = 0.0;
  EXPECT_CONTAINS(messageOf([&] { MultiAxisTrajectory(MultiAxisPath({q6, q6}), bad); }),
                  "MultiAxisTrajectory: max_velocity of axis 2 is 0 (axis unit)/s, expected a finite value > 0");
  bad = six;
  bad.acceleration_time.pop_back();
  EXPECT_CONTAINS(messageOf([&] { MultiAxisTrajectory(MultiAxisPath({q6, q6}), bad); }),
                  "acceleration_time has 5 values, expected 6");
  bad = six;
  bad.acceleration_time[4] = -1.0;
  EXPECT_CONTAINS(messageOf([&] { MultiAxisTrajectory(MultiAxisPath({q6, q6}), bad); }),
                  "acceleration_time of axis 4 is -1 s");
  std::vector<double> nan_waypoint = q6;
  nan_waypoint[1] = std::nan("");
  EXPECT_CONTAINS(messageOf([&] { MultiAxisTrajectory(MultiAxisPath({q6, nan_waypoint}), six); }),
                  "MultiAxisTrajectory: waypoint 1 axis 1 is nan, expected a finite number");
  EXPECT_CONTAINS(messageOf([&] { MultiAxisTrajectory(MultiAxisPath({q6, q6}), six, 7); }),
                  "blend order 7 is out of range, expected 2 to 5");
  EXPECT_CONTAINS(messageOf([] { MultiAxisTrajectory(5, MultiAxisConditions(), 1.0); }),
                  "the conditions have no axes");
  const std::vector<double> two{0, 1}, three{0, 1, 2};
  EXPECT_CONTAINS(messageOf([&] { MultiAxisConditions(two, three); }),
                  "MultiAxisConditions: 2 initial positions but 3 final ones");
  EXPECT_CONTAINS(messageOf([] { MultiAxisTrajectory::stop({}, 1.0); }), "stop from a state with no axes");
  const std::vector<State> one(1);
  EXPECT_CONTAINS(messageOf([&] { MultiAxisTrajectory::stop(one, 0.0); }), "stop time is 0 s");
}

}  // namespace
