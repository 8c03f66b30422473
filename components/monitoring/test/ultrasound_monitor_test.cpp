// UltrasoundMonitor fed by the PatientSimulator's ultrasound model: the needle swept across the
// imaging plane and the probe lifted off the skin, poses written by the test.
#include "cobra/components/monitoring/ultrasound_monitor.hpp"

#include <gtest/gtest.h>

#include "cobra/components/sim/patient_simulator.hpp"
#include "cobra/core/core.hpp"
#include "cobra/test_support/event_names.hpp"
#include "cobra/test_support/test_support.hpp"

namespace cobra::components {
namespace {

using namespace std::chrono_literals;
using Events = std::vector<std::string>;

// Phantom frame = world. Probe: array along y, beam along -z, 20 mm beside the needle's line x = 0.
const KDL::Rotation kProbeAxes(0, 1, 0, 1, 0, 0, 0, 0, -1);

struct Rig {
  PatientSimulator patient{"patient"};
  UltrasoundMonitor monitor{"monitor"};
  core::LockstepClock clock;
  core::OutputPort<KDL::Frame> needle{"needle", "", "m"};
  core::OutputPort<KDL::Frame> probe{"probe", "", "m"};
  core::InputPort<core::Event> events{"events", "", ""};

  Rig() {
    patient.setProperty("tip_to_needle", KDL::Frame::Identity());  // the test's needle frame: z = needle axis
    clock.add(patient, 1ms);
    clock.add(monitor, 1ms);
    core::connectPorts(needle, patient.port("needleTipPose"));
    core::connectPorts(probe, patient.port("probePose"));
    core::connectPorts(patient.port("needlePlaneDistance"), monitor.port("needlePlaneDistance"));
    core::connectPorts(patient.port("needleInImage"), monitor.port("needleInImage"));
    core::connectPorts(patient.port("probeContactForce"), monitor.port("probeContactForce"));
    core::connectPorts(monitor.port("events"), events, core::ConnPolicy::buffer(16));
    EXPECT_TRUE(patient.configure()) << patient.lastError();
    EXPECT_TRUE(monitor.configure()) << monitor.lastError();
    EXPECT_TRUE(patient.start());
    EXPECT_TRUE(monitor.start());
  }
  /// One step: probe pressed `press` m into the skin, needle tip 30 mm deep at x, pointing down.
  void step(double press, double x) {
    probe.write(KDL::Frame(kProbeAxes, KDL::Vector(0, 0.02, -press)));
    needle.write(KDL::Frame(KDL::Rotation::RotX(3.141592653589793), KDL::Vector(x, 0, -0.03)));
    clock.advance(1ms);
  }
  Events take() { return test_support::takeEventNames(events); }
};

TEST(UltrasoundMonitor, VisibilityFollowsTheNeedlesDistanceToThePlaneWithHysteresis) {
  Rig rig;
  rig.step(0.002, 0.01);  // 4 N on the skin, needle 10 mm out of the plane
  EXPECT_EQ(rig.take(), Events{"e_probe_contact"});
  // Sweep x from +10 mm to -10 mm and back in 0.1 mm steps; visible below 2 mm, lost above 3 mm.
  std::vector<std::pair<double, std::string>> seen;
  auto sweep = [&](double from, double to) {
    const int n = 200;
    for (int i = 0; i <= n; ++i) {
      const double x = from + (to - from) * i / n;
      rig.step(0.002, x);
      for (const std::string& e : rig.take()) seen.emplace_back(x, e);
    }
  };
  sweep(0.01, -0.01);
  sweep(-0.01, 0.01);
  ASSERT_EQ(seen.size(), 4u);
  EXPECT_EQ(seen[0].second, "e_needle_visible");
  EXPECT_NEAR(seen[0].first, 0.0019, 1e-6);
  EXPECT_EQ(seen[1].second, "e_needle_lost");
  EXPECT_NEAR(seen[1].first, -0.003, 1.01e-4);  // the first sample beyond 3 mm
  EXPECT_EQ(seen[2].second, "e_needle_visible");
  EXPECT_NEAR(seen[2].first, -0.0019, 1e-6);
  EXPECT_EQ(seen[3].second, "e_needle_lost");
  EXPECT_NEAR(seen[3].first, 0.003, 1.01e-4);
}

TEST(UltrasoundMonitor, LiftingTheProbeLosesContactAndTheImage) {
  Rig rig;
  rig.step(0.002, 0.0);
  EXPECT_EQ(rig.take(), (Events{"e_probe_contact", "e_needle_visible"}));
  rig.step(0.0008, 0.0);  // 1.6 N: between the 1 N and 2 N thresholds, still in contact
  EXPECT_EQ(rig.take(), Events{});
  rig.step(0.0004, 0.0);  // 0.8 N
  EXPECT_EQ(rig.take(), (Events{"e_probe_contact_lost", "e_needle_lost"}));
  rig.step(-0.01, 0.0);
  EXPECT_EQ(rig.take(), Events{});
  rig.step(0.0015, 0.0);  // 3 N
  EXPECT_EQ(rig.take(), (Events{"e_probe_contact", "e_needle_visible"}));
}

TEST(UltrasoundMonitor, ContactIsLostOnlyWhenTheForceStaysLowForContactLostTime) {
  Rig rig;
  ASSERT_TRUE(rig.monitor.stop());
  ASSERT_TRUE(rig.monitor.cleanup());
  rig.monitor.setProperty("contact_lost_time", 0.005);
  ASSERT_TRUE(rig.monitor.configure()) << rig.monitor.lastError();
  ASSERT_TRUE(rig.monitor.start());
  rig.step(0.002, 0.01);
  EXPECT_EQ(rig.take(), Events{"e_probe_contact"});
  for (int i = 0; i < 4; ++i) rig.step(0.0004, 0.01);  // 0.8 N for 4 ms: a dip
  rig.step(0.002, 0.01);
  EXPECT_EQ(rig.take(), Events{});
  for (int i = 0; i < 5; ++i) rig.step(0.0004, 0.01);  // below from the 1st sample to the 5th: 4 ms
  EXPECT_EQ(rig.take(), Events{});
  rig.step(0.0004, 0.01);  // 5 ms
  EXPECT_EQ(rig.take(), Events{"e_probe_contact_lost"});
}

TEST(UltrasoundMonitor, InconsistentThresholdsAreRefused) {
  UltrasoundMonitor monitor("us");
  monitor.setProperty("lost_distance", 0.001);
  core::Result r = monitor.configure();
  EXPECT_FALSE(r);
  EXPECT_CONTAINS(r.message, "expected 0 < visible_distance <= lost_distance");
  UltrasoundMonitor force("us");
  force.setProperty("contact_lost_force", 3.0);
  r = force.configure();
  EXPECT_FALSE(r);
  EXPECT_CONTAINS(r.message, "expected 0 <= contact_lost_force <= contact_force");
  UltrasoundMonitor time("us");
  time.setProperty("contact_lost_time", -0.1);
  r = time.configure();
  EXPECT_FALSE(r);
  EXPECT_CONTAINS(r.message, "property contact_lost_time (-0.100000 s): expected >= 0");
}

}  // namespace
}  // namespace cobra::components
