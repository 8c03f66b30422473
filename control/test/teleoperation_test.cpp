// Two-layer teleoperation (thesis §4.5.4) with a simulated master (a Phantom Omni-like device
// held by a hand with a grip impedance that yields to what it feels) and a slave pressing on a
// stiff wall: the switch from autonomous to teleoperated with a 5 cm misalignment, reference
// values of the literature (K = 50 N/m, B = 1.1 N·s/m, ē1 = 5 mm, ē2 = 10 mm, ε = 1 J,
// T_req = 5 J, T_ava = 10 J, T̄ = 20 J).
#include "cobra/control/teleoperation.hpp"

#include <gtest/gtest.h>

#include <limits>

#include <Eigen/Geometry>
#include <cmath>
#include <string>

#include "cobra/test_support/counting_new.hpp"
#include "cobra/test_support/test_support.hpp"
#include "simulated_world.hpp"

namespace cobra::control {
namespace {

constexpr double kDt = 1e-3;  // s

KDL::Frame at(const Vector3& p) { return KDL::Frame(KDL::Vector(p.x(), p.y(), p.z())); }
/// A twist or wrench [linear; angular] with only its linear part.
Vector6 linear(const Vector3& v) { return (Vector6() << v, Vector3::Zero()).finished(); }
Vector6 angular(const Vector3& w) { return (Vector6() << Vector3::Zero(), w).finished(); }
const Vector6 kZero = Vector6::Zero();

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
    transparency.engage(0.0, at(master.x), at(slave.x));
  }
  /// Kinetic, elastic (wall and hold spring) and tank energies, J.
  double energy() const {
    const double held = 0.5 * hold_stiffness * (slave.x - slave_at_switch).squaredNorm();
    return master.kinetic() + slave.kinetic() + wall.energy(slave.x.x()) + held + passivity.masterEnergy() +
           passivity.slaveEnergy();
  }
  void run(double seconds, double& t) {
    for (int i = 0; i < static_cast<int>(seconds / kDt); ++i, t += kDt) {
      Vector6 fm, fs;
      transparency.compute(t, at(master.x), linear(master.v), at(slave.x), linear(slave.v), fm, fs);
      const Vector3 hold = -hold_stiffness * (slave.x - slave_at_switch);
      const Vector3 wall_force(wall.force(slave.x.x()), 0, 0);
      const PassivityStep implemented =
          passivity.step(kDt, fm, fs, linear(master.v), linear(slave.v), master.dissipation(), slave.dissipation());
      const Vector3 human = hand.force(master.x, master.v);
      master.step(implemented.master_wrench.head<3>() + human, kDt);
      slave.step(implemented.slave_wrench.head<3>() + wall_force + hold, kDt);
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
  Vector6 fm, fs;
  const KDL::Frame origin = KDL::Frame::Identity();
  layer.compute(0.0, at(Vector3(0.05, 0, 0)), kZero, origin, kZero, fm, fs);
  EXPECT_EQ(fm, kZero);  // not engaged
  layer.engage(0.0, at(Vector3(0.05, 0, 0)), origin);
  layer.compute(0.0, at(Vector3(0.05, 0, 0)), kZero, origin, kZero, fm, fs);
  EXPECT_NEAR(fm.norm(), 0.0, 1e-12);  // rest length = offset at the switch: no force
  EXPECT_EQ(layer.alpha(), 0.0);
  layer.compute(1.0, at(Vector3(0.05, 0, 0)), kZero, origin, kZero, fm, fs);
  EXPECT_NEAR(layer.restLength().x(), 0.025, 1e-12);  // half way through t_c = 2 s
  EXPECT_LT(fm.x(), 0.0);                             // the master is pulled towards the slave...
  EXPECT_EQ(fs.norm(), 0.0);                          // ...the slave feels nothing (e = 5 cm > ē2)
  layer.compute(2.5, at(Vector3(0.004, 0, 0)), kZero, origin, kZero, fm, fs);
  EXPECT_EQ(layer.alpha(), 1.0);  // e = 4 mm < ē1 and l = 0
  EXPECT_NEAR(fs.x(), 50.0 * 0.004, 1e-12);
  layer.compute(3.0, at(Vector3(0.05, 0, 0)), kZero, origin, kZero, fm, fs);
  EXPECT_EQ(layer.alpha(), 1.0);  // once reached, alpha stays 1 (eq. 4.16)
}

TransparencyParameters rotational() {
  TransparencyParameters p;
  p.rotational_stiffness = 2.0;  // N·m/rad
  p.rotational_damping = 0.1;    // N·m·s/rad
  return p;
}

TEST(Teleoperation, TheRotationalRestLengthStartsAtTheOffsetAndVanishesOverTc) {
  TransparencyLayer layer{rotational()};
  // Master turned 0.5 rad about z relative to a slave that is itself turned about x.
  const KDL::Frame slave(KDL::Rotation::RotX(0.3), KDL::Vector(0.1, 0, 0));
  const KDL::Frame master(slave.M * KDL::Rotation::RotZ(0.5), slave.p);
  layer.engage(0.0, master, slave);
  Vector6 fm, fs;
  layer.compute(0.0, master, kZero, slave, kZero, fm, fs);
  EXPECT_NEAR(fm.norm(), 0.0, 1e-12) << "no torque jump at engage";
  EXPECT_NEAR(layer.restRotation().z(), 0.5, 1e-12);  // slave axes: about the slave's own z
  EXPECT_EQ(layer.alpha(), 0.0);  // 0.5 rad > rotation_rest_high
  // A common rotation of master and slave keeps the rest rotation (slave axes): still no torque.
  const KDL::Rotation turn = KDL::Rotation::RPY(0.2, -0.4, 1.0);
  layer.compute(0.0, KDL::Frame(turn * master.M, master.p), kZero, KDL::Frame(turn * slave.M, slave.p), kZero, fm, fs);
  EXPECT_NEAR(fm.norm(), 0.0, 1e-12);
  layer.compute(1.0, master, kZero, slave, kZero, fm, fs);  // half of t_c: half the offset is gone
  const Vector3 axis_z = Vector3(0, -std::sin(0.3), std::cos(0.3));  // the slave's z in the base frame
  EXPECT_NEAR(fm.tail<3>().dot(axis_z), -2.0 * 0.25, 1e-9) << "the master is turned back towards the slave";
  EXPECT_NEAR(fm.tail<3>().cross(axis_z).norm(), 0.0, 1e-9);
  EXPECT_NEAR(fm.head<3>().norm(), 0.0, 1e-12);
  layer.compute(2.0, master, kZero, slave, kZero, fm, fs);
  EXPECT_EQ(layer.restRotation().norm(), 0.0);
  EXPECT_NEAR(fm.tail<3>().dot(axis_z), -2.0 * 0.5, 1e-9);
  EXPECT_EQ(fs.norm(), 0.0) << "alpha = 0: the rotation error (0.5 rad) is above rotation_error_high";
  const KDL::Frame aligned(slave.M * KDL::Rotation::RotZ(0.04), slave.p);  // 0.04 rad < ē_r1
  const Vector6 spin = angular(Vector3(0.0, 0.0, 1.0));
  layer.compute(2.1, aligned, spin, slave, kZero, fm, fs);
  EXPECT_EQ(layer.alpha(), 1.0);
  EXPECT_NEAR(fs.tail<3>().dot(axis_z), 2.0 * 0.04 + 0.1 * axis_z.z(), 1e-9) << "K_r e_r + B_r (ω_m - ω_s)";
  EXPECT_NEAR((fs + fm).norm(), 0.0, 1e-12);
}

TEST(Teleoperation, WithoutRotationalStiffnessTheRotationNeitherCouplesNorWeighsAlpha) {
  TransparencyLayer layer{TransparencyParameters{}};
  const KDL::Frame slave(KDL::Rotation::RotY(2.0), KDL::Vector::Zero());
  layer.engage(0.0, KDL::Frame::Identity(), slave);
  Vector6 fm, fs;
  layer.compute(2.0, KDL::Frame::Identity(), angular(Vector3(1, 0, 0)), slave, kZero, fm, fs);
  EXPECT_EQ(layer.alpha(), 1.0);
  EXPECT_EQ(fm, kZero);
  EXPECT_EQ(fs, kZero);
}

TEST(Teleoperation, TanksRefuseWrenchesTheyCannotPayAndShareEnergyOnRequest) {
  PassivityParameters p;
  p.master.initial = 1.5;  // just above ε
  p.slave.initial = 15.0;  // rich: above T_ava
  PassivityLayer layer(p);
  const Vector6 v = linear(Vector3(0.1, 0, 0));
  // 6000 N against 0.1 m/s for 1 ms costs 0.6 J; the master tank has 0.5 J above ε: refused.
  PassivityStep out = layer.step(kDt, linear(Vector3(-6000.0, 0, 0)), kZero, -v, kZero, 0.0, 0.0);
  EXPECT_TRUE(out.master_limited);
  EXPECT_EQ(out.master_wrench, kZero);
  out = layer.step(kDt, linear(Vector3(-600.0, 0, 0)), kZero, -v, kZero, 0.0, 0.0);  // 0.06 J: paid
  EXPECT_FALSE(out.master_limited);
  EXPECT_EQ(out.master_wrench, linear(Vector3(-600.0, 0, 0)));
  double master_before = layer.masterEnergy(), slave_before = layer.slaveEnergy();
  for (int i = 0; i < 1000; ++i) layer.step(kDt, kZero, kZero, kZero, kZero, 0.0, 0.0);
  EXPECT_NEAR(layer.masterEnergy() - master_before, 1.0, 1e-9);  // P̄ = 1 W for 1 s, from the slave
  EXPECT_NEAR(slave_before - layer.slaveEnergy(), 1.0, 1e-9);
}

TEST(Teleoperation, ATankPaysForTheWholePowerPortTorqueTimesAngularVelocityToo) {
  PassivityLayer layer{PassivityParameters{}};  // both tanks at 10 J: no exchange (neither asks)
  // 20 N·m with 2 rad/s for 1 ms costs 0.04 J; a force across the motion costs nothing.
  const Vector6 wrench = (Vector6() << 0.0, 5.0, 0.0, 0.0, 0.0, 20.0).finished();
  const Vector6 twist = (Vector6() << 0.3, 0.0, 0.0, 0.0, 0.0, 2.0).finished();
  const PassivityStep out = layer.step(kDt, kZero, wrench, kZero, twist, 0.0, 0.0);
  EXPECT_EQ(out.slave_wrench, wrench);
  EXPECT_NEAR(layer.slaveEnergy(), 10.0 - 0.04, 1e-12);
  // A torque braking the rotation gives its energy to the tank.
  layer.step(kDt, kZero, -wrench, kZero, twist, 0.0, 0.0);
  EXPECT_NEAR(layer.slaveEnergy(), 10.0, 1e-12);
  // 9 J above ε are there, a torque that would cost 10 J is refused whole (its force too).
  const Vector6 huge = (Vector6() << 1.0, 0.0, 0.0, 0.0, 0.0, 5000.0).finished();
  const PassivityStep refused = layer.step(kDt, kZero, huge, kZero, twist, 0.0, 0.0);
  EXPECT_TRUE(refused.slave_limited);
  EXPECT_EQ(refused.slave_wrench, kZero);
}

// A NaN (a sensor's, a bad twist) is refused, never paid: the tanks stay finite and go on
// limiting afterwards; a NaN or negative dissipation adds nothing.
TEST(Teleoperation, ANonFiniteWrenchTwistOrDissipationNeverReachesATank) {
  PassivityLayer layer{PassivityParameters{}};
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const Vector6 v = linear(Vector3(0.1, 0, 0));
  PassivityStep out = layer.step(kDt, linear(Vector3(nan, 0, 0)), kZero, v, kZero, 0.0, 0.0);
  EXPECT_TRUE(out.master_limited);
  EXPECT_EQ(out.master_wrench, kZero);
  out = layer.step(kDt, kZero, linear(Vector3(1.0, 0, 0)), kZero, linear(Vector3(nan, 0, 0)), 0.0, 0.0);
  EXPECT_TRUE(out.slave_limited);
  EXPECT_EQ(out.slave_wrench, kZero);
  layer.step(kDt, kZero, kZero, kZero, kZero, nan, -5.0);
  layer.step(kDt, kZero, kZero, kZero, kZero, std::numeric_limits<double>::infinity(), 0.0);
  EXPECT_DOUBLE_EQ(layer.masterEnergy(), 10.0);
  EXPECT_DOUBLE_EQ(layer.slaveEnergy(), 10.0);
  // Still limiting: 9 J above ε, a wrench costing 10 J is refused.
  out = layer.step(kDt, linear(Vector3(1e5, 0, 0)), kZero, v, kZero, 0.0, 0.0);
  EXPECT_TRUE(out.master_limited);
}

// A rich tank feeds one that asks at P̄, but never below its own ε, however long the period.
TEST(Teleoperation, ATankThatGivesNeverGoesBelowItsMinimum) {
  PassivityParameters p;
  p.master.initial = 2.0;   // asks (below T_req = 5 J)
  p.slave.initial = 10.0;   // gives (at T_ava = 10 J)
  p.transfer_power = 1.0;
  PassivityLayer layer(p);
  layer.step(100.0, kZero, kZero, kZero, kZero, 0.0, 0.0);  // P̄·dt = 100 J > T_s - ε = 9 J
  EXPECT_DOUBLE_EQ(layer.slaveEnergy(), p.slave.minimum);
  EXPECT_DOUBLE_EQ(layer.masterEnergy(), 11.0);
}

// The master's tank pays for the wrench the device renders: a Phantom Omni's 3.3 N and no torque.
TEST(Teleoperation, TheMasterTankPaysForWhatTheDeviceRendersOnly) {
  PassivityParameters p;
  p.master_max_force = 3.3;
  p.master_max_torque = 0.0;
  PassivityLayer layer(p);
  const Vector6 desired = (Vector6() << 10.0, 0.0, 0.0, 0.0, 0.0, 2.0).finished();  // N, N·m
  const Vector6 twist = (Vector6() << 0.1, 0.0, 0.0, 0.0, 0.0, 1.0).finished();     // m/s, rad/s
  const PassivityStep out = layer.step(kDt, desired, kZero, twist, kZero, 0.0, 0.0);
  EXPECT_FALSE(out.master_limited);
  EXPECT_NEAR(out.master_wrench(0), 3.3, 1e-12);
  EXPECT_EQ(out.master_wrench(5), 0.0);
  EXPECT_NEAR(layer.masterEnergy(), 10.0 - 3.3 * 0.1 * kDt, 1e-12);  // not 10 N·0.1 m/s + 2 N·m·1 rad/s
  p.master_max_torque = -1.0;
  EXPECT_THROW(
      {
        try {
          PassivityLayer bad(p);
        } catch (const std::invalid_argument& e) {
          EXPECT_STREQ(e.what(), "PassivityLayer: master_max_torque = -1 N·m: must be >= 0 (the torque the master "
                                 "device renders)");
          throw;
        }
      },
      std::invalid_argument);
}

TEST(Teleoperation, BadParametersNameTheParameterAndTheRule) {
  using test_support::messageOf;
  auto transparency = [](auto change) {
    return messageOf([&] {
      TransparencyParameters p;
      change(p);
      TransparencyLayer layer(p);
    });
  };
  auto passivity = [](auto change) {
    return messageOf([&] {
      PassivityParameters p;
      change(p);
      PassivityLayer layer(p);
    });
  };
  EXPECT_EQ(transparency([](auto& p) { p.stiffness = -1.0; }), "TransparencyLayer: stiffness = -1 N/m: must be > 0");
  EXPECT_EQ(transparency([](auto& p) { p.rotational_stiffness = -2.0; }),
            "TransparencyLayer: rotational_stiffness = -2 N·m/rad: must be >= 0");
  EXPECT_EQ(transparency([](auto& p) { p.rotational_damping = -0.5; }),
            "TransparencyLayer: rotational_damping = -0.5 N·m·s/rad: must be >= 0");
  EXPECT_EQ(transparency([](auto& p) { p.rotation_error_high = 0.01; }),
            "TransparencyLayer: rotation_error_high = 0.01 rad: must be > rotation_error_low = 0.05 rad");
  EXPECT_EQ(transparency([](auto& p) { p.rest_high = 0.001; }),
            "TransparencyLayer: rest_high = 0.001 m: must be > rest_low = 0.005 m");
  const std::string rule = " (0 < minimum < request < available < maximum, minimum < initial <= maximum)";
  EXPECT_EQ(passivity([](auto& p) { p.slave.request = 12.0; }),
            "PassivityLayer: slave_available = 10 J: must be > slave_request = 12 J" + rule);
  EXPECT_EQ(passivity([](auto& p) { p.master.minimum = 0.0; }), "PassivityLayer: master_minimum = 0 J: must be > 0" + rule);
  EXPECT_EQ(passivity([](auto& p) { p.master.request = 0.5; }),
            "PassivityLayer: master_request = 0.5 J: must be > master_minimum = 1 J" + rule);
  EXPECT_EQ(passivity([](auto& p) { p.slave.maximum = 9.0; }),
            "PassivityLayer: slave_maximum = 9 J: must be > slave_available = 10 J" + rule);
  EXPECT_EQ(passivity([](auto& p) { p.slave.initial = 25.0; }),
            "PassivityLayer: slave_initial = 25 J: must be in (slave_minimum, slave_maximum] = (1, 20] J" + rule);
  EXPECT_EQ(passivity([](auto& p) { p.transfer_power = 0.0; }),
            "PassivityLayer: transfer_power = 0 W: must be > 0 (P̄, the rate of the exchange between the tanks)");
  EXPECT_EQ(passivity([](auto& p) { p.transfer_power = -3.0; }),
            "PassivityLayer: transfer_power = -3 W: must be > 0 (P̄, the rate of the exchange between the tanks)");
}

// One side's layer (as deployed, one per side): the tanks trade energy only in packets; what a
// packet carries left the sender when sent, and a packet lost on the way takes it along.
TEST(Teleoperation, PassivitySidesTradeEnergyOnlyInPacketsAndALostPacketsEnergyIsGone) {
  PassivitySideParameters poor, rich;
  poor.tank.initial = 2.0;   // J: below T_req = 5 J: asks
  rich.tank.initial = 15.0;  // J: above T_ava = 10 J: gives, to one that asks
  PassivitySide master(poor, "master"), slave(rich, "slave");
  PassivitySideStep m = master.step(kDt, kZero, kZero, 0.0);
  EXPECT_TRUE(m.packet.request);
  EXPECT_EQ(m.packet.energy, 0.0);
  PassivitySideStep s = slave.step(kDt, kZero, kZero, 0.0);
  EXPECT_EQ(s.packet.energy, 0.0) << "the request has not arrived";
  EXPECT_FALSE(s.packet.request);
  slave.receive(m.packet);
  s = slave.step(kDt, kZero, kZero, 0.0);
  EXPECT_DOUBLE_EQ(s.packet.energy, 1e-3);  // P̄ = 1 W for 1 ms
  EXPECT_DOUBLE_EQ(slave.energy(), 15.0 - 1e-3) << "sent: gone from the sender at once";
  // That packet is lost; the next arrives.
  s = slave.step(kDt, kZero, kZero, 0.0);
  master.receive(s.packet);
  EXPECT_DOUBLE_EQ(master.energy(), 2.0 + 1e-3);
  EXPECT_DOUBLE_EQ(master.received(), 1e-3);
  EXPECT_DOUBLE_EQ(slave.sent(), 2e-3);
  EXPECT_NEAR(master.energy() + slave.energy(), 17.0 - 1e-3, 1e-12) << "the lost packet's energy is gone";
  // A packet's energy that is not finite and >= 0 adds nothing; its request still counts.
  master.receive(EnergyPacket{std::numeric_limits<double>::quiet_NaN(), false});
  master.receive(EnergyPacket{-4.0, false});
  EXPECT_DOUBLE_EQ(master.energy(), 2.0 + 1e-3);
  slave.receive(EnergyPacket{0.0, false});
  EXPECT_EQ(slave.step(kDt, kZero, kZero, 0.0).packet.energy, 0.0) << "the request ended";
}

// A tank above T̄ stores nothing: what arrives is spilled, what its robot dissipates goes on to
// the other side in its packet.
TEST(Teleoperation, AFullSideSpillsWhatArrivesAndPassesItsDissipationOn) {
  PassivitySideParameters p;
  p.tank.initial = 20.0;
  PassivitySide side(p, "slave");
  side.receive(EnergyPacket{0.5, false});  // 20 J <= T̄: stored
  EXPECT_DOUBLE_EQ(side.energy(), 20.5);
  side.receive(EnergyPacket{0.25, false});  // above T̄: spilled
  EXPECT_DOUBLE_EQ(side.energy(), 20.5);
  EXPECT_DOUBLE_EQ(side.spilled(), 0.25);
  const PassivitySideStep out = side.step(kDt, kZero, kZero, 30.0);  // 30 W for 1 ms
  EXPECT_DOUBLE_EQ(out.packet.energy, 0.03);
  EXPECT_DOUBLE_EQ(side.energy(), 20.5);
}

// The tank pays F·t·dt with the twist at the period's start; a robot whose step moved with the
// twist at its end (the admittance's implicit step) did F·t_end·dt: the excess is paid at the
// next step, a shortfall is not refunded (an explicit step did the former).
TEST(Teleoperation, ASidePaysTheExcessOfAStepThatMovedWithItsEndTwist) {
  PassivitySide side(PassivitySideParameters{}, "slave");
  const Vector6 push = linear(Vector3(10.0, 0, 0));
  side.step(kDt, push, linear(Vector3(0.1, 0, 0)), 0.0);
  EXPECT_NEAR(side.energy(), 10.0 - 10.0 * 0.1 * kDt, 1e-12);
  side.step(kDt, kZero, linear(Vector3(0.3, 0, 0)), 0.0);  // it moved at 0.3 m/s: 2 mJ more
  EXPECT_NEAR(side.energy(), 10.0 - 10.0 * 0.3 * kDt, 1e-12);
  EXPECT_NEAR(side.paid(), 10.0 * 0.3 * kDt, 1e-12);
  side.step(kDt, kZero, linear(Vector3(-1.0, 0, 0)), 0.0);  // no wrench last period: nothing
  EXPECT_NEAR(side.energy(), 10.0 - 10.0 * 0.3 * kDt, 1e-12);
  side.step(kDt, push, linear(Vector3(0.2, 0, 0)), 0.0);
  side.step(kDt, kZero, linear(Vector3(0.1, 0, 0)), 0.0);  // slower than paid for: no refund
  EXPECT_NEAR(side.energy(), 10.0 - 10.0 * 0.5 * kDt, 1e-12);
}

// A master that renders nothing (a hand tracker: max_force = max_torque = 0) implements no
// wrench and pays nothing, however large the desired one; its tank still trades energy.
TEST(Teleoperation, AMasterThatRendersNothingPaysNothing) {
  PassivitySideParameters p;
  p.max_force = 0.0;
  p.max_torque = 0.0;
  PassivitySide side(p, "master");
  const Vector6 desired = (Vector6() << 30.0, -5.0, 2.0, 0.0, 1.0, 0.0).finished();
  const Vector6 twist = (Vector6() << 0.2, -0.1, 0.0, 0.0, 1.0, 0.0).finished();
  for (int i = 0; i < 100; ++i) {
    const PassivitySideStep out = side.step(kDt, desired, twist, 0.0);
    EXPECT_FALSE(out.limited);
    EXPECT_EQ(out.wrench, kZero);
  }
  EXPECT_DOUBLE_EQ(side.energy(), 10.0);
  EXPECT_DOUBLE_EQ(side.paid(), 0.0);
}

// One side's component names its own properties (minimum, ...: no master_/slave_ prefix).
TEST(Teleoperation, ASidesBadParametersNameItsOwnPropertiesAndTheRule) {
  using test_support::messageOf;
  auto side = [](auto change) {
    return messageOf([&] {
      PassivitySideParameters p;
      change(p);
      PassivitySide layer(p, "");
    });
  };
  const std::string rule = " (0 < minimum < request < available < maximum, minimum < initial <= maximum)";
  EXPECT_EQ(side([](auto& p) { p.tank.request = 0.5; }), "PassivityLayer: request = 0.5 J: must be > minimum = 1 J" + rule);
  EXPECT_EQ(side([](auto& p) { p.tank.initial = 0.5; }),
            "PassivityLayer: initial = 0.5 J: must be in (minimum, maximum] = (1, 20] J" + rule);
  EXPECT_EQ(side([](auto& p) { p.max_force = -2.0; }),
            "PassivityLayer: max_force = -2 N: must be >= 0 (the force its robot renders)");
  EXPECT_EQ(side([](auto& p) { p.transfer_power = 0.0; }),
            "PassivityLayer: transfer_power = 0 W: must be > 0 (P̄, the rate of the exchange between the tanks)");
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
  // The SE(3) path: rotation error, rest rotation, 6-D power port.
  TransparencyLayer layer{rotational()};
  PassivityLayer passivity{PassivityParameters{}};
  const KDL::Frame slave(KDL::Rotation::RotY(0.2), KDL::Vector(0.1, 0, 0));
  layer.engage(0.0, KDL::Frame(KDL::Rotation::RotZ(0.3), KDL::Vector::Zero()), slave);
  EXPECT_EQ(cobra::test_support::allocationsDuring([&] {
              for (int i = 0; i < 3000; ++i) {
                Vector6 fm, fs;
                const KDL::Frame master(KDL::Rotation::RotZ(0.3 - 1e-4 * i), KDL::Vector(1e-5 * i, 0, 0));
                layer.compute(i * kDt, master, angular(Vector3(0, 0, -0.1)), slave, kZero, fm, fs);
                passivity.step(kDt, fm, fs, angular(Vector3(0, 0, -0.1)), kZero, 0.0, 0.0);
              }
            }),
            0);
}

}  // namespace
}  // namespace cobra::control
