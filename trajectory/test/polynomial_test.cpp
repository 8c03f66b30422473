// Polynomial: the boundary conditions of every order (seeded random property test), derivative
// consistency, the stop motion, the thesis' closed forms and KDL's spline as an independent peer.

#include "cobra/trajectory/polynomial.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include <kdl/velocityprofile_spline.hpp>

#include "cobra/test_support/test_support.hpp"

namespace {

using cobra::test_support::messageOf;
using cobra::trajectory::Conditions;
using cobra::trajectory::Polynomial;
using cobra::trajectory::State;

constexpr int kCasesPerOrder = 500;  // random boundary problems per order in the property test

double component(const State& s, int k) {
  switch (k) {
    case 0: return s.position;
    case 1: return s.velocity;
    case 2: return s.acceleration;
    default: return s.jerk;
  }
}

State randomState(std::mt19937& rng) {
  std::uniform_real_distribution<double> value(-2.0, 2.0);
  return State{value(rng), value(rng), value(rng), value(rng)};
}

TEST(Polynomial, MeetsTheBoundaryConditionsOfEveryOrder) {
  std::mt19937 rng(20240611);
  std::uniform_real_distribution<double> duration(0.05, 8.0);
  for (int order = Polynomial::kMinOrder; order <= Polynomial::kMaxOrder; ++order) {
    const int initial_count = (order + 2) / 2;  // the header's table: even orders favour the start
    const int final_count = (order + 1) / 2;
    for (int i = 0; i < kCasesPerOrder; ++i) {
      const State q0 = randomState(rng);
      const State q1 = randomState(rng);
      const double T = duration(rng);
      const Polynomial p(order, Conditions(q0, q1), T);
      const State at0 = p.at(0.0);
      const State atT = p.at(T);
      for (int k = 0; k < initial_count; ++k)
        ASSERT_NEAR(component(at0, k), component(q0, k), 1e-9 * (1.0 + std::pow(T, -k)))
            << "order " << order << " derivative " << k << " at t = 0, T = " << T;
      for (int k = 0; k < final_count; ++k)
        ASSERT_NEAR(component(atT, k), component(q1, k), 1e-8 * (1.0 + std::pow(T, -k)))
            << "order " << order << " derivative " << k << " at t = T = " << T;
    }
  }
}

TEST(Polynomial, ConditionsBeyondTheOrderAreNotMetSoTheTableIsReal) {
  // A cubic cannot also meet end accelerations: proves the property test checks the right rows.
  const Polynomial cubic(3, Conditions(State{0, 0, 1, 0}, State{1, 0, 1, 0}), 1.0);
  EXPECT_GT(std::abs(cubic.at(0.0).acceleration - 1.0), 0.1);
}

TEST(Polynomial, DerivativesAreTheNumericalDerivativesOfEachOther) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  constexpr double h = 1e-5;
  for (int order = Polynomial::kMinOrder; order <= Polynomial::kMaxOrder; ++order) {
    for (int i = 0; i < 50; ++i) {
      const double T = 0.2 + 3.0 * unit(rng);
      const Polynomial p(order, Conditions(randomState(rng), randomState(rng)), T);
      const double t = T * unit(rng);
      const State minus = p.at(t - h);
      const State plus = p.at(t + h);
      const State here = p.at(t);
      const double scale = 1.0 + std::abs(here.position) + std::abs(here.velocity) + std::abs(here.acceleration) +
                           std::abs(here.jerk);
      EXPECT_NEAR(here.velocity, (plus.position - minus.position) / (2 * h), 1e-5 * scale) << "order " << order;
      EXPECT_NEAR(here.acceleration, (plus.velocity - minus.velocity) / (2 * h), 1e-5 * scale) << "order " << order;
      EXPECT_NEAR(here.jerk, (plus.acceleration - minus.acceleration) / (2 * h), 1e-4 * scale) << "order " << order;
    }
  }
}

TEST(Polynomial, CoefficientsFollowTheThesisEquationInPhysicalTime) {
  // Order 1: a0 = q0, a1 = (q1 - q0) / T. Order 2: a2 = (q1 - q0 - v0 T) / T^2 (eq. 3.6 solved by hand).
  const auto linear = Polynomial(1, Conditions(1.0, 4.0), 2.0).coefficients();
  EXPECT_DOUBLE_EQ(linear[0], 1.0);
  EXPECT_DOUBLE_EQ(linear[1], 1.5);
  EXPECT_EQ(linear[2], 0.0);
  const auto parabola = Polynomial(2, Conditions(State{1.0, 0.5}, State{4.0}), 2.0).coefficients();
  EXPECT_DOUBLE_EQ(parabola[0], 1.0);
  EXPECT_DOUBLE_EQ(parabola[1], 0.5);
  EXPECT_DOUBLE_EQ(parabola[2], (4.0 - 1.0 - 0.5 * 2.0) / 4.0);
  // Rest-to-rest quintic: q0 + h (10 s^3 - 15 s^4 + 6 s^5), the textbook minimum-jerk profile.
  const Polynomial quintic(5, Conditions(0.0, 2.0), 4.0);
  for (double s : {0.1, 0.37, 0.5, 0.81}) {
    const double expected = 2.0 * (10 * std::pow(s, 3) - 15 * std::pow(s, 4) + 6 * std::pow(s, 5));
    EXPECT_NEAR(quintic.at(4.0 * s).position, expected, 1e-12);
  }
  // Evaluating the physical coefficients directly gives what evaluate() gives.
  const Polynomial septic(7, Conditions(State{0.3, -1, 2, 5}, State{-1, 0.5, 0.1, -3}), 1.7);
  const auto a = septic.coefficients();
  double q = 0.0;
  for (int i = 7; i >= 0; --i) q = q * 0.9 + a[i];
  EXPECT_NEAR(q, septic.at(0.9).position, 1e-12);
}

TEST(Polynomial, MatchesKdlSplineProfiles) {
  // KDL::VelocityProfile_Spline is an independent implementation of the linear, cubic and quintic cases.
  std::mt19937 rng(99);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int i = 0; i < 200; ++i) {
    const State q0 = randomState(rng);
    const State q1 = randomState(rng);
    const double T = 0.1 + 4.0 * unit(rng);
    KDL::VelocityProfile_Spline linear, cubic, quintic;
    linear.SetProfileDuration(q0.position, q1.position, T);
    cubic.SetProfileDuration(q0.position, q0.velocity, q1.position, q1.velocity, T);
    quintic.SetProfileDuration(q0.position, q0.velocity, q0.acceleration, q1.position, q1.velocity, q1.acceleration, T);
    const Polynomial ours1(1, Conditions(q0, q1), T), ours3(3, Conditions(q0, q1), T), ours5(5, Conditions(q0, q1), T);
    for (int j = 0; j <= 10; ++j) {
      const double t = T * j / 10.0;
      for (const auto& [kdl, ours] : {std::pair<const KDL::VelocityProfile_Spline*, const Polynomial*>{&linear, &ours1},
                                      {&cubic, &ours3},
                                      {&quintic, &ours5}}) {
        const State s = ours->at(t);
        const double tol = 1e-9 * (1.0 + 1.0 / (T * T * T));
        ASSERT_NEAR(s.position, kdl->Pos(t), tol) << "order " << ours->order() << " t " << t;
        ASSERT_NEAR(s.velocity, kdl->Vel(t), tol) << "order " << ours->order() << " t " << t;
        ASSERT_NEAR(s.acceleration, kdl->Acc(t), tol) << "order " << ours->order() << " t " << t;
      }
    }
  }
}

TEST(Polynomial, StopReachesRestAtTheStopTimeFromAnyState) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int i = 0; i < 300; ++i) {
    const State current = randomState(rng);
    const double stop_time = 0.05 + 2.0 * unit(rng);
    const Polynomial stop = Polynomial::stop(current, stop_time);
    const State start = stop.at(0.0);
    const State end = stop.at(stop_time);
    ASSERT_NEAR(start.position, current.position, 1e-12);
    ASSERT_NEAR(start.velocity, current.velocity, 1e-9);
    ASSERT_NEAR(start.acceleration, current.acceleration, 1e-8);
    ASSERT_NEAR(end.velocity, 0.0, 1e-9);
    ASSERT_NEAR(end.acceleration, 0.0, 1e-8);
    // The rest position is the integral of the cubic Hermite velocity.
    ASSERT_NEAR(end.position,
                current.position + stop_time * (current.velocity / 2 + current.acceleration * stop_time / 12), 1e-9);
    // The velocity decays without overshooting past zero when starting with no acceleration.
    if (current.acceleration == 0.0) {
      ASSERT_GE(stop.at(stop_time * 0.9).velocity * current.velocity, 0.0);
    }
  }
}

TEST(Polynomial, InvalidInputThrowsWithAMessageNamingIt) {
  EXPECT_CONTAINS(messageOf([] { Polynomial(0, Conditions(0, 1), 1.0); }),
                  "Polynomial: order 0 is out of range, expected 1 to 7");
  EXPECT_CONTAINS(messageOf([] { Polynomial(8, Conditions(0, 1), 1.0); }), "order 8 is out of range");
  EXPECT_CONTAINS(messageOf([] { Polynomial(5, Conditions(0, 1), 0.0); }),
                  "Polynomial: duration is 0 s, expected a finite value > 0");
  EXPECT_CONTAINS(messageOf([] { Polynomial(5, Conditions(0, 1), -2.0); }), "duration is -2 s");
  EXPECT_CONTAINS(messageOf([] { Polynomial(5, Conditions(0, 1), std::numeric_limits<double>::infinity()); }),
                  "duration is inf s");
  EXPECT_CONTAINS(messageOf([] { Polynomial(5, Conditions(0, 1), std::nan("")); }), "duration is nan s");
  EXPECT_CONTAINS(messageOf([] { Conditions(std::nan(""), 1.0); }),
                  "Conditions: initial position is nan, expected a finite number");
  EXPECT_CONTAINS(messageOf([] { Conditions(State{0}, State{1, 0, std::numeric_limits<double>::infinity()}); }),
                  "Conditions: final acceleration is inf");
  EXPECT_CONTAINS(messageOf([] { Polynomial::stop(State{0, 1}, 0.0); }),
                  "Polynomial::stop: stop time is 0 s, expected a finite value > 0");
  EXPECT_CONTAINS(messageOf([] { Polynomial::stop(State{0, std::nan("")}, 1.0); }), "initial velocity is nan");
}

}  // namespace
