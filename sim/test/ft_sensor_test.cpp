// ForceTorqueSensor: presets from the thesis tables, saturation, quantisation, noise statistics,
// bias, filter step response, determinism for a seed, no allocation in step, parameter errors.

#include "cobra/sim/ft_sensor.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "cobra/test_support/counting_new.hpp"
#include "cobra/test_support/test_support.hpp"

namespace {

using cobra::sim::ForceTorqueSensor;
using cobra::sim::ForceTorqueSensorModel;
using cobra::test_support::messageOf;

KDL::Wrench wrench(double fx, double fy, double fz, double tx, double ty, double tz) {
  return {KDL::Vector(fx, fy, fz), KDL::Vector(tx, ty, tz)};
}

TEST(ForceTorqueSensor, PresetsCarryTheThesisTables) {
  EXPECT_DOUBLE_EQ(cobra::sim::atiNano17().saturation[2], 480.0);
  EXPECT_DOUBLE_EQ(cobra::sim::atiNano17().saturation[5], 1.8);
  EXPECT_DOUBLE_EQ(cobra::sim::atiNano43().saturation[0], 300.0);
  EXPECT_DOUBLE_EQ(cobra::sim::atiNano43().saturation[5], 4.6);
  const ForceTorqueSensorModel ft = cobra::sim::ftSens();
  EXPECT_DOUBLE_EQ(ft.saturation[0], 2000.0);
  EXPECT_DOUBLE_EQ(ft.saturation[3], 40.0);
  EXPECT_DOUBLE_EQ(ft.resolution[5], 0.037);
  EXPECT_DOUBLE_EQ(ft.max_rate_hz, 1000.0);
}

TEST(ForceTorqueSensor, SaturatesAndFlagsOnlyTheAxesBeyondTheirLimit) {
  ForceTorqueSensor sensor(cobra::sim::atiNano17(), 1);
  const auto& r = sensor.step(1e-3, wrench(300.0, -10.0, -500.0, 0.1, -2.0, 0.0));
  EXPECT_EQ(r.saturated, 0b010101);
  EXPECT_NEAR(r.wrench.force.x(), 250.0, 0.01);
  EXPECT_NEAR(r.wrench.force.z(), -480.0, 0.01);
  EXPECT_NEAR(r.wrench.torque.y(), -1.6, 1e-3);
  EXPECT_NEAR(r.wrench.force.y(), -10.0, 0.05);
}

TEST(ForceTorqueSensor, QuantisesToTheResolutionWithoutNoise) {
  ForceTorqueSensorModel m = cobra::sim::ftSens();
  m.noise_std = {};
  ForceTorqueSensor sensor(m, 1);
  const auto& r = sensor.step(1e-3, wrench(1.13, -0.13, 0.0, 0.1, 0.0, 0.02));
  EXPECT_DOUBLE_EQ(r.wrench.force.x(), 1.25);
  EXPECT_DOUBLE_EQ(r.wrench.force.y(), -0.25);
  EXPECT_DOUBLE_EQ(r.wrench.torque.x(), 2 * 0.049);
  EXPECT_DOUBLE_EQ(r.wrench.torque.z(), 0.037);
  EXPECT_FALSE(r.anySaturated());
}

TEST(ForceTorqueSensor, NoiseHasTheConfiguredStandardDeviationAndBiasShiftsTheMean) {
  ForceTorqueSensorModel m = cobra::sim::ftSens();
  m.resolution = {};
  m.noise_std = {0.5, 0.5, 0.5, 0.01, 0.01, 0.01};
  m.bias = wrench(2.0, 0, 0, 0, 0, 0);
  ForceTorqueSensor sensor(m, 42);
  constexpr int kSamples = 20000;
  double sum = 0, sum_sq = 0;
  for (int i = 0; i < kSamples; ++i) {
    const double v = sensor.step(1e-3, wrench(3.0, 0, 0, 0, 0, 0)).wrench.force.x();
    sum += v;
    sum_sq += v * v;
  }
  const double mean = sum / kSamples;
  const double std_dev = std::sqrt(sum_sq / kSamples - mean * mean);
  EXPECT_NEAR(mean, 5.0, 0.02);
  EXPECT_NEAR(std_dev, 0.5, 0.02);
}

TEST(ForceTorqueSensor, FilterFollowsTheFirstOrderStepResponse) {
  ForceTorqueSensorModel m = cobra::sim::ftSens();
  m.resolution = {};
  m.noise_std = {};
  m.filter_cutoff_hz = 10.0;
  ForceTorqueSensor sensor(m, 0);
  sensor.step(1e-3, KDL::Wrench::Zero());
  const double tau = 1.0 / (2 * std::numbers::pi * 10.0);
  double fz = 0;
  for (int i = 1; i <= 50; ++i) fz = sensor.step(1e-3, wrench(0, 0, 10.0, 0, 0, 0)).wrench.force.z();
  EXPECT_NEAR(fz, 10.0 * (1 - std::exp(-0.05 / tau)), 1e-9);
}

TEST(ForceTorqueSensor, IdenticalSeedsGiveIdenticalTracesAndOtherSeedsDiffer) {
  auto trace = [](std::uint64_t seed) {
    ForceTorqueSensor sensor(cobra::sim::atiNano43(), seed);
    std::vector<double> out;
    for (int i = 0; i < 200; ++i) out.push_back(sensor.step(1e-3, wrench(1, 2, 3, 0.01, 0.02, 0.03)).wrench.force.z());
    return out;
  };
  EXPECT_EQ(trace(7), trace(7));
  EXPECT_NE(trace(7), trace(8));
}

TEST(ForceTorqueSensor, StepAllocatesNothing) {
  ForceTorqueSensorModel m = cobra::sim::atiNano17();
  m.filter_cutoff_hz = 100.0;
  ForceTorqueSensor sensor(m, 3);
  EXPECT_EQ(cobra::test_support::allocationsDuring([&] {
              for (int i = 0; i < 1000; ++i) sensor.step(1e-3, wrench(i * 0.5, 0, 0, 0, 0, 0));
            }),
            0);
}

TEST(ForceTorqueSensor, BadParametersAreNamed) {
  ForceTorqueSensorModel m = cobra::sim::atiNano17();
  m.saturation[2] = 0.0;
  EXPECT_CONTAINS(messageOf([&] { ForceTorqueSensor s(m); }), "'AtiNano17': saturation[Fz] = 0.000000, expected a finite value > 0");
  m = cobra::sim::ftSens();
  m.noise_std[4] = -1.0;
  EXPECT_CONTAINS(messageOf([&] { ForceTorqueSensor s(m); }), "noise_std[Ty]");
  m = cobra::sim::ftSens();
  m.filter_cutoff_hz = std::nan("");
  EXPECT_CONTAINS(messageOf([&] { ForceTorqueSensor s(m); }), "filter_cutoff_hz = nan, expected >= 0 Hz");
}

}  // namespace
