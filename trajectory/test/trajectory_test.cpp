// Trajectory and PolynomialTrajectory: clamping outside [0, T], the thesis' default duration, the
// stop trajectory and segment lookup.

#include "cobra/trajectory/trajectory.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "cobra/test_support/test_support.hpp"

namespace {

using cobra::test_support::messageOf;
using cobra::trajectory::Conditions;
using cobra::trajectory::Polynomial;
using cobra::trajectory::PolynomialTrajectory;
using cobra::trajectory::State;
using cobra::trajectory::stopTrajectory;

TEST(PolynomialTrajectory, DurationDefaultsToOneSecondAsInTheThesis) {
  const PolynomialTrajectory t(5, Conditions(0.0, 1.0));
  EXPECT_EQ(t.duration(), 1.0);
  EXPECT_EQ(t.segments().size(), 1u);
  EXPECT_EQ(t.polynomial().order(), 5);
}

TEST(PolynomialTrajectory, InsideTheIntervalItIsThePolynomial) {
  const Conditions c(State{1.0, 0.5, -0.2, 0.1}, State{-2.0, 0.3, 0.4, -0.5});
  const PolynomialTrajectory t(7, c, 2.5);
  const Polynomial p(7, c, 2.5);
  for (double time : {0.0, 0.3, 1.25, 2.0, 2.5}) {
    const State a = t.at(time);
    const State b = p.at(time);
    EXPECT_EQ(a.position, b.position);
    EXPECT_EQ(a.velocity, b.velocity);
    EXPECT_EQ(a.acceleration, b.acceleration);
    EXPECT_EQ(a.jerk, b.jerk);
  }
}

TEST(PolynomialTrajectory, OutsideTheIntervalItHoldsTheEndPositionsAtRest) {
  // Moving conditions on purpose: the clamp documents rest, not extrapolation of the end velocity.
  const PolynomialTrajectory t(5, Conditions(State{1.0, 2.0, 3.0}, State{4.0, -1.0, 2.0}), 2.0);
  for (double before : {-1e-9, -1.0, -1e9, -std::numeric_limits<double>::infinity(), std::nan("")}) {
    const State s = t.at(before);
    EXPECT_EQ(s.position, 1.0) << before;
    EXPECT_EQ(s.velocity, 0.0);
    EXPECT_EQ(s.acceleration, 0.0);
    EXPECT_EQ(s.jerk, 0.0);
  }
  for (double after : {2.0 + 1e-9, 3.0, 1e9, std::numeric_limits<double>::infinity()}) {
    const State s = t.at(after);
    EXPECT_NEAR(s.position, 4.0, 1e-12) << after;
    EXPECT_EQ(s.velocity, 0.0);
    EXPECT_EQ(s.acceleration, 0.0);
    EXPECT_EQ(s.jerk, 0.0);
  }
  EXPECT_NEAR(t.at(2.0).velocity, -1.0, 1e-12);  // at exactly T the conditions hold
}

TEST(StopTrajectory, BringsAMovingAxisToRestInTheStopTime) {
  const State current{0.2, 0.8, -1.5};
  const auto stop = stopTrajectory(current, 0.4);
  EXPECT_EQ(stop.duration(), 0.4);
  const State start = stop.at(0.0);
  EXPECT_NEAR(start.velocity, 0.8, 1e-12);
  EXPECT_NEAR(start.acceleration, -1.5, 1e-12);
  const State end = stop.at(0.4);
  EXPECT_NEAR(end.velocity, 0.0, 1e-12);
  EXPECT_NEAR(end.acceleration, 0.0, 1e-12);
  const State later = stop.at(10.0);
  EXPECT_NEAR(later.position, end.position, 1e-15);
  EXPECT_EQ(later.velocity, 0.0);
  EXPECT_CONTAINS(messageOf([] { stopTrajectory(State{}, -0.1); }), "stop time is -0.1 s");
}

TEST(PolynomialTrajectory, InvalidInputThrows) {
  EXPECT_CONTAINS(messageOf([] { PolynomialTrajectory(9, Conditions(0, 1), 1.0); }), "order 9 is out of range");
  EXPECT_CONTAINS(messageOf([] { PolynomialTrajectory(3, Conditions(0, 1), 0.0); }), "duration is 0 s");
}

}  // namespace
