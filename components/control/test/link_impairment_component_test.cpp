// LinkImpairment between the two sides of a teleoperation coupling, on the lockstep clock: without
// impairment the outputs are the inputs of the same update; a delay shifts both directions by it;
// a seeded loss drops its share of the packets (counted) and the receiver keeps the previous
// sample; jitter never lets an older packet follow a newer one; the component is found in the
// cobra_control package; the Passivity layers' energy packets cross it once each (a sample not
// new sends 0 J), delayed, and are lost with their packet; bad properties are refused naming them;
// the update allocates nothing.
#include "cobra/components/control/link_impairment_component.hpp"

#include <gtest/gtest.h>

#include "cobra/components/builtin_packages.hpp"
#include "cobra/core/lockstep_clock.hpp"
#include "cobra/deploy/package_registry.hpp"

#include <cstdio>
#include <memory>
#include "cobra/test_support/counting_new.hpp"
#include "cobra/test_support/test_support.hpp"

namespace cobra::components {
namespace {

using namespace std::chrono_literals;

struct Link {
  LinkImpairmentComponent link{"Link"};
  core::LockstepClock clock;
  core::OutputPort<KDL::Frame> pose{"pose", "", "m"};
  core::OutputPort<KDL::Twist> twist{"twist", "", "m/s"};
  core::OutputPort<KDL::Wrench> wrench{"wrench", "", "N"};
  core::InputPort<KDL::Frame> linked_pose{"lp", "", "m"};
  core::InputPort<KDL::Twist> linked_twist{"lt", "", "m/s"};
  core::InputPort<KDL::Wrench> linked_wrench{"lw", "", "N"};
  core::InputPort<int> lost{"lost", "", "1"}, late{"late", "", "1"}, refused{"refused", "", "1"};

  Link(double delay, double jitter, double loss, int capacity = 4096) {
    link.setProperty("delay", delay);
    link.setProperty("jitter", jitter);
    link.setProperty("loss", loss);
    link.setProperty("seed", 7);
    link.setProperty("capacity", capacity);
    clock.add(link, 1ms);
    core::connectPorts(pose, link.port("masterPose"));
    core::connectPorts(twist, link.port("masterTwist"));
    core::connectPorts(wrench, link.port("slaveWrench"));
    core::connectPorts(link.port("linkedMasterPose"), linked_pose);
    core::connectPorts(link.port("linkedMasterTwist"), linked_twist);
    core::connectPorts(link.port("linkedSlaveWrench"), linked_wrench);
    core::connectPorts(link.port("lostForward"), lost);
    core::connectPorts(link.port("lateForward"), late);
    core::connectPorts(link.port("refusedForward"), refused);
    EXPECT_TRUE(link.configure()) << link.lastError();
    EXPECT_TRUE(link.start());
  }
  /// One period: the master at x = `x` (m), moving at `x` m/s; the slave's wrench `x` N.
  void step(double x) {
    pose.write(KDL::Frame(KDL::Rotation::RotZ(x), KDL::Vector(x, 0, 0)));
    twist.write(KDL::Twist(KDL::Vector(x, 0, 0), KDL::Vector::Zero()));
    wrench.write(KDL::Wrench(KDL::Vector(0, x, 0), KDL::Vector::Zero()));
    clock.advance(1ms);
  }
  double poseX() {
    KDL::Frame f;
    EXPECT_NE(linked_pose.read(f), core::FlowStatus::NoData);
    return f.p.x();
  }
  double wrenchY() {
    KDL::Wrench w;
    EXPECT_NE(linked_wrench.read(w), core::FlowStatus::NoData);
    return w.force.y();
  }
  int counter(core::InputPort<int>& port) {
    int n = -1;
    EXPECT_NE(port.read(n), core::FlowStatus::NoData);
    return n;
  }
};

TEST(LinkImpairmentComponent, WithoutImpairmentTheOutputsAreTheInputsOfTheSameUpdate) {
  Link l(0.0, 0.0, 0.0);
  for (int k = 1; k <= 20; ++k) {
    l.step(0.001 * k);
    EXPECT_DOUBLE_EQ(l.poseX(), 0.001 * k);
    EXPECT_DOUBLE_EQ(l.wrenchY(), 0.001 * k);
    KDL::Frame f;
    (void)l.linked_pose.read(f);
    EXPECT_TRUE(KDL::Equal(f.M, KDL::Rotation::RotZ(0.001 * k), 1e-15));  // the whole pose crosses
    KDL::Twist t;
    ASSERT_NE(l.linked_twist.read(t), core::FlowStatus::NoData);
    EXPECT_DOUBLE_EQ(t.vel.x(), 0.001 * k);
  }
  EXPECT_EQ(l.counter(l.lost), 0);
}

TEST(LinkImpairmentComponent, ADelayShiftsBothDirectionsByIt) {
  Link l(0.1, 0.0, 0.0);
  KDL::Frame f;
  for (int k = 1; k <= 100; ++k) l.step(0.001 * k);
  EXPECT_EQ(l.linked_pose.read(f), core::FlowStatus::NoData);  // the first packet is still on its way
  for (int k = 101; k <= 400; ++k) {
    l.step(0.001 * k);
    EXPECT_NEAR(l.poseX(), 0.001 * (k - 100), 1e-12) << "update " << k;  // sent 100 periods earlier
    EXPECT_NEAR(l.wrenchY(), 0.001 * (k - 100), 1e-12) << "update " << k;
  }
}

TEST(LinkImpairmentComponent, ASeededLossDropsItsShareAndTheReceiverKeepsThePreviousSample) {
  Link l(0.0, 0.0, 0.1);
  const int n = 20000;
  int held = 0;
  for (int k = 1; k <= n; ++k) {
    l.step(1e-6 * k);
    if (l.poseX() < 1e-6 * k - 1e-12) ++held;  // this update's packet was lost: the last one stays
  }
  const int lost = l.counter(l.lost);
  EXPECT_EQ(held, lost);
  EXPECT_NEAR(static_cast<double>(lost) / n, 0.1, 0.01);
  std::printf("lost %d of %d packets\n", lost, n);
}

TEST(LinkImpairmentComponent, JitterNeverDeliversAnOlderPacketAfterANewerOne) {
  Link l(0.05, 0.03, 0.0);
  double last = -1.0;
  for (int k = 1; k <= 3000; ++k) {
    l.step(0.001 * k);
    KDL::Frame f;
    if (l.linked_pose.read(f) == core::FlowStatus::NoData) continue;
    EXPECT_GE(f.p.x(), last);
    EXPECT_LE(f.p.x(), 0.001 * k - 0.05 + 1e-12);  // never earlier than the constant delay
    last = f.p.x();
  }
  EXPECT_GT(l.counter(l.late), 100);  // overtaken packets were discarded
}

TEST(LinkImpairmentComponent, AFullBufferRefusesSendsAndCountsThem) {
  Link l(0.1, 0.0, 0.0, 50);  // 100 packets in flight needed, 50 held
  for (int k = 1; k <= 300; ++k) l.step(0.001 * k);
  EXPECT_GT(l.counter(l.refused), 0);
}

// The tanks' energy rides the packets: a sample written once is sent once (the next updates send
// 0 J: energy is never duplicated), arrives after the delay, once; the request is told every
// period. With loss, the energy that arrives is what the delivered packets carried: never more
// than was sent.
TEST(LinkImpairmentComponent, TheTanksEnergyCrossesOnceDelayedAndIsLostWithItsPacket) {
  for (const double loss : {0.0, 0.3}) {
    LinkImpairmentComponent link{"Link"};
    core::LockstepClock clock;
    core::OutputPort<double> energy{"energy", "", "J"};
    core::OutputPort<bool> request{"request", "", "1"};
    core::InputPort<double> linked_energy{"le", "", "J"};
    core::InputPort<bool> linked_request{"lr", "", "1"};
    link.setProperty("delay", 0.005);
    link.setProperty("loss", loss);
    clock.add(link, 1ms);
    core::connectPorts(energy, link.port("slaveEnergy"));
    core::connectPorts(request, link.port("slaveRequest"));
    core::connectPorts(link.port("linkedSlaveEnergy"), linked_energy);
    core::connectPorts(link.port("linkedSlaveRequest"), linked_request);
    ASSERT_TRUE(link.configure()) << link.lastError();
    ASSERT_TRUE(link.start());
    double sent = 0.0, arrived = 0.0;
    int first_arrival = -1;
    for (int k = 0; k < 400; ++k) {
      if (k % 2 == 0) {  // a packet of 1 mJ every other period; nothing new in between
        energy.write(1e-3);
        sent += 1e-3;
      }
      request.write(k < 200);
      clock.advance(1ms);
      double e = 0.0;
      if (linked_energy.readNew(e) == core::FlowStatus::NewData) {
        arrived += e;
        if (e > 0.0 && first_arrival < 0) first_arrival = k;
      }
    }
    bool asks = true;
    ASSERT_NE(linked_request.read(asks), core::FlowStatus::NoData);
    EXPECT_FALSE(asks) << "the request's end crossed too";
    if (loss == 0.0) {
      EXPECT_EQ(first_arrival, 5) << "after the 5 ms delay";
      EXPECT_NEAR(arrived, sent - 2e-3, 1e-12) << "all but the two packets of the last 5 ms in flight, each once";
    } else {
      EXPECT_LT(arrived, 0.85 * sent) << "the lost packets' energy is gone";
      EXPECT_GT(arrived, 0.55 * sent);
    }
  }
}

TEST(LinkImpairmentComponent, IsInTheControlPackage) {
  deploy::PackageRegistry packages;
  addBuiltinPackages(packages);
  packages.load("cobra_control");
  const std::unique_ptr<core::Component> link = packages.create("LinkImpairment", "Link");
  EXPECT_NE(dynamic_cast<LinkImpairmentComponent*>(link.get()), nullptr);
}

TEST(LinkImpairmentComponent, BadPropertiesAreRefusedNamingThem) {
  auto refused = [](const char* property, double value) {
    LinkImpairmentComponent link("Link");
    core::LockstepClock clock;
    clock.add(link, 1ms);
    link.setProperty(property, value);
    const core::Result r = link.configure();
    EXPECT_FALSE(r);
    return r.message;
  };
  EXPECT_CONTAINS(refused("delay", -0.01), "component 'Link': LinkImpairment: delay must be >= 0 (s), got -0.01");
  EXPECT_CONTAINS(refused("jitter", -1.0), "component 'Link': LinkImpairment: jitter must be >= 0 (s)");
  EXPECT_CONTAINS(refused("loss", 1.5), "component 'Link': LinkImpairment: loss must be in [0, 1] (share of samples)");
  LinkImpairmentComponent link("Link");
  core::LockstepClock clock;
  clock.add(link, 1ms);
  link.setProperty("capacity", 0);
  EXPECT_CONTAINS(link.configure().message, "component 'Link': property capacity is 0; expected >= 1 packets");
  LinkImpairmentComponent unpaced("Unpaced");
  EXPECT_CONTAINS(unpaced.configure().message, "component 'Unpaced': needs a periodic activity");
}

TEST(LinkImpairmentComponent, TheUpdateAllocatesNothing) {
  Link l(0.1, 0.02, 0.1);
  for (int k = 1; k <= 200; ++k) l.step(0.001 * k);
  EXPECT_EQ(cobra::test_support::allocationsDuring([&] {
              for (int k = 201; k <= 1200; ++k) l.step(0.001 * k);
            }),
            0);
}

}  // namespace
}  // namespace cobra::components
