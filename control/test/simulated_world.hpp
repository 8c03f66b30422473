#pragma once
// Test fixtures of the control tests (not production code): a point mass, a stiff wall and a
// human hand holding a haptic master. Each reports the energy it exchanges, so a test can audit
// the whole loop. SI units throughout: m, m/s, N, kg, J.

#include <Eigen/Core>
#include <algorithm>

namespace cobra::control::test {

/// A point mass with viscous damping (kg, N·s/m), integrated with semi-implicit Euler.
struct PointMass {
  double mass;
  double damping;
  Eigen::Vector3d x = Eigen::Vector3d::Zero();
  Eigen::Vector3d v = Eigen::Vector3d::Zero();

  /// One step of dt s under `force` (N); returns the work the force did over the step (J).
  double step(const Eigen::Vector3d& force, double dt) {
    v += dt * (force - damping * v) / mass;
    x += dt * v;
    return force.dot(v) * dt;
  }
  double kinetic() const { return 0.5 * mass * v.squaredNorm(); }
  /// Power the damping dissipates now, W (D_i of eq. 4.19).
  double dissipation() const { return damping * v.squaredNorm(); }
};

/// A one-sided wall normal to +x at `position` (m) with `stiffness` (N/m): it only pushes back.
struct StiffWall {
  double position;
  double stiffness;

  double penetration(double x) const { return std::max(0.0, x - position); }
  /// Force on a point at x (N, along x).
  double force(double x) const { return -stiffness * penetration(x); }
  /// Elastic energy stored in the wall, J.
  double energy(double x) const { return 0.5 * stiffness * penetration(x) * penetration(x); }
};

/// A surgeon's hand on the master's stylus: the usual grip model of haptics, a spring-damper
/// (grip_stiffness N/m, grip_damping N·s/m) to where the hand is, and a hand that yields to what it
/// feels with a first-order lag of `yield_time` s (a relaxed grip: the hand lets the master be
/// guided). force() is what the hand applies to the master.
struct HumanHand {
  double grip_stiffness = 20.0;
  double grip_damping = 2.0;
  double yield_time = 0.1;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();

  Eigen::Vector3d force(const Eigen::Vector3d& master, const Eigen::Vector3d& master_velocity) const {
    return grip_stiffness * (position - master) - grip_damping * master_velocity;
  }
  /// The hand drifts towards the stylus (the human's own, internally powered motion).
  void yield(const Eigen::Vector3d& master, double dt) { position += dt / yield_time * (master - position); }
};

}  // namespace cobra::control::test
