// The energy audit of the two-layer teleoperation (thesis §4.5.4) as it is deployed, one
// Passivity layer per side (Franken et al. 2011), over 10^4 seeded random schedules: a surgeon
// moves the master in 6 DoF, the slave meets a stiff, damped environment in half of them, the
// master-slave link delays (0-200 ms, plus up to 10 ms of jitter) and loses (0-20 %) packets in
// both directions (LinkImpairment). As teleoperation_coupling.lua wires it: the master's pose and
// twist cross the link to the slave's side, where the Transparency layer computes both wrenches
// from them and the slave's own state; the slave's side's layer implements the slave's wrench
// with the slave's own twist; the master's wrench crosses the link back to the master's side's
// layer, which implements it with the device's own, undelayed twist; the tanks trade energy only
// in the link's packets (lost with them). The master is a 6-DoF mass-damper stepped as a device
// model is (explicit Euler: it moves with the twist at the period's start); the slave is stepped
// as the admittance is (implicit Euler: it moves with the twist at the period's end).
//
// The claims, with the work measured on the robots' actual motion (the wrench applied over the
// period times the displacement of the period, as a twist·dt), checked at every step of every
// schedule: per side, the energy the layer put into its robot never exceeds its tank's initial
// energy plus what arrived over the link plus the dissipation its robot reported; over the loop,
// what both layers put in never exceeds both tanks' initial energy plus the dissipation. With the
// Passivity layers bypassed (the desired wrenches applied as they arrive), the same audit finds
// violations: the audit can fail.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <random>

#include "cobra/control/link_impairment.hpp"
#include "cobra/control/teleoperation.hpp"
#include "cobra/test_support/counting_new.hpp"

namespace cobra::control {
namespace {

constexpr double kDt = 2e-3;       // s: a 500 Hz loop
constexpr int kSteps = 500;        // 1 s per schedule
constexpr int kSchedules = 10000;
constexpr double kTolerance = 1e-9;  // J: rounding of the sums

Vector3 vector(const KDL::Vector& v) { return {v.x(), v.y(), v.z()}; }
KDL::Vector kdl(const Vector3& v) { return {v.x(), v.y(), v.z()}; }

/// A rigid body with viscous damping on SE(3): mass (kg), inertia (kg·m², isotropic), damping
/// (N·s/m, N·m·s/rad). Twist [v; ω] in the base frame. `implicit`: the twist is updated first
/// and the pose moves with it (the admittance's step), else the pose moves with the twist at the
/// period's start (explicit Euler).
struct Body {
  double mass, inertia, damping, angular_damping;
  KDL::Frame pose;
  bool implicit = false;
  Vector6 twist = Vector6::Zero();

  /// Steps by `dt` (s) under `wrench`; returns the twist the pose moved with (its displacement
  /// over the period is that times dt).
  Vector6 step(const Vector6& wrench, double dt) {
    const Vector6 before = twist;
    if (implicit) {  // (m + dt b) v' = m v + dt F
      twist.head<3>() = (mass * twist.head<3>() + dt * wrench.head<3>()) / (mass + dt * damping);
      twist.tail<3>() = (inertia * twist.tail<3>() + dt * wrench.tail<3>()) / (inertia + dt * angular_damping);
    } else {
      twist.head<3>() += dt / mass * (wrench.head<3>() - damping * twist.head<3>());
      twist.tail<3>() += dt / inertia * (wrench.tail<3>() - angular_damping * twist.tail<3>());
    }
    const Vector6 moved = implicit ? twist : before;
    pose.p += kdl(moved.head<3>()) * dt;
    const Vector3 turn = moved.tail<3>() * dt;
    if (turn.norm() > 0.0) pose.M = KDL::Rotation::Rot2(kdl(turn.normalized()), turn.norm()) * pose.M;
    return moved;
  }
  /// D_i of eq. 4.19, W: what the damping dissipates at this twist (over the period past, for
  /// the implicit step, whose damping acted with it).
  double dissipation() const {
    return damping * twist.head<3>().squaredNorm() + angular_damping * twist.tail<3>().squaredNorm();
  }
};

/// What travels master -> slave: the master's pose and twist, and the master's tank's packet.
struct Forward {
  KDL::Frame pose;
  Vector6 twist = Vector6::Zero();
  EnergyPacket packet;
};
/// What travels slave -> master: the desired master wrench, and the slave's tank's packet.
struct Backward {
  Vector6 wrench = Vector6::Zero();
  EnergyPacket packet;
};

struct Schedule {
  TransparencyParameters coupling;
  PassivitySideParameters master_tank, slave_tank;
  LinkImpairmentParameters to_slave, to_master;
  Vector3 offset, rotation_offset;           // m, rad: master relative to slave at engage
  Vector3 amplitude[2], frequency[2], phase[2];  // the surgeon's motion: translation (m), rotation (rad); Hz; rad
  bool contact;
  Vector3 wall_normal;        // unit: the wall pushes the slave along it
  double wall_distance;       // m: from the slave's start to the wall, along -normal
  double wall_stiffness;      // N/m
  double wall_damping;        // N·s/m
  double wall_torsion;        // N·m/rad: the tissue resists turning while penetrated
  double master_damping;      // N·s/m: the master's own (D_m = b_m |v|² + b_m/100 |ω|²)
  double slave_damping;       // N·s/m: the slave's own (D_s = b_s |v|² + b_s/60 |ω|²)

  explicit Schedule(std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    auto uniform = [&](double low, double high) { return std::uniform_real_distribution<double>(low, high)(rng); };
    auto vector3 = [&](double low, double high) { return Vector3(uniform(low, high), uniform(low, high), uniform(low, high)); };
    coupling.stiffness = uniform(100.0, 800.0);
    coupling.damping = uniform(0.5, 3.0);
    coupling.rotational_stiffness = uniform(0.0, 2.0);
    coupling.rotational_damping = uniform(0.0, 0.2);
    coupling.compensation_time = uniform(0.1, 0.8);
    for (PassivitySideParameters* t : {&master_tank, &slave_tank}) {
      t->tank = TankLevels{0.01, 0.05, 0.1, 0.5, uniform(0.02, 0.1)};  // J: small tanks, so the audit is sharp
    }
    master_tank.transfer_power = slave_tank.transfer_power = uniform(0.1, 2.0);
    master_tank.settle = false;  // the master moves with the twist at the period's start (explicit)
    for (LinkImpairmentParameters* l : {&to_slave, &to_master}) {
      l->delay = uniform(0.0, 0.2);
      l->jitter = uniform(0.0, 0.01);
      l->loss = uniform(0.0, 0.2);
      l->seed = rng();
      l->capacity = 128;  // samples: 210 ms at 2 ms
    }
    offset = vector3(-0.04, 0.04);
    rotation_offset = vector3(-0.3, 0.3);
    for (int i = 0; i < 2; ++i) {
      amplitude[i] = vector3(0.0, i == 0 ? 0.03 : 0.3);
      frequency[i] = vector3(0.2, 2.0);
      phase[i] = vector3(0.0, 6.3);
    }
    contact = uniform(0.0, 1.0) < 0.5;
    wall_normal = vector3(-1.0, 1.0).normalized();
    wall_distance = uniform(0.0, 0.005);
    wall_stiffness = uniform(1000.0, 5000.0);
    wall_damping = uniform(0.0, 20.0);
    wall_torsion = uniform(0.0, 2.0);
    master_damping = uniform(0.1, 1.0);
    slave_damping = uniform(2.0, 10.0);
  }
};

/// What one schedule's audit found.
struct Audit {
  bool side_violated = false;  // a side injected > its initial + received + dissipation at some step
  bool loop_violated = false;  // both injected > both initial + dissipation at some step
  double worst_side_excess = -1e300;  // J: max over steps and sides of injected - bound
  double worst_loop_excess = -1e300;  // J
  double lowest_tank = 1e300;         // J
  double injected[2] = {0.0, 0.0}, dissipation[2] = {0.0, 0.0}, received[2] = {0.0, 0.0};  // J: master, slave
  bool violated() const { return side_violated || loop_violated; }
};

/// The surgeon's hand: a spring-damper (200 N/m, 5 N·s/m; 1 N·m/rad, 0.05 N·m·s/rad) from the
/// master to where the surgeon wants it.
Vector6 hand(const Schedule& s, const KDL::Frame& start, double t, const Body& master) {
  Vector3 p, r, v, w;
  for (int a = 0; a < 3; ++a) {
    const double wt0 = 6.283185307179586 * s.frequency[0](a), wt1 = 6.283185307179586 * s.frequency[1](a);
    p(a) = s.amplitude[0](a) * std::sin(wt0 * t + s.phase[0](a));
    v(a) = s.amplitude[0](a) * wt0 * std::cos(wt0 * t + s.phase[0](a));
    r(a) = s.amplitude[1](a) * std::sin(wt1 * t + s.phase[1](a));
    w(a) = s.amplitude[1](a) * wt1 * std::cos(wt1 * t + s.phase[1](a));
  }
  const KDL::Rotation target = KDL::Rotation::Rot(kdl(r), r.norm()) * start.M;
  Vector6 f;
  f.head<3>() = 200.0 * (vector(start.p) + p - vector(master.pose.p)) + 5.0 * (v - master.twist.head<3>());
  f.tail<3>() = 1.0 * vector(KDL::diff(master.pose.M, target)) + 0.05 * (w - master.twist.tail<3>());
  return f;
}

/// The environment's wrench on the slave: a one-sided wall (spring-damper) that also resists
/// turning (torsion spring about the orientation at first contact) while penetrated.
Vector6 environment(const Schedule& s, const KDL::Frame& start, const Body& slave, KDL::Rotation& contact_rotation,
                    bool& touching) {
  Vector6 f = Vector6::Zero();
  if (!s.contact) return f;
  const double depth = -s.wall_normal.dot(vector(slave.pose.p - start.p)) - s.wall_distance;
  if (depth <= 0.0) {
    touching = false;
    return f;
  }
  if (!touching) contact_rotation = slave.pose.M;
  touching = true;
  const double speed = s.wall_normal.dot(slave.twist.head<3>());
  f.head<3>() = s.wall_normal * std::max(0.0, s.wall_stiffness * depth - s.wall_damping * speed);
  f.tail<3>() = s.wall_torsion * vector(KDL::diff(slave.pose.M, contact_rotation));
  return f;
}

/// One schedule; `passive`: through the Passivity layers, else the desired wrenches as they
/// arrive. Stops once both bounds are violated when bypassed (the answer is known).
Audit run(const Schedule& s, bool passive, long* allocations = nullptr) {
  const KDL::Frame slave_start(KDL::Rotation::RPY(0.3, -0.2, 0.5), KDL::Vector(0.4, 0.0, 0.1));
  const KDL::Frame master_start(
      KDL::Rotation::Rot(kdl(s.rotation_offset), s.rotation_offset.norm()) * slave_start.M,
      slave_start.p + kdl(s.offset));
  Body master{0.3, 0.002, s.master_damping, s.master_damping / 100.0, master_start, false};
  Body slave{2.0, 0.05, s.slave_damping, s.slave_damping / 60.0, slave_start, true};
  TransparencyLayer transparency(s.coupling);  // on the slave's side
  PassivitySide master_side(s.master_tank, "master"), slave_side(s.slave_tank, "slave");
  LinkImpairment<Forward> to_slave(s.to_slave);
  LinkImpairment<Backward> to_master(s.to_master);
  transparency.engage(0.0, master.pose, slave.pose);
  Forward master_seen{master.pose, Vector6::Zero(), EnergyPacket{}};  // the slave's side's last sample of the master
  Backward wrench_seen;              // the master's side's last desired wrench
  KDL::Rotation contact_rotation;
  bool touching = false;
  const double initial[2] = {s.master_tank.tank.initial, s.slave_tank.tank.initial};
  Audit audit;
  const long before = test_support::newCalls();
  for (int k = 0; k < kSteps; ++k) {
    const double t = k * kDt;
    // What arrived by now: each side takes the packets' energy into its tank.
    if (to_slave.receive(t, master_seen)) slave_side.receive(master_seen.packet);
    if (to_master.receive(t, wrench_seen)) master_side.receive(wrench_seen.packet);
    Vector6 master_desired, slave_desired;
    transparency.compute(t, master_seen.pose, master_seen.twist, slave.pose, slave.twist, master_desired,
                         slave_desired);
    const double dm = master.dissipation(), ds = slave.dissipation();
    Vector6 fm = wrench_seen.wrench, fs = slave_desired;
    EnergyPacket from_master, from_slave;
    if (passive) {
      const PassivitySideStep m = master_side.step(kDt, wrench_seen.wrench, master.twist, dm);
      const PassivitySideStep sl = slave_side.step(kDt, slave_desired, slave.twist, ds);
      fm = m.wrench;
      fs = sl.wrench;
      from_master = m.packet;
      from_slave = sl.packet;
      audit.lowest_tank = std::min({audit.lowest_tank, master_side.energy(), slave_side.energy()});
    }
    to_slave.send(t, Forward{master.pose, master.twist, from_master});
    to_master.send(t, Backward{master_desired, from_slave});
    const Vector6 on_master = fm + hand(s, master_start, t, master);
    const Vector6 on_slave = fs + environment(s, slave_start, slave, contact_rotation, touching);
    // The work of the period's wrenches on the robots' actual displacement.
    audit.injected[0] += fm.dot(master.step(on_master, kDt)) * kDt;
    audit.injected[1] += fs.dot(slave.step(on_slave, kDt)) * kDt;
    audit.dissipation[0] += dm * kDt;
    audit.dissipation[1] += ds * kDt;
    audit.received[0] = master_side.received();
    audit.received[1] = slave_side.received();
    for (int side = 0; side < 2; ++side) {
      const double excess = audit.injected[side] - (initial[side] + audit.received[side] + audit.dissipation[side]);
      audit.worst_side_excess = std::max(audit.worst_side_excess, excess);
      if (excess > kTolerance) audit.side_violated = true;
    }
    const double loop = audit.injected[0] + audit.injected[1] -
                        (initial[0] + initial[1] + audit.dissipation[0] + audit.dissipation[1]);
    audit.worst_loop_excess = std::max(audit.worst_loop_excess, loop);
    if (loop > kTolerance) audit.loop_violated = true;
    if (!passive && audit.side_violated && audit.loop_violated) break;
  }
  if (allocations) *allocations = test_support::newCalls() - before;
  return audit;
}

TEST(TeleoperationAudit, ThroughOnePassivityLayerPerSideNoSideAndNotTheLoopInjectsMoreThanItsTanksHold) {
  int limited_schedules = 0, delayed = 0;
  double worst_side = -1e300, worst_loop = -1e300, lowest = 1e300;
  const double epsilon = 0.01;  // J: every schedule's ε
  for (int i = 0; i < kSchedules; ++i) {
    const Schedule s(1000 + static_cast<std::uint64_t>(i));
    long allocations = 0;
    const Audit a = run(s, true, i == 0 ? &allocations : nullptr);
    if (i == 0) {
      EXPECT_EQ(allocations, 0) << "the layers and the link allocate nothing per step";
    }
    worst_side = std::max(worst_side, a.worst_side_excess);
    worst_loop = std::max(worst_loop, a.worst_loop_excess);
    lowest = std::min(lowest, a.lowest_tank);
    delayed += s.to_slave.delay + s.to_master.delay > 0.2;
    if (a.lowest_tank < 0.02) ++limited_schedules;
    ASSERT_FALSE(a.side_violated) << "schedule " << i << ": a side injected " << a.worst_side_excess
                                  << " J more than its tank's initial energy, what it received and its dissipation";
    ASSERT_FALSE(a.loop_violated) << "schedule " << i << ": the loop injected " << a.worst_loop_excess
                                  << " J more than the tanks' initial energy plus the dissipation";
    // ε is where a tank stops paying; settling an implicit step's excess may take it below by
    // that one period's excess (a tank below ε implements nothing more), never to 0: the per-side
    // bound needs the tank's energy >= 0.
    ASSERT_GT(a.lowest_tank, 0.0) << "schedule " << i;
  }
  std::printf("per side: worst margin %.3g J; loop: worst margin %.3g J; lowest tank %.4g J (epsilon %.3g J); %d "
              "schedules drained a tank to within 10 mJ of epsilon; %d with a round trip > 200 ms\n",
              worst_side, worst_loop, lowest, epsilon, limited_schedules, delayed);
  EXPECT_GT(limited_schedules, kSchedules / 20) << "the tanks must be the limit in many schedules, else the audit "
                                                   "would prove little";
}

TEST(TeleoperationAudit, WithThePassivityLayersBypassedTheAuditFindsViolations) {
  int side = 0, loop = 0, delayed_violations = 0, delayed = 0;
  for (int i = 0; i < kSchedules; ++i) {
    const Schedule s(1000 + static_cast<std::uint64_t>(i));
    const bool long_delay = s.to_slave.delay + s.to_master.delay > 0.2;
    const Audit a = run(s, false);
    side += a.side_violated;
    loop += a.loop_violated;
    delayed += long_delay;
    delayed_violations += a.violated() && long_delay;
  }
  std::printf("bypassed: %d of %d schedules violate a side's bound, %d the loop's; %d of the %d with a round trip "
              "> 200 ms violate one\n",
              side, kSchedules, loop, delayed_violations, delayed);
  EXPECT_GT(side, kSchedules / 10);
  EXPECT_GT(loop, kSchedules / 20);
}

}  // namespace
}  // namespace cobra::control
