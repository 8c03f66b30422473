// HapticMaster: the hand settles on its target with the mass-spring-damper's static balance,
// force saturation at 3.3 N, a rendered wall against the hand, workspace clamping, the encoder's
// 0.055 mm resolution, no allocation, parameter errors.

#include "cobra/sim/haptic.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "cobra/test_support/counting_new.hpp"
#include "cobra/test_support/test_support.hpp"

namespace {

using cobra::sim::HapticMaster;
using cobra::sim::HapticMasterModel;

TEST(HapticMaster, HandSettlesOnTheTargetWithinTheFrictionBand) {
  HapticMaster master(HapticMasterModel{});
  master.setHandTarget(KDL::Vector(0.03, -0.02, 0.01));
  for (int i = 0; i < 3000; ++i) master.step(1e-3);
  // Static balance: the hand spring can hold at most the backdrive friction, 0.26 N / 400 N/m.
  EXPECT_LE((master.position() - KDL::Vector(0.03, -0.02, 0.01)).Norm(), 0.26 / 400.0 + 1e-9);
  EXPECT_LT(master.velocity().Norm(), 1e-3);
}

TEST(HapticMaster, ReportsThePowerItsBackdriveFrictionDissipates) {
  HapticMaster master(HapticMasterModel{});
  EXPECT_EQ(master.dissipatedPower(), 0.0);
  double energy = 0.0, largest = 0.0;  // J, W
  for (int i = 0; i < 2000; ++i) {
    // The hand sweeps along x and back at up to 0.1 m/s: far above the friction band (1 mm/s).
    master.setHandTarget(KDL::Vector(0.03 * std::sin(i * 1e-3 * 3.0), 0.0, 0.0));
    master.step(1e-3);
    EXPECT_GE(master.dissipatedPower(), 0.0);
    // Coulomb friction f = 0.26 N tanh(v / 1 mm/s) against v: at most 0.26 N · |v|.
    EXPECT_LE(master.dissipatedPower(), 0.26 * master.velocity().Norm() + 1e-12);
    energy += master.dissipatedPower() * 1e-3;
    largest = std::max(largest, master.dissipatedPower());
  }
  EXPECT_GT(largest, 0.26 * 0.05);  // the sweep reaches more than 5 cm/s
  EXPECT_GT(energy, 0.26 * 0.05);   // more than 5 cm of travel against 0.26 N
}

TEST(HapticMaster, RenderedForceSaturatesAtTheOmnisMaximum) {
  HapticMaster master(HapticMasterModel{});
  master.setCommandedForce(KDL::Vector(3.0, 4.0, 0.0));
  const auto flags = master.step(1e-3);
  EXPECT_TRUE(flags & cobra::sim::kForceSaturated);
  EXPECT_TRUE(flags & cobra::sim::kOverContinuous);
  EXPECT_NEAR(master.renderedForce().Norm(), 3.3, 1e-12);
  EXPECT_NEAR(master.renderedForce().x() / master.renderedForce().y(), 0.75, 1e-12);
  master.setCommandedForce(KDL::Vector(0.5, 0.0, 0.0));
  EXPECT_EQ(master.step(1e-3) & (cobra::sim::kForceSaturated | cobra::sim::kOverContinuous), 0U);
}

TEST(HapticMaster, WallRenderedAtTheDeviceStiffnessBalancesTheHand) {
  const HapticMasterModel model;
  HapticMaster master(model);
  const double k_wall = master.renderableStiffness(KDL::Vector(5000, 5000, 5000)).x();
  EXPECT_DOUBLE_EQ(k_wall, 1260.0);
  master.setHandTarget(KDL::Vector(0.004, 0, 0));  // 4 mm into a wall at x = 0
  for (int i = 0; i < 5000; ++i) {
    const double x = master.position().x();
    master.setCommandedForce(KDL::Vector(x > 0 ? -k_wall * x : 0.0, 0, 0));
    master.step(1e-3);
  }
  // 400·(0.004 - x) = 1260·x within the friction band.
  EXPECT_NEAR(master.position().x(), 400.0 * 0.004 / (400.0 + 1260.0), 0.26 / (400.0 + 1260.0));
}

TEST(HapticMaster, StaysInsideTheWorkspaceAndQuantisesTheReading) {
  HapticMaster master(HapticMasterModel{});
  master.setHandTarget(KDL::Vector(0.0, 0.0, 0.2));
  std::uint32_t flags = 0;
  for (int i = 0; i < 2000; ++i) flags |= master.step(1e-3);
  EXPECT_TRUE(flags & cobra::sim::kWorkspaceLimit);
  EXPECT_DOUBLE_EQ(master.position().z(), 0.035);
  master.setHandTarget(KDL::Vector(0.01234, 0.0, 0.0));
  for (int i = 0; i < 3000; ++i) master.step(1e-3);
  const double x = master.position().x();
  EXPECT_NEAR(master.measured().x(), 0.055e-3 * std::round(x / 0.055e-3), 1e-15);
  EXPECT_LE(std::abs(master.measured().x() - x), 0.0275e-3 + 1e-15);
}

TEST(HapticMaster, StepAllocatesNothing) {
  HapticMaster master(HapticMasterModel{});
  EXPECT_EQ(cobra::test_support::allocationsDuring([&] {
              for (int i = 0; i < 1000; ++i) {
                master.setHandTarget(KDL::Vector(0.0001 * i, 0, 0));
                master.step(1e-3);
              }
            }),
            0);
}

TEST(HapticMaster, BadParametersAreNamed) {
  HapticMasterModel m;
  m.max_stiffness = KDL::Vector(1260.0, -1.0, 1020.0);
  EXPECT_CONTAINS(cobra::test_support::messageOf([&] { HapticMaster h(m); }),
                  "haptic master: max_stiffness.y = -1.000000, expected > 0 N/m");
  EXPECT_CONTAINS(cobra::test_support::messageOf([&] { HapticMaster h(HapticMasterModel{}, KDL::Vector(0, 0, 0.05)); }),
                  "outside the workspace");
}

}  // namespace
