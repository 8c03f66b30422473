// Ultrasound probe: contact force from indentation, needle visibility following the needle's
// distance to the imaging plane, tumour visibility when the plane cuts it, coupling threshold.

#include "cobra/sim/ultrasound.hpp"

#include <gtest/gtest.h>

#include <numbers>

#include "cobra/test_support/test_support.hpp"

namespace {

using cobra::sim::UltrasoundProbeModel;

/// Probe pressing `indentation` (m) into the skin at y = `y`, beam down, imaging plane y = const.
KDL::Frame probeAt(double y, double indentation) {
  return {KDL::Rotation::RotX(std::numbers::pi), KDL::Vector(0.0, y, -indentation)};
}

KDL::Frame needleAt(double y) { return {KDL::Rotation::RotX(std::numbers::pi), KDL::Vector(0.0, y, -0.04)}; }

TEST(Ultrasound, ContactForceIsThePenaltyStiffnessTimesTheIndentation) {
  const UltrasoundProbeModel m;
  const auto phantom = cobra::sim::defaultAbdomen();
  EXPECT_DOUBLE_EQ(cobra::sim::observe(m, phantom, probeAt(0, 0.003), needleAt(0)).contact_force.z(), 6.0);
  EXPECT_DOUBLE_EQ(cobra::sim::observe(m, phantom, probeAt(0, -0.001), needleAt(0)).contact_force.z(), 0.0);
}

TEST(Ultrasound, NeedleVisibilityFollowsItsDistanceToThePlane) {
  const UltrasoundProbeModel m;
  const auto phantom = cobra::sim::defaultAbdomen();
  for (int k = 0; k <= 16; ++k) {
    const double offset = k * 0.0003;  // m; steps straddle the 2 mm tolerance without landing on it
    const auto view = cobra::sim::observe(m, phantom, probeAt(0.0, 0.002), needleAt(offset));
    EXPECT_NEAR(view.needle_distance, offset, 1e-12);
    EXPECT_EQ(view.needle_visible, offset <= m.plane_tolerance) << "offset " << offset;
  }
  // A needle crossing the plane at an angle: the tip is in it, the shaft behind it is not.
  const KDL::Frame tilted(KDL::Rotation::RotX(std::numbers::pi - 0.3), KDL::Vector(0, 0, -0.04));
  EXPECT_FALSE(cobra::sim::observe(m, phantom, probeAt(0.0, 0.002), tilted).needle_visible);
  // Not pressed hard enough: no image.
  EXPECT_FALSE(cobra::sim::observe(m, phantom, probeAt(0.0, 0.0005), needleAt(0.0)).needle_visible);
}

TEST(Ultrasound, TumourVisibleWhenThePlaneCutsIt) {
  const UltrasoundProbeModel m;
  const auto phantom = cobra::sim::defaultAbdomen();  // tumour radius 10 mm at y = 0
  EXPECT_TRUE(cobra::sim::observe(m, phantom, probeAt(0.009, 0.002), needleAt(0)).tumour_visible);
  EXPECT_FALSE(cobra::sim::observe(m, phantom, probeAt(0.011, 0.002), needleAt(0)).tumour_visible);
  EXPECT_FALSE(cobra::sim::observe(m, phantom, probeAt(0.0, 0.0), needleAt(0)).tumour_visible);
}

TEST(Ultrasound, BadParametersAreNamed) {
  UltrasoundProbeModel m;
  m.plane_tolerance = 0.0;
  EXPECT_CONTAINS(cobra::test_support::messageOf([&] { cobra::sim::validate(m); }),
                  "ultrasound probe: plane_tolerance = 0.000000, expected > 0 m");
}

}  // namespace
