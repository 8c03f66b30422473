#pragma once
/// @file
/// Two-layer passive teleoperation (thesis §4.5.4, eq. 4.12-4.23; Franken, Stramigioli, Misra,
/// Secchi, Macchelli, "Bilateral telemanipulation with time delays: a two-layer approach combining
/// passivity and transparency", IEEE T-RO 2011): the Transparency layer computes the coupling
/// forces a surgeon should feel and the slave should get; the Passivity layer implements them only
/// as far as the master's and the slave's energy tanks can pay. Positions are 3-D (the actuated
/// translation of a Phantom Omni-like master), m; forces N; energies J; powers W.

#include <Eigen/Core>

namespace cobra::control {

using Vector3 = Eigen::Vector3d;

/// Smooth non-increasing step from 1 (s <= 0) to 0 (s >= 1): 1 - (10s³ - 15s⁴ + 6s⁵), C² continuous.
double smoothFall(double s) noexcept;

struct TransparencyParameters {
  double stiffness = 50.0;       ///< K of the PD coupling, N/m (reference value of the literature)
  double damping = 1.1;          ///< B, N·s/m
  double compensation_time = 2.0;  ///< t_c: the rest length l(t) goes from the offset to 0 in it, s
  double error_low = 0.005;      ///< ē1: alpha1 = 1 below it, m
  double error_high = 0.010;     ///< ē2: alpha1 = 0 above it, m
  double rest_low = 0.005;       ///< λ̄1: alpha2 = 1 below it, m
  double rest_high = 0.010;      ///< λ̄2: alpha2 = 0 above it, m
};

/// The Transparency layer (eq. 4.15-4.18). Configure time throws std::invalid_argument naming the
/// parameter; the rest is noexcept and allocation-free.
class TransparencyLayer {
 public:
  explicit TransparencyLayer(const TransparencyParameters& parameters);

  /// Starts teleoperation at `time` (s) with master and slave at `master` and `slave` (m): the
  /// rest length starts at their offset, so nothing jumps.
  void engage(double time, const Vector3& master, const Vector3& slave) noexcept;
  bool engaged() const noexcept { return engaged_; }

  /// Desired forces on master and slave at `time` (eq. 4.15). Before engage: zero.
  void compute(double time, const Vector3& master, const Vector3& master_velocity, const Vector3& slave,
               const Vector3& slave_velocity, Vector3& master_force, Vector3& slave_force) noexcept;

  /// l(t) (m) and alpha(t) of the last compute.
  const Vector3& restLength() const noexcept { return rest_; }
  double alpha() const noexcept { return alpha_; }

 private:
  TransparencyParameters p_;
  bool engaged_ = false;
  bool full_ = false;  // alpha reached 1 (t >= t_M): it stays 1
  double start_ = 0.0;
  Vector3 offset_ = Vector3::Zero();
  Vector3 rest_ = Vector3::Zero();
  double alpha_ = 0.0;
};

/// Energy levels of one tank, J: ε < T_req < T_ava < T̄ (Fig. 4.16).
struct TankLevels {
  double minimum = 1.0;     ///< ε: below it no energy is taken out
  double request = 5.0;     ///< T_req: below it the tank asks the other for energy
  double available = 10.0;  ///< T_ava: above it the tank gives to a tank that asks
  double maximum = 20.0;    ///< T̄: above it the tank stores nothing more
  double initial = 10.0;    ///< T(0)
};

struct PassivityParameters {
  TankLevels master;
  TankLevels slave;
  double transfer_power = 1.0;  ///< P̄: rate of the energy exchange between tanks, W
};

/// What one Passivity layer step did.
struct PassivityStep {
  Vector3 master_force = Vector3::Zero();  ///< implemented F_m, N
  Vector3 slave_force = Vector3::Zero();   ///< implemented F_s, N
  bool master_limited = false;  ///< F_md could not be paid for (F_m = 0)
  bool slave_limited = false;
};

/// The Passivity layer (eq. 4.19-4.23): two tanks, filled by the robots' dissipation and by each
/// other, emptied by the coupling forces they implement. noexcept and allocation-free.
class PassivityLayer {
 public:
  /// @throws std::invalid_argument when the levels are not 0 < ε < T_req < T_ava < T̄ with
  /// ε < T(0) <= T̄, or P̄ <= 0.
  explicit PassivityLayer(const PassivityParameters& parameters);

  /// One period `dt` (s): `master_dissipation` and `slave_dissipation` are the robots' dissipated
  /// powers D_i (W, ≥ 0, e.g. vᵀR v); the velocities are those the forces act on over the period.
  PassivityStep step(double dt, const Vector3& master_desired, const Vector3& slave_desired,
                     const Vector3& master_velocity, const Vector3& slave_velocity, double master_dissipation,
                     double slave_dissipation) noexcept;

  double masterEnergy() const noexcept { return master_; }
  double slaveEnergy() const noexcept { return slave_; }
  /// Energy the tanks let go (stored while full, σ = 0), J: the layer's own dissipation.
  double spilled() const noexcept { return spilled_; }

 private:
  PassivityParameters p_;
  double master_ = 0.0;
  double slave_ = 0.0;
  double spilled_ = 0.0;
};

}  // namespace cobra::control
