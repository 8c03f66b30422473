// Two-layer teleoperation (thesis §4.5.4) with a simulated master (a Phantom Omni-like device
// held by a hand with a grip impedance that yields to what it feels) and a slave pressing on a
// stiff wall: the switch from autonomous to teleoperated with a 5 cm misalignment, reference
// values of the literature (K = 50 N/m, B = 1.1 N·s/m, ē1 = 5 mm, ē2 = 10 mm, ε = 1 J,
// T_req = 5 J, T_ava = 10 J, T̄ = 20 J).
#include "cobra/control/teleoperation.hpp"

#include <gtest/gtest.h>

#include "cobra/test_support/counting_new.hpp"
#include "cobra/test_support/test_support.hpp"
#include "simulated_world.hpp"

namespace cobra::control {
namespace {

constexpr double kDt = 1e-3;  // s

using test::HumanHand;
using test::PointMass;
using test::StiffWall;

struct Scenario {
  TransparencyLayer transparency{TransparencyParameters{}};
  PassivityLayer passivity{PassivityParameters{}};
  PointMass master{0.1, 0.5};  // Phantom Omni-like end point
  PointMass slave{2.0, 30.0};  // the slave robot's admittance
  StiffWall wall{0.0, 5000.0};  // the slave presses 1 mm into it
  HumanHand hand;
  double hold_stiffness = 4000.0;  // N/m: the autonomous controller holds the slave where it was
  double human_energy = 0.0;       // work of the hand on the master, J
  double lowest_master = 1e9, lowest_slave = 1e9, largest_slave_motion = 0.0;
  Vector3 slave_at_switch;

  Scenario() {
    slave.x = Vector3(0.001, 0, 0);
    master.x = slave.x + Vector3(0.05, 0.0, 0.0);  // 5 cm misalignment at the switch
    hand.position = master.x;
    slave_at_switch = slave.x;
    transparency.engage(0.0, master.x, slave.x);
  }
  /// Kinetic, elastic (wall and hold spring) and tank energies, J.
  double energy() const {
    const double held = 0.5 * hold_stiffness * (slave.x - slave_at_switch).squaredNorm();
    return master.kinetic() + slave.kinetic() + wall.energy(slave.x.x()) + held + passivity.masterEnergy() +
           passivity.slaveEnergy();
  }
  void run(double seconds, double& t) {
    for (int i = 0; i < static_cast<int>(seconds / kDt); ++i, t += kDt) {
      Vector3 fm, fs;
      transparency.compute(t, master.x, master.v, slave.x, slave.v, fm, fs);
      const Vector3 hold = -hold_stiffness * (slave.x - slave_at_switch);
      const Vector3 wall_force(wall.force(slave.x.x()), 0, 0);
      const PassivityStep implemented =
          passivity.step(kDt, fm, fs, master.v, slave.v, master.dissipation(), slave.dissipation());
      const Vector3 human = hand.force(master.x, master.v);
      master.step(implemented.master_force + human, kDt);
      slave.step(implemented.slave_force + wall_force + hold, kDt);
      human_energy += human.dot(master.v) * kDt;
      hand.yield(master.x, kDt);
      lowest_master = std::min(lowest_master, passivity.masterEnergy());
      lowest_slave = std::min(lowest_slave, passivity.slaveEnergy());
      largest_slave_motion = std::max(largest_slave_motion, (slave.x - slave_at_switch).norm());
    }
  }
};

TEST(Teleoperation, SwitchingWithAFiveCentimetreMisalignmentDoesNotMoveTheSlave) {
  Scenario s;
  double t = 0.0;
  s.run(0.1, t);
  EXPECT_LT((s.master.x - (s.slave.x + Vector3(0.05, 0, 0))).norm(), 1e-3) << "no jump at the switch";
  s.run(2.0, t);  // t = t_c + 0.1 s
  EXPECT_LT((s.master.x - s.slave.x).norm(), 0.005) << "the offset is recovered within t_c (to ē1)";
  s.run(2.9, t);
  EXPECT_LT(s.largest_slave_motion, 1e-3) << "the slave is not dragged towards the master";  // < 1 mm
  EXPECT_LT((s.master.x - s.slave.x).norm(), 0.001);
  EXPECT_DOUBLE_EQ(s.transparency.alpha(), 1.0);
  EXPECT_EQ(s.transparency.restLength().norm(), 0.0);
  EXPECT_GE(s.lowest_master, 1.0);
  EXPECT_GE(s.lowest_slave, 1.0);
}

TEST(Teleoperation, AlphaWeighsTheSlavesForceByErrorAndRestLength) {
  TransparencyLayer layer{TransparencyParameters{}};
  Vector3 fm, fs;
  layer.compute(0.0, Vector3(0.05, 0, 0), Vector3::Zero(), Vector3::Zero(), Vector3::Zero(), fm, fs);
  EXPECT_EQ(fm, Vector3::Zero());  // not engaged
  layer.engage(0.0, Vector3(0.05, 0, 0), Vector3::Zero());
  layer.compute(0.0, Vector3(0.05, 0, 0), Vector3::Zero(), Vector3::Zero(), Vector3::Zero(), fm, fs);
  EXPECT_NEAR(fm.norm(), 0.0, 1e-12);  // rest length = offset at the switch: no force
  EXPECT_EQ(layer.alpha(), 0.0);
  layer.compute(1.0, Vector3(0.05, 0, 0), Vector3::Zero(), Vector3::Zero(), Vector3::Zero(), fm, fs);
  EXPECT_NEAR(layer.restLength().x(), 0.025, 1e-12);  // half way through t_c = 2 s
  EXPECT_LT(fm.x(), 0.0);                             // the master is pulled towards the slave...
  EXPECT_EQ(fs.norm(), 0.0);                          // ...the slave feels nothing (e = 5 cm > ē2)
  layer.compute(2.5, Vector3(0.004, 0, 0), Vector3::Zero(), Vector3::Zero(), Vector3::Zero(), fm, fs);
  EXPECT_EQ(layer.alpha(), 1.0);  // e = 4 mm < ē1 and l = 0
  EXPECT_NEAR(fs.x(), 50.0 * 0.004, 1e-12);
  layer.compute(3.0, Vector3(0.05, 0, 0), Vector3::Zero(), Vector3::Zero(), Vector3::Zero(), fm, fs);
  EXPECT_EQ(layer.alpha(), 1.0);  // once reached, alpha stays 1 (eq. 4.16)
}

TEST(Teleoperation, TanksRefuseForcesTheyCannotPayAndShareEnergyOnRequest) {
  PassivityParameters p;
  p.master.initial = 1.5;  // just above ε
  p.slave.initial = 15.0;  // rich: above T_ava
  PassivityLayer layer(p);
  const Vector3 v(0.1, 0, 0);
  // 6000 N against 0.1 m/s for 1 ms costs 0.6 J; the master tank has 0.5 J above ε: refused.
  PassivityStep out = layer.step(kDt, Vector3(-6000.0, 0, 0), Vector3::Zero(), -v, Vector3::Zero(), 0.0, 0.0);
  EXPECT_TRUE(out.master_limited);
  EXPECT_EQ(out.master_force, Vector3::Zero());
  out = layer.step(kDt, Vector3(-600.0, 0, 0), Vector3::Zero(), -v, Vector3::Zero(), 0.0, 0.0);  // 0.06 J: paid
  EXPECT_FALSE(out.master_limited);
  EXPECT_EQ(out.master_force, Vector3(-600.0, 0, 0));
  double master_before = layer.masterEnergy(), slave_before = layer.slaveEnergy();
  const Vector3 zero = Vector3::Zero();
  for (int i = 0; i < 1000; ++i) layer.step(kDt, zero, zero, zero, zero, 0.0, 0.0);
  EXPECT_NEAR(layer.masterEnergy() - master_before, 1.0, 1e-9);  // P̄ = 1 W for 1 s, from the slave
  EXPECT_NEAR(slave_before - layer.slaveEnergy(), 1.0, 1e-9);
  EXPECT_CONTAINS(cobra::test_support::messageOf([] {
                    PassivityParameters bad;
                    bad.slave.request = 12.0;
                    PassivityLayer l(bad);
                  }),
                  "PassivityLayer: the slave tank needs 0 < minimum < request < available < maximum");
}

TEST(Teleoperation, TheTotalEnergyBalanceHolds) {
  Scenario s;
  const double before = s.energy();
  double t = 0.0;
  s.run(5.0, t);
  // Masses, wall, hold spring and tanks together never gained more than the hand put in; the
  // robots' own damping is what filled the tanks.
  EXPECT_LE(s.energy() - before, s.human_energy + 1e-3);
}

TEST(Teleoperation, LayersAllocateNothing) {
  Scenario s;
  double t = 0.0;
  EXPECT_EQ(cobra::test_support::allocationsDuring([&] { s.run(0.5, t); }), 0);
}

}  // namespace
}  // namespace cobra::control
