// Unit tests of geometry.hpp: the equivalent wrench of thesis eq. 6.1–6.3 against a hand
// computation and the textbook inverse map, the adjoint matrix against KDL's Frame * Wrench, and
// the KDL <-> Eigen conversions (round trips on seeded random values).

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "cobra/kinematics/geometry.hpp"

namespace cobra::kinematics {
namespace {

constexpr double kTight = 1e-12;

KDL::Frame randomFrame(std::mt19937& rng) {
  std::uniform_real_distribution<double> angle(-std::numbers::pi, std::numbers::pi);
  std::uniform_real_distribution<double> length(-1.0, 1.0);
  return KDL::Frame(KDL::Rotation::RPY(angle(rng), angle(rng) / 2.0, angle(rng)),
                    KDL::Vector(length(rng), length(rng), length(rng)));
}

void expectNear(const KDL::Vector& a, const KDL::Vector& b, double tolerance) {
  EXPECT_NEAR(a.x(), b.x(), tolerance);
  EXPECT_NEAR(a.y(), b.y(), tolerance);
  EXPECT_NEAR(a.z(), b.z(), tolerance);
}

TEST(EquivalentWrench, MatchesAHandComputation) {
  // C is B turned by +90° about z and moved by p = (1, 0, 0) m. A force of 10 N along B's y at
  // B's origin: about C's origin it has τ = -p × f = -(1,0,0) × (0,10,0) = (0,0,-10) N·m; in C's
  // axes (x_C = y_B, y_C = -x_B) the force is (10, 0, 0) N and the torque stays (0, 0, -10).
  const KDL::Frame g_bc(KDL::Rotation::RotZ(std::numbers::pi / 2.0), KDL::Vector(1.0, 0.0, 0.0));
  const KDL::Wrench w_b(KDL::Vector(0.0, 10.0, 0.0), KDL::Vector(0.0, 0.0, 0.0));

  const KDL::Wrench both = equivalentWrench(g_bc, w_b);
  expectNear(both.force, KDL::Vector(10.0, 0.0, 0.0), kTight);
  expectNear(both.torque, KDL::Vector(0.0, 0.0, -10.0), kTight);

  const KDL::Wrench point_only = equivalentWrench(g_bc, w_b, {.application_point = true, .reference_frame = false});
  expectNear(point_only.force, KDL::Vector(0.0, 10.0, 0.0), kTight);
  expectNear(point_only.torque, KDL::Vector(0.0, 0.0, -10.0), kTight);

  const KDL::Wrench frame_only = equivalentWrench(g_bc, w_b, {.application_point = false, .reference_frame = true});
  expectNear(frame_only.force, KDL::Vector(10.0, 0.0, 0.0), kTight);
  expectNear(frame_only.torque, KDL::Vector(0.0, 0.0, 0.0), kTight);

  const KDL::Wrench unchanged = equivalentWrench(g_bc, w_b, {.application_point = false, .reference_frame = false});
  expectNear(unchanged.force, w_b.force, 0.0);
  expectNear(unchanged.torque, w_b.torque, 0.0);
}

// 1000 seeded random frames and wrenches: mapping F_c back with the textbook adjoint of g_bc,
// f_b = R f_c, τ_b = R τ_c + p × (R f_c), gives F_b again; the Eigen matrix of eq. 6.2 gives the
// same numbers as equivalentWrench; KDL's g_bc.Inverse() * F_b agrees too.
TEST(EquivalentWrench, InvertsTheTextbookAdjointOnRandomFrames) {
  std::mt19937 rng(20240611);
  std::uniform_real_distribution<double> value(-50.0, 50.0);
  for (int i = 0; i < 1000; ++i) {
    const KDL::Frame g_bc = randomFrame(rng);
    const KDL::Wrench w_b(KDL::Vector(value(rng), value(rng), value(rng)),
                          KDL::Vector(value(rng), value(rng), value(rng)));
    const KDL::Wrench w_c = equivalentWrench(g_bc, w_b);

    const KDL::Vector f_b = g_bc.M * w_c.force;
    const KDL::Vector tau_b = g_bc.M * w_c.torque + g_bc.p * f_b;
    expectNear(f_b, w_b.force, 1e-10);
    expectNear(tau_b, w_b.torque, 1e-10);

    const Vector6d by_matrix = wrenchAdjointTranspose(g_bc) * toEigen(w_b);
    EXPECT_LT((by_matrix - toEigen(w_c)).norm(), 1e-10);
    EXPECT_LT((toEigen(g_bc.Inverse() * w_b) - toEigen(w_c)).norm(), 1e-10);
  }
}

TEST(Skew, IsTheCrossProductMatrixOfEquation63) {
  const Eigen::Vector3d p(1.0, -2.0, 3.0);
  const Eigen::Vector3d v(0.5, 4.0, -1.0);
  EXPECT_LT((skew(p) * v - p.cross(v)).norm(), kTight);
  EXPECT_LT((skew(p) + skew(p).transpose()).norm(), kTight);
  EXPECT_DOUBLE_EQ(skew(p)(0, 1), -3.0);
  EXPECT_DOUBLE_EQ(skew(p)(0, 2), -2.0);
  EXPECT_DOUBLE_EQ(skew(p)(1, 2), -1.0);
}

TEST(Conversions, RoundTripKdlEigenKdl) {
  std::mt19937 rng(7);
  for (int i = 0; i < 200; ++i) {
    const KDL::Frame f = randomFrame(rng);
    const Eigen::Isometry3d iso = toEigen(f);
    // Same point transformed by both representations.
    const KDL::Vector x(0.3, -0.2, 0.9);
    EXPECT_LT((toEigen(f * x) - iso * toEigen(x)).norm(), kTight);
    const KDL::Frame back = toKdl(iso);
    EXPECT_EQ(norm(back.p - f.p), 0.0);
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) EXPECT_EQ(back.M(r, c), f.M(r, c));
    EXPECT_LT(orientationError(toKdl(toEigenQuaternion(f.M)), f.M), 1e-14);
    const KDL::Twist t(KDL::Vector(1, 2, 3), KDL::Vector(4, 5, 6));
    EXPECT_EQ(toKdlTwist(toEigen(t)), t);
    EXPECT_DOUBLE_EQ(toEigen(t)(3), 4.0);
    const KDL::Wrench w(KDL::Vector(-1, -2, -3), KDL::Vector(-4, -5, -6));
    EXPECT_EQ(toKdlWrench(toEigen(w)), w);
    EXPECT_DOUBLE_EQ(toEigen(w)(5), -6.0);
  }
}

TEST(RotationVector, IsAxisTimesAngle) {
  for (const double angle : {1e-12, 1e-6, 0.3, 2.5}) {
    const KDL::Vector axis = KDL::Vector(1, -2, 0.5) / norm(KDL::Vector(1, -2, 0.5));
    const KDL::Vector v = rotationVector(KDL::Rotation::Rot(axis, angle));
    EXPECT_LT(norm(v - axis * angle), 1e-15 + 1e-12 * angle);
  }
}

TEST(OrientationError, IsTheResidualAngleEvenBelowKdlsEpsilon) {
  const KDL::Rotation a = KDL::Rotation::RPY(0.3, -0.2, 1.1);
  for (const double angle : {1e-10, 1e-7, 0.5, 3.0}) {
    const KDL::Rotation b = a * KDL::Rotation::Rot(KDL::Vector(1, 2, 3), angle);
    EXPECT_NEAR(orientationError(a, b), angle, 1e-15 + angle * 1e-9);
  }
  EXPECT_NEAR(orientationError(a, a), 0.0, 1e-15);
}

}  // namespace
}  // namespace cobra::kinematics
