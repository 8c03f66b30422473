// NeedleInsertionMonitor on the lockstep clock with the wrench and poses written by the test.
#include "cobra/components/monitoring/needle_insertion_monitor.hpp"

#include <gtest/gtest.h>

#include "cobra/core/core.hpp"
#include "cobra/test_support/test_support.hpp"

namespace cobra::components {
namespace {

using namespace std::chrono_literals;

struct Rig {
  NeedleInsertionMonitor monitor{"monitor"};
  core::LockstepClock clock;
  core::OutputPort<KDL::Wrench> wrench{"wrench", "", "N"};
  core::OutputPort<KDL::Frame> pose{"pose", "", "m"};
  core::OutputPort<KDL::Frame> target{"target", "", "m"};
  core::InputPort<core::Event> events{"events", "", ""};

  Rig() {
    clock.add(monitor, 1ms);
    core::connectPorts(wrench, monitor.port("measWrench"));
    core::connectPorts(pose, monitor.port("measCartPose"));
    core::connectPorts(target, monitor.port("targetPose"));
    core::connectPorts(monitor.port("events"), events, core::ConnPolicy::buffer(16));
  }
  void start() {
    ASSERT_TRUE(monitor.configure()) << monitor.lastError();
    ASSERT_TRUE(monitor.start());
  }
  /// One step with an axial force `axial` (N, resisting insertion) on a needle along x.
  void push(double axial) {
    wrench.write(KDL::Wrench(KDL::Vector(-axial, 0, 0), KDL::Vector::Zero()));
    clock.advance(1ms);
  }
  std::vector<std::string> take() {
    std::vector<std::string> out;
    core::Event e;
    while (events.read(e) == core::FlowStatus::NewData) out.push_back(e.name.str());
    return out;
  }
};

using Events = std::vector<std::string>;

TEST(NeedleInsertionMonitor, ASharpDropAfterThePeakIsAPunctureASlowOneIsNot) {
  Rig rig;
  rig.start();
  rig.push(0.1);
  EXPECT_EQ(rig.take(), Events{});
  // Membrane loading to 1.4 N, then the robot backs off slowly: no puncture.
  for (int i = 1; i <= 140; ++i) rig.push(0.01 * i);
  EXPECT_EQ(rig.take(), Events{"e_skin_touched"});
  for (int i = 140; i >= 60; --i) rig.push(0.01 * i);
  EXPECT_EQ(rig.take(), Events{});
  // Loading again, then rupture: 1.5 N -> 0.4 N in one step.
  for (int i = 60; i <= 150; ++i) rig.push(0.01 * i);
  rig.push(0.4);
  EXPECT_EQ(rig.take(), Events{"e_skin_penetrated"});
  rig.push(2.0);  // the next layer: latched until reset()
  rig.push(0.3);
  EXPECT_EQ(rig.take(), Events{});
  rig.monitor.call<void>("reset");
  rig.push(0.5);
  EXPECT_EQ(rig.take(), Events{"e_skin_touched"});
}

TEST(NeedleInsertionMonitor, ForceOverThresholdAndTrappedNeedleAreEdgeTriggered) {
  Rig rig;
  rig.monitor.setProperty("max_force", 5.0);
  rig.monitor.setProperty("extraction_threshold", 10.0);
  rig.monitor.setProperty("release_force", 2.0);
  rig.start();
  rig.push(1.5);  // through the skin first
  rig.push(0.3);
  EXPECT_EQ(rig.take(), (Events{"e_skin_touched", "e_skin_penetrated"}));
  rig.push(6.0);
  rig.push(7.0);
  EXPECT_EQ(rig.take(), Events{"e_force_over_threshold"});
  rig.push(4.5);  // above 0.8 x 5 N: still the same episode
  rig.push(6.0);
  EXPECT_EQ(rig.take(), Events{});
  rig.push(0.0);
  rig.push(-12.0);  // pulled back against the iceball
  rig.push(-30.0);
  EXPECT_EQ(rig.take(), (Events{"e_force_over_threshold", "e_needle_trapped"}));
  rig.push(-3.0);
  EXPECT_EQ(rig.take(), Events{});
  rig.push(-1.0);
  EXPECT_EQ(rig.take(), Events{"e_needle_free"});
}

TEST(NeedleInsertionMonitor, TargetAndForbiddenRegionsFromTheMeasuredTip) {
  Rig rig;
  rig.monitor.setProperty("target_tolerance", 0.002);
  // A rib along y at x = 0.05, z = -0.02 (radius 6 mm); warn 2 mm before touching.
  rig.monitor.setProperty("forbidden_regions", std::vector<double>{0.05, -0.1, -0.02, 0.05, 0.1, -0.02, 0.006});
  rig.monitor.setProperty("forbidden_margin", 0.002);
  rig.start();
  rig.target.write(KDL::Frame(KDL::Vector(0, 0, -0.05)));
  for (double z = 0.0; z >= -0.06; z -= 0.0005) {
    rig.pose.write(KDL::Frame(KDL::Vector(0, 0, z)));
    rig.clock.advance(1ms);
    const Events e = rig.take();
    if (z > -0.048 + 1e-9) {
      EXPECT_EQ(e, Events{}) << z;
    } else if (z > -0.0485) {
      EXPECT_EQ(e, Events{"e_target_reached"}) << z;
    }
  }
  for (double x = 0.0; x <= 0.05; x += 0.0005) {
    rig.pose.write(KDL::Frame(KDL::Vector(x, 0, -0.02)));
    rig.clock.advance(1ms);
    const Events e = rig.take();
    if (x < 0.042 - 1e-9) {
      EXPECT_EQ(e, Events{}) << x;
    } else if (x < 0.0425) {
      EXPECT_EQ(e, Events{"e_forbidden_region"}) << x;  // 8 mm from the axis = radius + margin
    }
  }
}

TEST(NeedleInsertionMonitor, BadPropertiesAreRefusedByName) {
  NeedleInsertionMonitor capsules("m");
  capsules.setProperty("forbidden_regions", std::vector<double>{0, 0, 0, 1, 1, 1});
  core::Result r = capsules.configure();
  EXPECT_FALSE(r);
  EXPECT_EQ(r.message,
            "component 'm': property forbidden_regions has 6 numbers; give 7 per capsule (ax, ay, az, bx, by, bz, "
            "radius in m)");
  NeedleInsertionMonitor axis("m");
  axis.setProperty("needle_axis", KDL::Vector(1, 1, 0));
  r = axis.configure();
  EXPECT_FALSE(r);
  EXPECT_CONTAINS(r.message, "property needle_axis has length 1.414214; give a unit vector");
  NeedleInsertionMonitor drop("m");
  drop.setProperty("puncture_drop", 1.5);
  r = drop.configure();
  EXPECT_FALSE(r);
  EXPECT_CONTAINS(r.message, "property puncture_drop is 1.500000; expected a fraction in (0, 1)");
  NeedleInsertionMonitor release("m");
  release.setProperty("release_force", 20.0);
  r = release.configure();
  EXPECT_FALSE(r);
  EXPECT_CONTAINS(r.message, "release_force (20.000000 N) must be below extraction_threshold (10.000000 N)");
  NeedleInsertionMonitor negative("m");
  negative.setProperty("max_force", -1.0);
  r = negative.configure();
  EXPECT_FALSE(r);
  EXPECT_CONTAINS(r.message, "property max_force is -1.000000 N; expected > 0 N");
}

}  // namespace
}  // namespace cobra::components
