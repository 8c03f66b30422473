// FTSensDriver on the lockstep clock, on the simulated FTSens of a SimulatedFTSens component found
// through its `bus` property: the sensor's wrench through the CAN codec to measWrench one step
// later, tare, garbled frames counted, timeout and restore events, the same measurements whatever
// the order of the two components on the clock, no allocation, and the messages of bad properties.

#include "cobra/components/drivers/ftsens_driver.hpp"

#include <gtest/gtest.h>

#include "cobra/components/sim/simulated_ftsens.hpp"
#include "cobra/core/lockstep_clock.hpp"
#include "cobra/test_support/counting_new.hpp"
#include "cobra/test_support/test_support.hpp"

namespace cobra::components {
namespace {

using namespace std::chrono_literals;

struct Bench {
  SimulatedFTSens sensor;
  FTSensDriver driver{"FTSens"};
  core::LockstepClock clock;
  core::InputPort<core::Event> events{"events", "", ""};
  core::OutputPort<KDL::Wrench> truth{"truth", "", "N, N·m"};
  core::InputPort<KDL::Wrench> measured{"measured", "", "N, N·m"};

  explicit Bench(const KDL::Wrench& bias = KDL::Wrench::Zero(), bool driver_first = false,
                 const std::string& sensor_name = "FTSensSim")
      : sensor(sensor_name) {
    sensor.setProperty("bias", bias);
    sensor.setProperty("seed", 4);
    driver.setProperty("bus", "sim:" + sensor_name);
    if (driver_first) clock.add(driver, 1ms);
    clock.add(sensor, 1ms);
    if (!driver_first) clock.add(driver, 1ms);
    core::connectPorts(driver.port("events"), events, core::ConnPolicy::buffer(64));
    core::connectPorts(truth, sensor.port("trueWrench"));
    core::connectPorts(driver.port("measWrench"), measured);
    EXPECT_TRUE(sensor.configure());  // registers sim:<name>: before the driver looks it up
    EXPECT_TRUE(driver.configure());
    EXPECT_TRUE(sensor.start());
    EXPECT_TRUE(driver.start());
  }
  std::vector<std::string> takeEvents() {
    std::vector<std::string> names;
    core::Event e;
    while (events.read(e) == core::FlowStatus::NewData) names.push_back(e.name.str());
    return names;
  }
  KDL::Wrench read() {
    KDL::Wrench w;
    EXPECT_NE(measured.read(w), core::FlowStatus::NoData);
    return w;
  }
};

KDL::Wrench wrench(double fz, double tx) { return {KDL::Vector(0, 0, fz), KDL::Vector(tx, 0, 0)}; }

// One FTSens sample's torque is within 5 standard deviations of its noise (0.049 N·m, sim::ftSens)
// plus half a resolution step (0.049 N·m) of the truth: a bound a correct sensor model keeps
// whatever its seed (2 sigma, the bound before, fails for one sample in 20).
constexpr double kTorqueTolerance = 5 * 0.049 + 0.049 / 2;  // N·m

TEST(FTSensDriver, PublishesTheSensorsWrenchAndTares) {
  Bench b(wrench(8.0, 0.3));  // the sensor's own offset
  b.truth.write(wrench(50.0, 1.0));
  b.clock.advance(20ms);
  KDL::Wrench w = b.read();
  EXPECT_NEAR(w.force.z(), 58.0, 1.0);  // truth + bias, within the FTSens noise and resolution
  EXPECT_NEAR(w.torque.x(), 1.3, kTorqueTolerance);
  b.truth.write(wrench(0.0, 0.0));
  b.clock.advance(5ms);
  b.driver.call("tare");
  b.clock.advance(98ms);  // tare_samples: 100 samples at 1 ms, not all in yet
  EXPECT_TRUE(b.takeEvents().empty());
  b.clock.advance(4ms);
  EXPECT_EQ(b.takeEvents(), (std::vector<std::string>{"e_tared"}));
  b.truth.write(wrench(-20.0, 0.5));
  b.clock.advance(5ms);
  w = b.read();
  EXPECT_NEAR(w.force.z(), -20.0, 1.0);
  EXPECT_NEAR(w.torque.x(), 0.5, kTorqueTolerance);
  b.driver.call("clearTare");
  b.clock.advance(2ms);
  EXPECT_NEAR(b.read().force.z(), -12.0, 1.0);
  // 134 instants (0-133 ms): the sensor takes the stream command at 1 ms (sent at start, seen one
  // step later), samples at 1-133 ms, and the driver has seen those of 1-132 ms.
  EXPECT_CONTAINS(b.driver.call<std::string>("statistics"), "samples 132, lost 0, garbled 0, unpaired 0, timeouts 0");
}

// A tare averages tare_samples samples: the zero it leaves is finer than the sensor's noise and
// 0.25 N resolution, which a one-sample tare would carry into every later measurement.
TEST(FTSensDriver, AnAveragedTareLeavesAZeroFinerThanOneSample) {
  Bench b(wrench(8.0, 0.3));
  b.truth.write(wrench(0.0, 0.0));
  b.clock.advance(5ms);
  b.driver.call("tare");
  b.clock.advance(110ms);
  ASSERT_EQ(b.takeEvents(), (std::vector<std::string>{"e_tared"}));
  double sum = 0.0;
  constexpr int kSamples = 1000;
  for (int i = 0; i < kSamples; ++i) {
    b.clock.advance(1ms);
    sum += b.read().force.z();
  }
  EXPECT_LT(std::abs(sum / kSamples), 0.25 / 4);  // N: a quarter of the resolution
}

TEST(FTSensDriver, CountsGarbledFramesAndReportsTimeoutAndRestore) {
  Bench b;
  b.truth.write(wrench(10.0, 0.0));
  b.clock.advance(5ms);
  b.sensor.call("garbleFrames", 3);
  b.clock.advance(5ms);
  EXPECT_CONTAINS(b.driver.call<std::string>("statistics"), "garbled 3");
  b.sensor.call("setSilent", true);
  b.clock.advance(10ms);
  EXPECT_TRUE(b.takeEvents().empty());  // 10 ms without a sample is still within the timeout
  b.clock.advance(2ms);
  EXPECT_EQ(b.takeEvents(), (std::vector<std::string>{"e_comm_timeout"}));
  b.clock.advance(50ms);
  EXPECT_TRUE(b.takeEvents().empty());  // once
  b.sensor.call("setSilent", false);
  b.clock.advance(2ms);
  EXPECT_EQ(b.takeEvents(), (std::vector<std::string>{"e_comm_restored"}));
  EXPECT_CONTAINS(b.driver.call<std::string>("statistics"), "timeouts 1");
  EXPECT_EQ(cobra::test_support::allocationsDuring([&] {
              for (int i = 0; i < 100; ++i) {
                b.truth.write(wrench(i * 0.1, 0.0));
                b.clock.advance(1ms);
              }
            }),
            0);
}

TEST(FTSensDriver, TheOrderOfSensorAndDriverOnTheClockDoesNotChangeTheMeasurements) {
  Bench sensor_first(wrench(1.0, 0.0), false, "FTSensSimA");
  Bench driver_first(wrench(1.0, 0.0), true, "FTSensSimB");  // another name: one registry per process
  for (int ms = 0; ms < 200; ++ms) {
    const KDL::Wrench truth = wrench(30.0 * std::sin(ms * 0.05), 0.2 * ms * 1e-2);
    sensor_first.truth.write(truth);
    driver_first.truth.write(truth);
    sensor_first.clock.advance(1ms);
    driver_first.clock.advance(1ms);
    if (ms > 2) {
      const KDL::Wrench a = sensor_first.read(), b = driver_first.read();
      for (int axis = 0; axis < 6; ++axis) ASSERT_EQ(a(axis), b(axis)) << "at " << ms << " ms, axis " << axis;
    }
  }
  EXPECT_EQ(sensor_first.driver.call<std::string>("statistics"),
            driver_first.driver.call<std::string>("statistics"));
}

TEST(FTSensDriver, BadPropertiesAreRefusedWithTheirName) {
  SimulatedFTSens sensor("FTSensSim");
  FTSensDriver d("FTSens");
  core::LockstepClock clock;
  clock.add(sensor, 1ms);
  clock.add(d, 1ms);
  ASSERT_TRUE(sensor.configure());
  d.setProperty("address", 16);
  EXPECT_CONTAINS(d.configure().message, "component 'FTSens': FTSens codec: address = 16, expected 0-15");
  d.setProperty("address", 3);
  d.setProperty("stream_period", 0.0015);
  EXPECT_CONTAINS(d.configure().message,
                  "property stream_period = 0.001500 s; expected whole milliseconds from 0.001 to 0.255 s");
  d.setProperty("stream_period", 0.002);
  d.setProperty("timeout", 0.0);
  EXPECT_CONTAINS(d.configure().message, "property timeout = 0.000000 s; expected > 0 s");
  d.setProperty("timeout", 0.01);
  EXPECT_CONTAINS(d.configure().message,
                  "property bus = '': '' is not a CAN bus backend name: expected <scheme>:<address>; backends that "
                  "exist: 'sim:FTSensSim' (simulated FTSens of component 'FTSensSim')");
  d.setProperty("bus", "sim:FTSensSin");
  EXPECT_CONTAINS(d.configure().message,
                  "property bus = 'sim:FTSensSin': no CAN bus backend 'sim:FTSensSin'; backends that exist: "
                  "'sim:FTSensSim' (simulated FTSens of component 'FTSensSim')");
  d.setProperty("bus", "sim:FTSensSim");
  EXPECT_TRUE(d.configure());
  ASSERT_TRUE(sensor.cleanup());  // the sensor's bus is gone from the registry
  EXPECT_CONTAINS(d.configure().message, "no CAN bus backend 'sim:FTSensSim'");
}

}  // namespace
}  // namespace cobra::components
