// ContactMonitor: a tool pressed on a surface and lifted off, pushed off its nominal path and
// back, a force above the limit; the thresholds, their hysteresis and the release time; the
// configure-time checks; no allocation in the update.
#include "cobra/components/monitoring/contact_monitor.hpp"

#include <gtest/gtest.h>

#include "cobra/core/core.hpp"
#include "cobra/test_support/counting_new.hpp"
#include "cobra/test_support/event_names.hpp"
#include "cobra/test_support/test_support.hpp"

namespace cobra::components {
namespace {

using namespace std::chrono_literals;
using Events = std::vector<std::string>;

struct Rig {
  ContactMonitor monitor{"monitor"};
  core::LockstepClock clock;
  core::OutputPort<KDL::Wrench> wrench{"wrench", "", "N"};
  core::OutputPort<KDL::Frame> measured{"measured", "", "m"};
  core::OutputPort<KDL::Frame> nominal{"nominal", "", "m"};
  core::InputPort<core::Event> events{"events", "", ""};

  Rig() {
    clock.add(monitor, 1ms);
    core::connectPorts(wrench, monitor.port("measWrench"));
    core::connectPorts(measured, monitor.port("measPose"));
    core::connectPorts(nominal, monitor.port("nominalPose"));
    core::connectPorts(monitor.port("events"), events, core::ConnPolicy::buffer(16));
  }
  void start() {
    EXPECT_TRUE(monitor.configure()) << monitor.lastError();
    EXPECT_TRUE(monitor.start());
  }
  /// One 1 ms step: force `fz` N along z (and 0.3 of it along y: only the magnitude counts), the
  /// tool `off` m above its nominal position.
  void step(double fz, double off) {
    wrench.write(KDL::Wrench(KDL::Vector(0, 0.3 * fz, fz), KDL::Vector(0.1, 0, 0)));
    nominal.write(KDL::Frame(KDL::Vector(0.35, 0.01, 0.10)));
    measured.write(KDL::Frame(KDL::Vector(0.35, 0.01, 0.10 + off)));
    clock.advance(1ms);
  }
  Events take() { return test_support::takeEventNames(events); }
};

TEST(ContactMonitor, ContactIsMadeAboveTheContactForceAndLostAfterTheReleaseTimeBelowTheReleaseForce) {
  Rig rig;
  rig.start();  // contact 1 N, release 0.5 N for 50 ms
  rig.step(0.9, 0);
  EXPECT_EQ(rig.take(), Events{});
  rig.step(1.0, 0);  // |F| = 1.044 N
  EXPECT_EQ(rig.take(), Events{"e_contact"});
  rig.step(3.0, 0);
  rig.step(0.6, 0);  // between the two thresholds: still in contact
  EXPECT_EQ(rig.take(), Events{});
  for (int i = 0; i < 30; ++i) rig.step(0.2, 0);  // a 30 ms dip is a bounce, not a loss
  rig.step(2.0, 0);
  EXPECT_EQ(rig.take(), Events{});
  int steps = 0;
  Events seen;
  while (seen.empty() && steps < 200) {
    rig.step(0.2, 0);
    ++steps;
    seen = rig.take();
  }
  EXPECT_EQ(seen, Events{"e_contact_lost"});
  EXPECT_EQ(steps, 51);  // the first sample below at 0 ms, lost once 50 ms have passed
  rig.step(1.5, 0);
  EXPECT_EQ(rig.take(), Events{"e_contact"});
}

TEST(ContactMonitor, TheForceLimitIsReportedOncePerEpisode) {
  Rig rig;
  rig.start();  // limit 10 N
  rig.step(2, 0);
  rig.step(9.5, 0);  // |F| = 9.92 N
  EXPECT_EQ(rig.take(), Events{"e_contact"});
  rig.step(9.7, 0);  // |F| = 10.13 N
  EXPECT_EQ(rig.take(), Events{"e_force_over_limit"});
  rig.step(12, 0);
  rig.step(5, 0);
  rig.step(12, 0);
  EXPECT_EQ(rig.take(), Events{});  // not re-armed until the contact is released
  for (int i = 0; i < 60; ++i) rig.step(0, 0);
  EXPECT_EQ(rig.take(), Events{"e_contact_lost"});
  rig.step(12, 0);
  EXPECT_EQ(rig.take(), (Events{"e_contact", "e_force_over_limit"}));
}

TEST(ContactMonitor, OffAndBackOnThePathWithHysteresis) {
  Rig rig;
  rig.monitor.setProperty("off_path_distance", 0.005);
  rig.monitor.setProperty("on_path_distance", 0.001);
  rig.start();
  std::vector<std::pair<double, std::string>> seen;
  auto sweep = [&](double from, double to) {
    const int n = 100;
    for (int i = 0; i <= n; ++i) {
      const double off = from + (to - from) * i / n;
      rig.step(0, off);
      for (const std::string& e : rig.take()) seen.emplace_back(off, e);
    }
  };
  sweep(0, 0.01);       // 0.1 mm steps up to 10 mm
  sweep(0.01, 0.003);   // down to 3 mm: still off the path
  sweep(0.003, 0);
  ASSERT_EQ(seen.size(), 2u);
  EXPECT_EQ(seen[0].second, "e_off_path");
  EXPECT_NEAR(seen[0].first, 0.005, 1.01e-4);  // the first 0.1 mm step beyond 5 mm (rounding decides which)
  EXPECT_EQ(seen[1].second, "e_on_path");
  EXPECT_NEAR(seen[1].first, 0.001, 1.01e-4);  // the first step below 1 mm, not at 3 mm
}

TEST(ContactMonitor, NoPathEventBeforeBothPosesHaveArrived) {
  Rig rig;
  rig.start();
  rig.measured.write(KDL::Frame(KDL::Vector(0, 0, 1)));
  rig.clock.advance(1ms);
  EXPECT_EQ(rig.take(), Events{});
  rig.nominal.write(KDL::Frame(KDL::Vector(0, 0, 0)));
  rig.clock.advance(1ms);
  EXPECT_EQ(rig.take(), Events{"e_off_path"});
}

TEST(ContactMonitor, BadThresholdsAreRefusedNamingThePropertiesAndWhatIsExpected) {
  {
    ContactMonitor m("m");
    m.setProperty("release_force", 2.0);
    EXPECT_FALSE(m.configure());
    EXPECT_CONTAINS(m.lastError(), "release_force (2.000000 N): expected 0 <= release_force <= contact_force");
  }
  {
    ContactMonitor m("m");
    m.setProperty("max_force", 0.5);
    EXPECT_FALSE(m.configure());
    EXPECT_CONTAINS(m.lastError(), "max_force (0.500000 N): expected > contact_force (1.000000 N)");
  }
  {
    ContactMonitor m("m");
    m.setProperty("on_path_distance", 0.01);
    EXPECT_FALSE(m.configure());
    EXPECT_CONTAINS(m.lastError(), "expected 0 < on_path_distance < off_path_distance");
  }
  {
    ContactMonitor m("m");
    m.setProperty("release_time", -1.0);
    EXPECT_FALSE(m.configure());
    EXPECT_CONTAINS(m.lastError(), "release_time (-1.000000 s): expected >= 0");
  }
}

TEST(ContactMonitor, TheUpdateAllocatesNothing) {
  Rig rig;
  rig.start();
  rig.step(0, 0);
  rig.take();
  const long allocations = test_support::allocationsDuring([&] {
    for (int i = 0; i < 2000; ++i) rig.step(i % 500 < 250 ? 20.0 : 0.0, i % 300 < 150 ? 0.01 : 0.0);
  });
  EXPECT_EQ(allocations, 0);
  EXPECT_GT(rig.take().size(), 8u);  // the loop did cross every threshold several times
}

}  // namespace
}  // namespace cobra::components
