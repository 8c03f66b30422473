// The Transparency and Passivity layer components on the lockstep clock: coupling only after
// engage, the tanks they report, a slave (the VariableAdmittance component) that follows a
// master's pose on SE(3) - its orientation too - without a jump at engage, wired as
// teleoperation_coupling.lua wires them (a Passivity layer per side, a LinkImpairment between),
// the slave's tank filled by the admittance's dissipatedPower, the tanks' exchange in the link's
// packets (delayed, and lost with them), bad properties named with their component, and no
// allocation.
#include "cobra/components/control/teleoperation_components.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <tuple>
#include <utility>
#include <vector>

#include "cobra/components/control/link_impairment_component.hpp"
#include "cobra/components/control/variable_admittance_component.hpp"
#include "cobra/core/lockstep_clock.hpp"
#include "cobra/test_support/counting_new.hpp"
#include "cobra/test_support/test_support.hpp"

namespace cobra::components {
namespace {

using namespace std::chrono_literals;

TEST(TeleoperationComponents, TeleoperationLayersCoupleOnlyAfterEngageAndReportTheirTanks) {
  TransparencyLayerComponent transparency("Transparency");
  PassivityLayerComponent passivity("Passivity");
  core::LockstepClock clock;
  clock.add(transparency, 1ms);
  clock.add(passivity, 1ms);
  core::OutputPort<KDL::Frame> master{"master", "", "m"}, slave{"slave", "", "m"};
  core::InputPort<KDL::Wrench> master_force{"mf", "", "N"};
  core::InputPort<double> tank{"st", "", "J"};
  core::connectPorts(master, transparency.port("masterPose"));
  core::connectPorts(slave, transparency.port("slavePose"));
  // The master's side's layer (no twist wired: the master does not move, so it pays nothing).
  core::connectPorts(transparency.port("masterForceDesired"), passivity.port("forceDesired"));
  core::connectPorts(passivity.port("force"), master_force);
  core::connectPorts(passivity.port("tankEnergy"), tank);
  for (core::Component* c : {static_cast<core::Component*>(&transparency), static_cast<core::Component*>(&passivity)}) {
    ASSERT_TRUE(c->configure());
    ASSERT_TRUE(c->start());
  }
  master.write(KDL::Frame(KDL::Vector(0.05, 0, 0)));
  slave.write(KDL::Frame::Identity());
  clock.advance(2ms);
  KDL::Wrench f;
  ASSERT_NE(master_force.read(f), core::FlowStatus::NoData);
  EXPECT_EQ(f.force.Norm(), 0.0);  // not engaged
  transparency.call<void>("engage");
  clock.advance(1000ms);  // half of t_c: the rest length has shrunk, the master is pulled
  ASSERT_NE(master_force.read(f), core::FlowStatus::NoData);
  EXPECT_LT(f.force.x(), -0.5);
  double energy = 0.0;
  ASSERT_NE(tank.read(energy), core::FlowStatus::NoData);
  EXPECT_DOUBLE_EQ(energy, 10.0);  // nothing moved: nothing paid
  EXPECT_EQ(cobra::test_support::allocationsDuring([&] { clock.advance(100ms); }), 0);
}

/// Smooth ramp from 0 (t <= t0) to 1 (t >= t1) and its rate (1/s).
double ramp(double t, double t0, double t1) {
  if (t <= t0) return 0.0;
  if (t >= t1) return 1.0;
  return 0.5 - 0.5 * std::cos(M_PI * (t - t0) / (t1 - t0));
}
double rampRate(double t, double t0, double t1) {
  if (t <= t0 || t >= t1) return 0.0;
  return 0.5 * M_PI / (t1 - t0) * std::sin(M_PI * (t - t0) / (t1 - t0));
}

/// Transparency + Passivity coupling a scripted master (its pose and twist written by the test)
/// with a slave that is the VariableAdmittance component (no stiffness: it goes where it is
/// pushed), wired as teleoperation_coupling.lua wires them (without the clutch): the master's
/// pose and twist over the link to the Transparency layer, one Passivity layer per side, the
/// master's wrench back over the link, the tanks' packets both ways.
struct Teleoperated {
  TransparencyLayerComponent transparency{"Transparency"};
  PassivityLayerComponent master_side{"MasterPassivity"}, slave_side{"SlavePassivity"};
  LinkImpairmentComponent link{"Link"};
  VariableAdmittanceController slave{"Admittance"};
  core::LockstepClock clock;
  core::OutputPort<KDL::Frame> master_pose{"masterPose", "", "m"}, reference{"reference", "", "m"};
  core::OutputPort<KDL::Twist> master_twist{"masterTwist", "", "m/s, rad/s"};
  core::OutputPort<KDL::Wrench> push{"push", "", "N, N·m"};
  core::InputPort<KDL::Frame> slave_pose{"slavePose", "", "m"};
  core::InputPort<KDL::Wrench> master_force{"masterForce", "", "N, N·m"}, slave_force{"slaveForce", "", "N, N·m"};
  core::InputPort<double> slave_tank{"slaveTank", "", "J"}, master_tank{"masterTank", "", "J"};

  /// `admittance_tank` (J, > 0): the admittance's own tank starts there (and its maximum is that).
  /// `tanks`: the master's and the slave's side's tanks' initial energy (J); `link_setting`: the
  /// link's delay (s) and loss (0..1).
  explicit Teleoperated(const KDL::Frame& start, double admittance_tank = 0.0, std::pair<double, double> tanks = {10, 10},
                        std::pair<double, double> link_setting = {0.0, 0.0}) {
    if (admittance_tank > 0.0) {
      slave.setProperty("tank_max", admittance_tank);
      slave.setProperty("tank_initial", admittance_tank);
    }
    master_side.setProperty("initial", tanks.first);
    slave_side.setProperty("initial", tanks.second);
    link.setProperty("delay", link_setting.first);
    link.setProperty("loss", link_setting.second);
    transparency.setProperty("rotational_stiffness", 2.0);  // N·m/rad
    transparency.setProperty("rotational_damping", 0.1);    // N·m·s/rad
    slave.setProperty("inertia", std::vector<double>{1, 1, 1, 0.05, 0.05, 0.05});
    slave.setProperty("constant_inertia", std::vector<double>{1, 1, 1, 0.05, 0.05, 0.05});
    slave.setProperty("damping", std::vector<double>{30, 30, 30, 0.5, 0.5, 0.5});
    slave.setProperty("stiffness", std::vector<double>{0, 0, 0, 0, 0, 0});
    slave.setProperty("constant_stiffness", std::vector<double>{0, 0, 0, 0, 0, 0});
    for (core::Component* c : components()) clock.add(*c, 1ms);
    auto wire = [](core::PortBase& out, core::PortBase& in) { core::connectPorts(out, in); };
    wire(master_pose, link.port("masterPose"));
    wire(master_twist, link.port("masterTwist"));
    wire(master_twist, master_side.port("twist"));
    wire(link.port("linkedMasterPose"), transparency.port("masterPose"));
    wire(link.port("linkedMasterTwist"), transparency.port("masterTwist"));
    wire(slave.port("admPose"), transparency.port("slavePose"));
    wire(slave.port("admTwist"), transparency.port("slaveTwist"));
    wire(transparency.port("slaveForceDesired"), slave_side.port("forceDesired"));
    wire(slave.port("admTwist"), slave_side.port("twist"));
    wire(slave.port("dissipatedPower"), slave_side.port("dissipation"));
    wire(slave_side.port("force"), slave.port("extWrench"));
    wire(transparency.port("masterForceDesired"), link.port("slaveWrench"));
    wire(link.port("linkedSlaveWrench"), master_side.port("forceDesired"));
    wire(master_side.port("energyOut"), link.port("masterEnergy"));
    wire(master_side.port("request"), link.port("masterRequest"));
    wire(link.port("linkedMasterEnergy"), slave_side.port("energyIn"));
    wire(link.port("linkedMasterRequest"), slave_side.port("peerRequest"));
    wire(slave_side.port("energyOut"), link.port("slaveEnergy"));
    wire(slave_side.port("request"), link.port("slaveRequest"));
    wire(link.port("linkedSlaveEnergy"), master_side.port("energyIn"));
    wire(link.port("linkedSlaveRequest"), master_side.port("peerRequest"));
    wire(reference, slave.port("refPose"));
    wire(push, slave.port("measWrench"));
    wire(slave.port("admPose"), slave_pose);
    wire(master_side.port("force"), master_force);
    wire(slave_side.port("force"), slave_force);
    wire(slave_side.port("tankEnergy"), slave_tank);
    wire(master_side.port("tankEnergy"), master_tank);
    reference.write(start);
    master_pose.write(start);
    master_twist.write(KDL::Twist::Zero());
    for (core::Component* c : components()) {
      EXPECT_TRUE(c->configure()) << c->lastError();
      EXPECT_TRUE(c->start());
    }
  }
  std::vector<core::Component*> components() { return {&slave, &link, &transparency, &master_side, &slave_side}; }
  template <class T>
  T read(core::InputPort<T>& port) {
    T value{};
    EXPECT_NE(port.read(value), core::FlowStatus::NoData) << port.name();
    return value;
  }
};

TEST(TeleoperationComponents, TheSlavesOrientationFollowsTheMastersAndNothingJumpsAtEngage) {
  const KDL::Frame start(KDL::Rotation::RotX(0.4) * KDL::Rotation::RotY(-0.2), KDL::Vector(0.3, 0.1, 0.2));
  Teleoperated rig(start);
  rig.clock.advance(10ms);
  // The surgeon takes over with the master 3 cm and 0.3 rad away from the slave; over 1.5 s they
  // bring it within 2 mrad of the slave's pose, then turn it by 0.4 rad about the slave's z in 1 s.
  const KDL::Vector axis = start.M.UnitZ();
  const KDL::Vector offset(0.03, -0.01, 0.0);
  auto master = [&](double t) {
    const double back = 1.0 - ramp(t, 0.0, 1.5), turn = ramp(t, 2.5, 3.5);
    const double angle = 0.02 + 0.28 * back + 0.4 * turn;
    const double rate = -0.28 * rampRate(t, 0.0, 1.5) + 0.4 * rampRate(t, 2.5, 3.5);
    return std::pair{KDL::Frame(start.M * KDL::Rotation::RotZ(angle), start.p + offset * back),
                     KDL::Twist(offset * -rampRate(t, 0.0, 1.5), axis * rate)};
  };
  auto [pose, twist] = master(0.0);
  rig.master_pose.write(pose);
  rig.master_twist.write(twist);
  rig.clock.advance(1ms);
  rig.transparency.call<void>("engage");
  const KDL::Frame slave_at_engage = rig.read(rig.slave_pose);
  double largest_master_wrench = 0.0, largest_slave_step = 0.0;  // N and N·m; m and rad
  KDL::Frame previous = slave_at_engage;
  for (int ms = 1; ms <= 6000; ++ms) {
    std::tie(pose, twist) = master(ms * 1e-3);
    rig.master_pose.write(pose);
    rig.master_twist.write(twist);
    rig.clock.advance(1ms);
    const KDL::Frame now = rig.read(rig.slave_pose);
    if (ms <= 20) {  // the first 20 ms after engage
      const KDL::Wrench w = rig.read(rig.master_force);
      largest_master_wrench = std::max({largest_master_wrench, w.force.Norm(), w.torque.Norm()});
      largest_slave_step = std::max({largest_slave_step, (now.p - previous.p).Norm(), KDL::diff(previous.M, now.M).Norm()});
    }
    previous = now;
  }
  // At engage the rest lengths hold the 3 cm and 0.3 rad offsets: 50 N/m · 3 cm would be 1.5 N.
  EXPECT_LT(largest_master_wrench, 0.01);
  EXPECT_LT(largest_slave_step, 1e-6);
  const KDL::Frame slave = rig.read(rig.slave_pose);
  EXPECT_LT(KDL::diff(slave.M, pose.M).Norm(), M_PI / 180.0) << "within 1 degree of the master's orientation";
  EXPECT_GT(KDL::diff(slave_at_engage.M, slave.M).Norm(), 0.4) << "the slave turned with the master";
  EXPECT_LT((slave.p - pose.p).Norm(), 0.001);
  EXPECT_EQ(cobra::test_support::allocationsDuring([&] { rig.clock.advance(100ms); }), 0);
}

// The slave's tank fills with what the admittance dissipated and its own tank did not store:
// nothing while that tank has room (the energy is there already, counted once), all of it once
// that tank is full.
TEST(TeleoperationComponents, TheSlaveTankFillsWithTheDissipationTheAdmittancesTankLetsGo) {
  for (const bool full : {false, true}) {
    Teleoperated rig(KDL::Frame::Identity(), full ? 20.0 : 0.0);
    // Not engaged: no coupling to pay. A hand pushes the slave (the admittance) around for 2 s.
    for (int ms = 0; ms < 2000; ++ms) {
      rig.push.write(KDL::Wrench(KDL::Vector(5.0 * std::sin(ms * 6e-3), 0, 0), KDL::Vector(0, 0.3, 0)));
      rig.clock.advance(1ms);
    }
    if (full) {
      EXPECT_GT(rig.read(rig.slave_tank), 10.0 + 0.05);  // W · s the full admittance tank let go
    } else {
      EXPECT_DOUBLE_EQ(rig.read(rig.slave_tank), 10.0);
    }
    EXPECT_EQ(rig.read(rig.slave_force).force.Norm(), 0.0);
  }
}

TEST(TeleoperationComponents, BadPropertiesAreRefusedNamingTheComponentAndTheProperty) {
  TransparencyLayerComponent transparency("Transparency");
  transparency.setProperty("rotational_stiffness", -1.0);
  EXPECT_EQ(transparency.configure().message,
            "component 'Transparency': TransparencyLayer: rotational_stiffness = -1 N·m/rad: must be >= 0");
  transparency.setProperty("rotational_stiffness", 1.0);
  transparency.setProperty("stiffness", 0.0);
  EXPECT_EQ(transparency.configure().message, "component 'Transparency': TransparencyLayer: stiffness = 0 N/m: must be > 0");
  PassivityLayerComponent passivity("Passivity");
  core::LockstepClock clock;
  clock.add(passivity, 1ms);
  passivity.setProperty("available", 25.0);
  EXPECT_CONTAINS(passivity.configure().message,
                  "component 'Passivity': PassivityLayer: maximum = 20 J: must be > available = 25 J");
  passivity.setProperty("available", 10.0);
  passivity.setProperty("transfer_power", -1.0);
  EXPECT_CONTAINS(passivity.configure().message, "PassivityLayer: transfer_power = -1 W: must be > 0");
  passivity.setProperty("transfer_power", 1.0);
  passivity.setProperty("max_torque", 2.0);
  passivity.setProperty("request", 0.5);
  EXPECT_CONTAINS(passivity.configure().message,
                  "component 'Passivity': PassivityLayer: request = 0.5 J: must be > minimum = 1 J");
}

// The tanks trade energy only in the link's packets: the master's side's tank (2 J, below T_req =
// 5 J) asks, the request takes the link's delay to reach the slave's side's tank (15 J, above
// T_ava = 10 J), whose packets (P̄ = 1 W: 1 mJ a period) take the delay back: nothing arrives
// before the round trip. What the slave's side sent left its tank at once; of it, the master's
// side gets what the link delivered: with half of the packets lost, about half, never more.
TEST(TeleoperationComponents, TheTanksTradeEnergyOnlyInTheLinksPacketsDelayedAndLostWithThem) {
  for (const double loss : {0.0, 0.5}) {
    Teleoperated rig(KDL::Frame::Identity(), 0.0, {2.0, 15.0}, {0.05, loss});
    rig.clock.advance(95ms);  // less than the 100 ms round trip
    EXPECT_DOUBLE_EQ(rig.read(rig.master_tank), 2.0) << "loss " << loss;
    EXPECT_LT(rig.read(rig.slave_tank), 15.0) << "the slave's side sends once the request arrived, 50 ms in";
    rig.clock.advance(1905ms);  // 2 s in all
    const double received = rig.read(rig.master_tank) - 2.0, sent = 15.0 - rig.read(rig.slave_tank);
    // The slave's side sent from 50 ms (the request's arrival) on: about 1.95 J at 1 W.
    EXPECT_NEAR(sent, 1.95, 0.01) << "loss " << loss;
    if (loss == 0.0) {
      EXPECT_NEAR(received, sent - 0.05, 0.01) << "all but the last 50 ms in flight";
    } else {
      EXPECT_LT(received, 0.7 * sent) << "the lost packets' energy is gone";
      EXPECT_GT(received, 0.3 * sent);
    }
  }
}

}  // namespace
}  // namespace cobra::components
