// The energy audit of the two-layer teleoperation (thesis §4.5.4) over 10^4 seeded random
// schedules: a surgeon moves the master in 6 DoF, the slave meets a stiff, damped environment in
// half of them, the master-slave link delays (0-200 ms, plus up to 10 ms of jitter) and loses
// (0-20 %) samples in both directions (LinkImpairment), and master and slave are 6-DoF
// mass-dampers. Each side has its own Transparency layer (Franken et al. 2011): it couples its
// robot's own state with the other side's state as last received. The claim checked at every
// step of every schedule: the net energy the controller has put into the robots, the sum over
// steps of (F_m·t_m + F_s·t_s)·dt with the implemented wrenches and the robots' twists, never
// exceeds the tanks' initial energy plus the dissipation the robots reported to them; and the
// tanks never go below ε. The same audit with the Passivity layer bypassed (the desired wrenches
// applied as they are) must find violations: the audit can fail.
//
// The robots integrate their pose with the twist at the start of the period (explicit Euler), so
// F·t·dt is exactly the work of the period's constant wrench over the period's displacement.
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
/// (N·s/m, N·m·s/rad). Twist [v; ω] in the base frame.
struct Body {
  double mass, inertia, damping, angular_damping;
  KDL::Frame pose;
  Vector6 twist = Vector6::Zero();

  void step(const Vector6& wrench, double dt) {
    pose.p += kdl(twist.head<3>()) * dt;
    const Vector3 turn = twist.tail<3>() * dt;
    if (turn.norm() > 0.0) pose.M = KDL::Rotation::Rot2(kdl(turn.normalized()), turn.norm()) * pose.M;
    twist.head<3>() += dt / mass * (wrench.head<3>() - damping * twist.head<3>());
    twist.tail<3>() += dt / inertia * (wrench.tail<3>() - angular_damping * twist.tail<3>());
  }
  /// D_i of eq. 4.19, W: what the damping dissipates at this twist.
  double dissipation() const {
    return damping * twist.head<3>().squaredNorm() + angular_damping * twist.tail<3>().squaredNorm();
  }
};

/// What travels on the link: a robot's pose and twist.
struct State {
  KDL::Frame pose;
  Vector6 twist = Vector6::Zero();
};

struct Schedule {
  TransparencyParameters coupling;
  PassivityParameters tanks;
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
    for (TankLevels* t : {&tanks.master, &tanks.slave}) {
      *t = TankLevels{0.01, 0.05, 0.1, 0.5, uniform(0.02, 0.1)};  // J: small tanks, so the audit is sharp
    }
    tanks.transfer_power = uniform(0.1, 2.0);
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
  bool violated = false;     // injected > initial + dissipation at some step
  double worst_excess = -1e300;  // J: max over steps of injected - (initial + dissipation)
  double lowest_tank = 1e300;    // J
  double injected = 0.0, dissipation = 0.0;  // J at the end
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

/// One schedule; `passive`: through the Passivity layer, else the desired wrenches directly.
/// Stops at the first violation when bypassed (the answer is known).
Audit run(const Schedule& s, bool passive, long* allocations = nullptr) {
  const KDL::Frame slave_start(KDL::Rotation::RPY(0.3, -0.2, 0.5), KDL::Vector(0.4, 0.0, 0.1));
  const KDL::Frame master_start(
      KDL::Rotation::Rot(kdl(s.rotation_offset), s.rotation_offset.norm()) * slave_start.M,
      slave_start.p + kdl(s.offset));
  Body master{0.3, 0.002, s.master_damping, s.master_damping / 100.0, master_start};
  Body slave{2.0, 0.05, s.slave_damping, s.slave_damping / 60.0, slave_start};
  TransparencyLayer master_side(s.coupling), slave_side(s.coupling);
  PassivityLayer passivity(s.tanks);
  LinkImpairment<State> to_slave(s.to_slave), to_master(s.to_master);
  master_side.engage(0.0, master.pose, slave.pose);
  slave_side.engage(0.0, master.pose, slave.pose);
  State master_seen{master.pose}, slave_seen{slave.pose};  // each side's last sample of the other
  KDL::Rotation contact_rotation;
  bool touching = false;
  const double initial = s.tanks.master.initial + s.tanks.slave.initial;
  Audit audit;
  const long before = test_support::newCalls();
  for (int k = 0; k < kSteps; ++k) {
    const double t = k * kDt;
    to_slave.send(t, State{master.pose, master.twist});
    to_master.send(t, State{slave.pose, slave.twist});
    to_slave.receive(t, master_seen);
    to_master.receive(t, slave_seen);
    Vector6 master_desired, slave_desired, unused;
    master_side.compute(t, master.pose, master.twist, slave_seen.pose, slave_seen.twist, master_desired, unused);
    slave_side.compute(t, master_seen.pose, master_seen.twist, slave.pose, slave.twist, unused, slave_desired);
    const double dm = master.dissipation(), ds = slave.dissipation();
    Vector6 fm = master_desired, fs = slave_desired;
    if (passive) {
      const PassivityStep out = passivity.step(kDt, master_desired, slave_desired, master.twist, slave.twist, dm, ds);
      fm = out.master_wrench;
      fs = out.slave_wrench;
      audit.lowest_tank = std::min({audit.lowest_tank, passivity.masterEnergy(), passivity.slaveEnergy()});
    }
    audit.injected += (fm.dot(master.twist) + fs.dot(slave.twist)) * kDt;
    audit.dissipation += (dm + ds) * kDt;
    const double excess = audit.injected - (initial + audit.dissipation);
    audit.worst_excess = std::max(audit.worst_excess, excess);
    if (excess > kTolerance) {
      audit.violated = true;
      if (!passive) break;
    }
    const Vector6 on_master = fm + hand(s, master_start, t, master);
    const Vector6 on_slave = fs + environment(s, slave_start, slave, contact_rotation, touching);
    master.step(on_master, kDt);
    slave.step(on_slave, kDt);
  }
  if (allocations) *allocations = test_support::newCalls() - before;
  return audit;
}

TEST(TeleoperationAudit, ThroughThePassivityLayerTheControllerNeverInjectsMoreThanItsTanksHold) {
  int violations = 0, limited_schedules = 0;
  double worst = -1e300, lowest = 1e300;
  const double epsilon = 0.01;  // J: every schedule's ε
  for (int i = 0; i < kSchedules; ++i) {
    const Schedule s(1000 + static_cast<std::uint64_t>(i));
    long allocations = 0;
    const Audit a = run(s, true, i == 0 ? &allocations : nullptr);
    if (i == 0) {
      EXPECT_EQ(allocations, 0) << "the layers and the link allocate nothing per step";
    }
    if (a.violated) ++violations;
    worst = std::max(worst, a.worst_excess);
    lowest = std::min(lowest, a.lowest_tank);
    if (a.lowest_tank < 0.02) ++limited_schedules;
    ASSERT_FALSE(a.violated) << "schedule " << i << ": the controller injected " << a.injected << " J, "
                             << a.worst_excess << " J more than the tanks' initial energy plus the dissipation";
    ASSERT_GE(a.lowest_tank, epsilon - kTolerance) << "schedule " << i;
  }
  std::printf("passive: %d of %d schedules violate the bound (worst margin %.3g J), lowest tank %.4g J, "
              "%d schedules drained a tank to within 10 mJ of epsilon\n",
              violations, kSchedules, worst, lowest, limited_schedules);
  EXPECT_GT(limited_schedules, kSchedules / 20) << "the tanks must be the limit in many schedules, else the audit "
                                                   "would prove little";
}

TEST(TeleoperationAudit, WithThePassivityLayerBypassedTheAuditFindsViolations) {
  int violations = 0, delayed_violations = 0, delayed = 0;
  for (int i = 0; i < kSchedules; ++i) {
    const Schedule s(1000 + static_cast<std::uint64_t>(i));
    const bool long_delay = s.to_slave.delay + s.to_master.delay > 0.2;
    const Audit a = run(s, false);
    violations += a.violated;
    delayed += long_delay;
    delayed_violations += a.violated && long_delay;
  }
  std::printf("bypassed: %d of %d schedules violate the bound; %d of the %d with a round trip > 200 ms\n", violations,
              kSchedules, delayed_violations, delayed);
  EXPECT_GT(violations, kSchedules / 10);  // measured: 2744 of 10^4
}

}  // namespace
}  // namespace cobra::control
