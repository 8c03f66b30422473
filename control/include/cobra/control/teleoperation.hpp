#pragma once
/// @file
/// Two-layer passive teleoperation (thesis §4.5.4, eq. 4.12-4.23; Franken, Stramigioli, Misra,
/// Secchi, Macchelli, "Bilateral telemanipulation with time delays: a two-layer approach combining
/// passivity and transparency", IEEE T-RO 2011): the Transparency layer computes the coupling
/// forces a surgeon should feel and the slave should get; the Passivity layer implements them only
/// as far as the master's and the slave's energy tanks can pay. Both layers work on SE(3): poses
/// are KDL frames (m), twists and wrenches 6-vectors [linear; angular] in the base frame (m/s,
/// rad/s; N, N·m), so the power a wrench does on a twist is their full dot product (force·v +
/// torque·ω). Energies J; powers W.

#include <Eigen/Core>
#include <limits>
#include <string>
#include <kdl/frames.hpp>

namespace cobra::control {

using Vector3 = Eigen::Vector3d;
using Vector6 = Eigen::Matrix<double, 6, 1>;  ///< [linear; angular], base frame

/// Smooth non-increasing step from 1 (s <= 0) to 0 (s >= 1): 1 - (10s³ - 15s⁴ + 6s⁵), C² continuous.
double smoothFall(double s) noexcept;

/// The layer's parameter names are those of the TransparencyLayer component's properties.
struct TransparencyParameters {
  double stiffness = 50.0;       ///< K of the PD coupling, N/m (reference value of the literature)
  double damping = 1.1;          ///< B, N·s/m
  /// K_r, N·m/rad (>= 0). 0: the rotation is not coupled (a 3-DoF master such as the Phantom
  /// Omni, which actuates no wrist; its simulation measures no stylus rotation): no rotational
  /// spring, and the rotation errors do not weigh alpha.
  double rotational_stiffness = 0.0;
  double rotational_damping = 0.0;  ///< B_r, N·m·s/rad (>= 0)
  double compensation_time = 2.0;  ///< t_c: the rest length l(t) goes from the offset to 0 in it, s
  double error_low = 0.005;      ///< ē1: alpha1 = 1 below it, m
  double error_high = 0.010;     ///< ē2: alpha1 = 0 above it, m
  double rest_low = 0.005;       ///< λ̄1: alpha2 = 1 below it, m
  double rest_high = 0.010;      ///< λ̄2: alpha2 = 0 above it, m
  double rotation_error_low = 0.05;   ///< ē1 of the rotation error angle, rad (about 3°)
  double rotation_error_high = 0.10;  ///< ē2 of the rotation error angle, rad
  double rotation_rest_low = 0.05;    ///< λ̄1 of the rest rotation angle, rad
  double rotation_rest_high = 0.10;   ///< λ̄2 of the rest rotation angle, rad
};

/// The Transparency layer (eq. 4.15-4.18) on SE(3). The coupling wrench is a PD on the pose
/// error: translation K (p_m - p_s - l(t)) + B (v_m - v_s); rotation K_r e_r + B_r (ω_m - ω_s)
/// with e_r the rotation vector (base frame axes, rad) from R_s Exp(φ_l(t)) to R_m (KDL::diff),
/// where φ_l(t) = φ_L·f(t) is the rotational rest length: φ_L = log(R_sᵀ R_m) at engage (slave
/// axes, so a common rotation of master and slave does not change it), shrunk to 0 over t_c by
/// the same smoothFall f as the translation's l(t). So at engage the whole coupling's spring part
/// is zero, and from t_s + t_c on the slave is pulled onto the master's pose. alpha = alpha1·alpha2
/// until it first reaches 1 (t_M), then 1; alpha1 = w(|p_m - p_s|; ē1, ē2)·w(angle(R_sᵀR_m); ē_r1,
/// ē_r2), alpha2 = w(|l|; λ̄1, λ̄2)·w(|φ_l|; λ̄_r1, λ̄_r2), the rotation factors only when
/// rotational_stiffness > 0. Configure time throws std::invalid_argument naming the parameter;
/// the rest is noexcept and allocation-free.
class TransparencyLayer {
 public:
  explicit TransparencyLayer(const TransparencyParameters& parameters);

  /// Starts teleoperation at `time` (s) with master and slave at `master` and `slave`: the rest
  /// lengths start at their offset, so nothing jumps.
  void engage(double time, const KDL::Frame& master, const KDL::Frame& slave) noexcept;
  bool engaged() const noexcept { return engaged_; }

  /// Desired wrenches on master and slave at `time` (eq. 4.15), from the poses and twists
  /// ([v; ω], base frame). Before engage: zero.
  void compute(double time, const KDL::Frame& master, const Vector6& master_twist, const KDL::Frame& slave,
               const Vector6& slave_twist, Vector6& master_wrench, Vector6& slave_wrench) noexcept;

  /// l(t) (m, base frame), φ_l(t) (rad, slave axes) and alpha(t) of the last compute.
  const Vector3& restLength() const noexcept { return rest_; }
  const Vector3& restRotation() const noexcept { return rest_rotation_; }
  double alpha() const noexcept { return alpha_; }

 private:
  TransparencyParameters p_;
  bool engaged_ = false;
  bool full_ = false;  // alpha reached 1 (t >= t_M): it stays 1
  double start_ = 0.0;
  Vector3 offset_ = Vector3::Zero();
  Vector3 rest_ = Vector3::Zero();
  Vector3 rotation_offset_ = Vector3::Zero();
  Vector3 rest_rotation_ = Vector3::Zero();
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

/// One side's Passivity layer (Franken et al. 2011): its tank and what its robot renders.
struct PassivitySideParameters {
  TankLevels tank;
  double transfer_power = 1.0;  ///< P̄: the most this tank sends the other per second, W
  /// What the robot renders (N, N·m; infinity: all): a desired wrench is cut to it before the
  /// tank pays, so the tank pays for the wrench the robot exerts, not for one it cannot (a Phantom
  /// Omni saturates at 3.3 N and actuates no wrist: torque 0; a hand tracker renders nothing: 0
  /// and 0). Paying for, or being credited with, work nobody does would make the bound a fiction.
  double max_force = std::numeric_limits<double>::infinity();
  double max_torque = std::numeric_limits<double>::infinity();
  /// Pay, at the next period, the excess work of a robot step that moved with the twist at the
  /// period's end (an implicit step, as the VariableAdmittance's). True: the tank has paid at least
  /// the work done whichever step the robot takes (the safe default); false for a robot known to
  /// move with the twist at the period's start (explicit Euler), where the excess is no work.
  bool settle = true;
};

/// What crosses the link from one side's tank to the other's, once per period, with the side's
/// other data (Franken et al. 2011, "energy exchange"): the energy the sender took out of its tank
/// for the receiver (it left the sender when sent, reaches the receiver delayed, and is gone when
/// the packet is lost: energy is never created) and whether the sender's tank asks for energy.
struct EnergyPacket {
  double energy = 0.0;   ///< J, >= 0
  bool request = false;  ///< the sender's tank is below its T_req
};

/// What one step of one side's Passivity layer did.
struct PassivitySideStep {
  Vector6 wrench = Vector6::Zero();  ///< implemented wrench on this side's robot, [N; N·m]
  bool limited = false;              ///< the desired wrench could not be paid for (wrench = 0)
  EnergyPacket packet;               ///< to send to the other side this period
};

/// One side's Passivity layer (thesis eq. 4.19-4.23 split per side as Franken et al. 2011 do
/// it: a layer next to each robot, with that robot's tank, paying with that robot's own,
/// undelayed twist). Per period: the tank stores what its robot dissipated (D·dt, while at most
/// T̄; a full tank passes it on to the other), pays F·t·dt for the wrench it implements (force·v +
/// torque·ω, with t the robot's twist at the period's start) and refuses the whole wrench when that
/// would take it below ε; a robot whose step moves with the twist at the period's end (an
/// implicit integration such as the admittance's) did F·t_end·dt instead: the next step pays the
/// excess (settle), so the tank has paid at least the work done for both kinds of step. A tank
/// at or above T_ava sends the other, while that one asks (its last packet said so), P̄·dt per
/// period, never below its own ε. Packets are taken by receive(), in any number per period.
/// noexcept and allocation-free after construction.
class PassivitySide {
 public:
  /// `name` prefixes the levels in messages ("master" -> master_minimum; "": minimum, the
  /// PassivityLayer component's own properties). @throws std::invalid_argument when the levels are
  /// not 0 < ε < T_req < T_ava < T̄ with ε < T(0) <= T̄, P̄ <= 0 or a limit < 0: the message names
  /// the level or parameter and the rule it breaks.
  PassivitySide(const PassivitySideParameters& parameters, const std::string& name);

  /// A packet from the other side arrived: its energy fills the tank (spilled when the tank is
  /// above T̄; a packet energy that is not finite and >= 0 adds nothing), its request is the other
  /// side's state until the next packet.
  void receive(const EnergyPacket& packet) noexcept;

  /// One period `dt` (s): `desired` the Transparency layer's wrench for this robot, `twist` the
  /// robot's twist now ([m/s; rad/s], the wrench's frame), `dissipation` the power its damping
  /// dissipated over the last period (W, >= 0; else nothing is stored).
  PassivitySideStep step(double dt, const Vector6& desired, const Vector6& twist, double dissipation) noexcept;

  double energy() const noexcept { return energy_; }      ///< the tank, J
  bool requesting() const noexcept { return energy_ < p_.tank.request; }
  double sent() const noexcept { return sent_; }          ///< J sent in packets since construction
  double received() const noexcept { return received_; }  ///< J received (stored or spilled)
  double spilled() const noexcept { return spilled_; }    ///< J let go while above T̄
  double paid() const noexcept { return paid_; }          ///< J paid for wrenches (net)
  double credited() const noexcept { return credited_; }  ///< J of dissipation stored or passed on

 private:
  PassivitySideParameters p_;
  double energy_ = 0.0;
  bool peer_request_ = false;
  Vector6 last_wrench_ = Vector6::Zero();  // implemented last period, [N; N·m]
  Vector6 last_twist_ = Vector6::Zero();   // the twist it was paid with
  double last_dt_ = 0.0;                   // s
  double sent_ = 0.0, received_ = 0.0, spilled_ = 0.0, paid_ = 0.0, credited_ = 0.0;
};

struct PassivityParameters {
  TankLevels master;
  TankLevels slave;
  double transfer_power = 1.0;  ///< P̄: rate of the exchange between tanks, W
  /// What the master device renders (N, N·m; infinity: all), as PassivitySideParameters::max_force.
  double master_max_force = std::numeric_limits<double>::infinity();
  double master_max_torque = std::numeric_limits<double>::infinity();
};

/// What one Passivity layer step did.
struct PassivityStep {
  Vector6 master_wrench = Vector6::Zero();  ///< implemented F_m, [N; N·m]
  Vector6 slave_wrench = Vector6::Zero();   ///< implemented F_s, [N; N·m]
  bool master_limited = false;  ///< F_md could not be paid for (F_m = 0: the whole wrench)
  bool slave_limited = false;
};

/// Both sides' Passivity layers where master and slave run in one loop with no link between
/// them (a simulation, a bench): the two PassivitySides with their packets handed over in the
/// same step. A deployment whose master and slave are apart over a link runs one PassivitySide
/// on each side instead (component PassivityLayer; the exchange then crosses the link).
class PassivityLayer {
 public:
  /// @throws std::invalid_argument as PassivitySide, naming the level as master_request, ...
  explicit PassivityLayer(const PassivityParameters& parameters);

  /// One period `dt` (s): `master_dissipation` and `slave_dissipation` are the robots' dissipated
  /// powers D_i (W, ≥ 0, e.g. tᵀR t); the twists ([m/s; rad/s], base frame, as the wrenches) are
  /// the robots' now.
  PassivityStep step(double dt, const Vector6& master_desired, const Vector6& slave_desired,
                     const Vector6& master_twist, const Vector6& slave_twist, double master_dissipation,
                     double slave_dissipation) noexcept;

  double masterEnergy() const noexcept { return master_.energy(); }
  double slaveEnergy() const noexcept { return slave_.energy(); }
  /// Energy the tanks let go (stored while full), J: the layer's own dissipation.
  double spilled() const noexcept { return master_.spilled() + slave_.spilled(); }

 private:
  PassivitySide master_, slave_;
};

}  // namespace cobra::control
