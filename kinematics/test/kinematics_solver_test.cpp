// Unit tests of kinematics_solver.hpp's input checks: validFrame and validJointArray decide as
// a plain reading of their contracts does (the straightforward loops below, an independent
// implementation), on seeded random poses and their corruptions: near and beyond the
// orthonormality tolerance, reflections, NaN and infinity in each element.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "cobra/kinematics/kinematics_solver.hpp"

namespace cobra::kinematics {
namespace {

/// The contract read literally: finite translation and rotation, RᵀR = I within 1e-6 per
/// element, det(R) > 0.
bool referenceValidFrame(const KDL::Frame& frame) {
  for (int i = 0; i < 3; ++i) {
    if (!std::isfinite(frame.p(i))) return false;
    for (int j = 0; j < 3; ++j)
      if (!std::isfinite(frame.M(i, j))) return false;
  }
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      double dot = 0.0;
      for (int k = 0; k < 3; ++k) dot += frame.M(k, i) * frame.M(k, j);
      if (std::abs(dot - (i == j ? 1.0 : 0.0)) > 1e-6) return false;
    }
  }
  return KDL::dot(frame.M.UnitX() * frame.M.UnitY(), frame.M.UnitZ()) > 0.0;
}

KDL::Frame randomPose(std::mt19937& rng) {
  std::uniform_real_distribution<double> angle(-3.2, 3.2), metre(-2.0, 2.0);
  return KDL::Frame(KDL::Rotation::RPY(angle(rng), angle(rng), angle(rng)),
                    KDL::Vector(metre(rng), metre(rng), metre(rng)));
}

TEST(ValidFrame, DecidesAsTheContractOnRandomPosesAndTheirCorruptions) {
  // 2,000 seeded poses, each also with one element of R or p changed by a random amount around
  // the tolerance, set to NaN or ±infinity, and with one column negated (a reflection).
  std::mt19937 rng(20261125);
  std::uniform_int_distribution<int> element(0, 11), column(0, 2);
  std::uniform_real_distribution<double> exponent(-9.0, -3.0);
  constexpr double kInf = std::numeric_limits<double>::infinity();
  int accepted = 0, refused = 0;
  for (int n = 0; n < 2000; ++n) {
    const KDL::Frame pose = randomPose(rng);
    ASSERT_TRUE(validFrame(pose)) << "pose " << n;
    for (const double change : {std::pow(10.0, exponent(rng)), -std::pow(10.0, exponent(rng)),
                                std::numeric_limits<double>::quiet_NaN(), kInf, -kInf}) {
      KDL::Frame corrupted = pose;
      const int e = element(rng);
      double& value = e < 9 ? corrupted.M.data[e] : corrupted.p.data[e - 9];
      value = std::isfinite(change) ? value + change : change;
      const bool expected = referenceValidFrame(corrupted);
      EXPECT_EQ(validFrame(corrupted), expected) << "pose " << n << " element " << e << " changed by " << change;
      (expected ? accepted : refused) += 1;
    }
    KDL::Frame reflected = pose;
    const int c = column(rng);
    for (int row = 0; row < 3; ++row) reflected.M.data[3 * row + c] = -reflected.M.data[3 * row + c];
    EXPECT_FALSE(validFrame(reflected)) << "pose " << n << " column " << c << " negated";
  }
  // Both outcomes occur among the perturbed poses: the cross-check is not one-sided.
  EXPECT_GT(accepted, 1000);
  EXPECT_GT(refused, 1000);
}

TEST(ValidJointArray, NeedsTheCountAndFiniteValues) {
  KDL::JntArray q(6);
  for (unsigned i = 0; i < 6; ++i) q(i) = 0.1 * i;
  EXPECT_TRUE(validJointArray(q, 6));
  EXPECT_FALSE(validJointArray(q, 5));
  EXPECT_FALSE(validJointArray(q, 7));
  for (unsigned i = 0; i < 6; ++i) {
    for (const double bad : {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity(),
                             -std::numeric_limits<double>::infinity()}) {
      KDL::JntArray corrupted = q;
      corrupted(i) = bad;
      EXPECT_FALSE(validJointArray(corrupted, 6)) << "joint " << i + 1 << " = " << bad;
    }
  }
  EXPECT_TRUE(validJointArray(KDL::JntArray(0), 0));
}

}  // namespace
}  // namespace cobra::kinematics
