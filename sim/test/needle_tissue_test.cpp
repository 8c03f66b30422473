// NeedleTissueModel: skin puncture peak and drop, friction growing with depth, lateral channel
// force, tumour puncture, forbidden-region penalty, iceball trapping until thaw, no allocation.

#include "cobra/sim/needle_tissue.hpp"
#include "cobra/sim/ft_sensor.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "cobra/test_support/counting_new.hpp"
#include "cobra/test_support/test_support.hpp"

namespace {

using cobra::sim::NeedleForces;
using cobra::sim::NeedleTissueModel;

/// Needle pointing straight down (its z-axis = -z of the phantom), tip at (x, y, -depth).
KDL::Frame tipAt(double depth, double x = 0.0, double y = 0.0) {
  return {KDL::Rotation::RotX(std::numbers::pi), KDL::Vector(x, y, -depth)};
}

/// Inserts from 5 mm above the skin to `depth` at `speed` (m/s), 1 kHz; returns the axial trace.
std::vector<NeedleForces> insert(NeedleTissueModel& model, double depth, double speed = 0.01, double x = 0.0) {
  std::vector<NeedleForces> trace;
  constexpr double kDt = 1e-3;
  for (double d = -0.005; d <= depth; d += speed * kDt) trace.push_back(model.step(kDt, tipAt(d, x)));
  return trace;
}

TEST(NeedleTissue, SkinShowsThePunctureForcePeakThenADrop) {
  NeedleTissueModel model(cobra::sim::defaultAbdomen());
  const auto trace = insert(model, 0.004);
  std::size_t puncture = 0;
  while (puncture < trace.size() && !(trace[puncture].flags & cobra::sim::kPunctureEvent)) ++puncture;
  ASSERT_LT(puncture, trace.size());
  const double peak = trace[puncture - 1].axial;
  EXPECT_GT(peak, 1.45);  // just below the skin's 1.5 N puncture force (10 µm per step)
  EXPECT_LT(peak, 1.5);
  for (std::size_t i = 1; i < puncture; ++i) EXPECT_GE(trace[i].axial, trace[i - 1].axial);  // stiffening
  EXPECT_LT(trace[puncture].axial, 0.5 * peak);
  EXPECT_TRUE(trace.back().flags & cobra::sim::kSkinPunctured);
  EXPECT_EQ(trace.front().flags & cobra::sim::kSkinContact, 0U);
}

TEST(NeedleTissue, FrictionGrowsWithInsertedDepth) {
  NeedleTissueModel model(cobra::sim::defaultAbdomen());
  const auto trace = insert(model, 0.016);
  // In the fat layer (2..17 mm) the tip cuts at a constant speed: friction must rise with depth.
  double previous = 0.0;
  int samples = 0;
  for (const auto& f : trace) {
    if (f.layer == 1 && f.membrane == 0.0 && f.inserted_length > 0.006) {
      EXPECT_GT(f.friction, previous);
      previous = f.friction;
      ++samples;
    }
  }
  EXPECT_GT(samples, 500);
  EXPECT_GT(previous, 0.03);
}

TEST(NeedleTissue, SidewaysPushMeetsTheLateralStiffnessOfTheTipLayer) {
  NeedleTissueModel model(cobra::sim::defaultAbdomen());
  insert(model, 0.020);
  const NeedleForces& f = model.step(1e-3, tipAt(0.020, 0.001));
  EXPECT_EQ(f.layer, 2);  // muscle
  EXPECT_NEAR(f.lateral.x(), -600.0 * 0.001, 1e-9);
  EXPECT_NEAR(f.lateral.y(), 0.0, 1e-12);
}

TEST(NeedleTissue, TumourIsPuncturedAndFlagged) {
  NeedleTissueModel model(cobra::sim::defaultAbdomen());
  const auto trace = insert(model, 0.060);
  int punctures = 0;
  for (const auto& f : trace) punctures += (f.flags & cobra::sim::kPunctureEvent) ? 1 : 0;
  EXPECT_EQ(punctures, 5);  // skin, fat, muscle, kidney, tumour
  EXPECT_TRUE(trace.back().flags & cobra::sim::kInTumour);
}

TEST(NeedleTissue, ForbiddenRegionGivesAPenaltyForceAndAFlag) {
  NeedleTissueModel model(cobra::sim::defaultAbdomen());
  insert(model, 0.068, 0.01, 0.02);
  const NeedleForces& f = model.step(1e-3, KDL::Frame(KDL::Rotation::RotX(std::numbers::pi), KDL::Vector(0.02, -0.018, -0.07)));
  EXPECT_TRUE(f.flags & cobra::sim::kForbiddenContact);
  EXPECT_EQ(f.forbidden_region, 1);
  EXPECT_NEAR(f.penalty.y(), 1.0e5 * 0.002, 1e-6);  // pushed out of the 4 mm vessel, 2 mm deep
}

TEST(NeedleTissue, IceballTrapsTheNeedleUntilThawed) {
  NeedleTissueModel model(cobra::sim::defaultAbdomen());
  insert(model, 0.050);
  model.startFreeze();
  for (int i = 0; i < 30000; ++i) model.step(0.01, tipAt(0.050));  // 300 s
  EXPECT_NEAR(model.forces().iceball_radius, 0.015 * (1 - std::exp(-300.0 / 120.0)), 1e-6);
  model.startThaw();
  // Pull back 5 mm while it thaws: the extraction force stays above the threshold while trapped.
  int trapped_steps = 0;
  bool released = false;
  for (int i = 0; i < 30000; ++i) {
    const NeedleForces& f = model.step(0.01, tipAt(0.045));
    if (f.flags & cobra::sim::kTrapped) {
      ASSERT_FALSE(released);
      EXPECT_TRUE(f.flags & cobra::sim::kExtractionOverThreshold);
      EXPECT_GT(f.ice.Norm(), 20.0);
      ++trapped_steps;
    } else {
      released = true;
      EXPECT_LT(f.force.Norm(), 20.0);
    }
  }
  EXPECT_TRUE(released);
  // Thaw law: 0.0138 m shrinks to the 2 mm release radius in τ·ln(r0/0.002) ≈ 116 s.
  const double r0 = 0.015 * (1 - std::exp(-300.0 / 120.0));
  EXPECT_NEAR(trapped_steps * 0.01, 60.0 * std::log(r0 / 0.002), 0.02);
}

TEST(NeedleTissue, IdenticalSeedsGiveIdenticalSensorTracesOfAnInsertion) {
  auto trace = [](std::uint64_t seed) {
    NeedleTissueModel model(cobra::sim::defaultAbdomen());
    cobra::sim::ForceTorqueSensor sensor(cobra::sim::atiNano17(), seed);
    std::vector<double> out;
    for (const NeedleForces& f : insert(model, 0.03)) {
      out.push_back(sensor.step(1e-3, KDL::Wrench(f.force, KDL::Vector::Zero())).wrench.force.z());
    }
    return out;
  };
  const auto first = trace(11);
  EXPECT_EQ(first, trace(11));
  EXPECT_NE(first, trace(12));
}

TEST(NeedleTissue, StepAllocatesNothing) {
  NeedleTissueModel model(cobra::sim::defaultAbdomen());
  model.startFreeze();
  EXPECT_EQ(cobra::test_support::allocationsDuring([&] { insert(model, -0.006); }), 0);  // warm-up: empty trace
  EXPECT_EQ(cobra::test_support::allocationsDuring([&] {
              for (int i = 0; i < 8000; ++i) model.step(1e-3, tipAt(-0.005 + i * 1e-5, 0.0001 * (i % 3)));
            }),
            0);
}

TEST(NeedleTissue, BadNeedleParametersAreNamed) {
  cobra::sim::NeedleModel needle;
  needle.iceball.thaw_time_constant = -1.0;
  EXPECT_CONTAINS(cobra::test_support::messageOf([&] { NeedleTissueModel m(cobra::sim::defaultAbdomen(), needle); }),
                  "needle model: iceball.thaw_time_constant = -1.000000, expected > 0 s");
}

}  // namespace
