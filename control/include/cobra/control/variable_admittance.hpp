#pragma once
/// @file
/// Tank-based variable admittance (thesis §4.5.3, eq. 4.1-4.11; Ferraguti, Secchi, Fantuzzi, "A
/// tank-based approach to impedance control with variable stiffness", ICRA 2013, and the variable
/// admittance of Ferraguti et al., IROS 2015).
///
/// The interaction model Λd(t) ẍ̃ + D(t) ẋ̃ + Kd(t) x̃ = F_ext, with Λd = Λc + Λv(t) and
/// Kd = Kc + Kv(t), is the port-Hamiltonian system of the constant parts (Λc, D, Kc) driven by
/// F_ext and by w = -Kv x̃ - Λv ẍ̃ (eq. 4.10-4.11); w is applied only when the energy tank can pay
/// for it, so the controlled system stays passive whatever the schedule of Λd(t), Kd(t).
///
/// State: x̃ = (position error in m, rotation error as exponential coordinates in rad, in the
/// reference frame's axes), ẋ̃ its rate (m/s, rad/s). Output pose: p = p_ref + x̃_p,
/// R = R_ref Exp(x̃_r): always a rotation (SO(3)), never Euler angles. The torque enters as the
/// generalised force J_l(x̃_r)ᵀ τ (J_l: left Jacobian of SO(3), τ in the reference's axes), so the
/// power port (F_ext, ẋ̃) is the physical one (wrench, relative twist) at any rotation error < π.
///
/// Discretisation (and why the discrete energy balance holds): one step of dt is backward Euler,
///   (M + dt D + dt² K) v' = M v + dt (F - K x),  x' = x + dt v',
/// with M = Λd, K = Kd when the variable parts are applied, else Λc, Kc. Seen from the constant
/// parts, that is backward Euler on (Λc, D, Kc) driven by F + w with w = -Kv x' - Λv (v' - v)/dt,
/// and for backward Euler H_c(x', v') - H_c(x, v) = (F + w)ᵀΔx - dt v'ᵀDv' - N with N ≥ 0 (its
/// numerical dissipation). The step's dissipated energy δ = (F + w)ᵀΔx - ΔH_c = dt v'ᵀDv' + N
/// is therefore ≥ 0, the tank gets σδ - wᵀΔx (eq. 4.6 with u_tᵀy_t = -wᵀΔx), and over every step
///   ΔH_c + ΔT = FᵀΔx - (1 - σ)δ ≤ FᵀΔx:
/// the energy the controller gives back to the environment never exceeds what it received plus
/// the initial tank. A step whose w would take the tank below ε is recomputed with w = 0 (eq.
/// 4.11), so T ≥ ε always. σ = 1 while T ≤ T̄ (eq. 4.7).

#include <cstdint>

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <kdl/frames.hpp>

namespace cobra::control {

using Vector6 = Eigen::Matrix<double, 6, 1>;
using Matrix6 = Eigen::Matrix<double, 6, 6>;

/// Energy tank bounds (J).
struct TankParameters {
  double initial_energy = 5.0;  ///< T(0), J (> min_energy)
  double max_energy = 20.0;     ///< T̄: above it the tank stops storing (σ = 0), J
  double min_energy = 1.0;      ///< ε: the tank never goes below it, J (> 0)
};

/// Configure-time description. Matrices are [translation; rotation]: kg and kg·m² (inertia),
/// N·s/m and N·m·s/rad (damping), N/m and N·m/rad (stiffness); symmetric positive definite.
struct AdmittanceParameters {
  Matrix6 constant_inertia = Matrix6::Identity();    ///< Λc: the smallest inertia ever implemented
  Matrix6 constant_stiffness = Matrix6::Zero();      ///< Kc: the smallest stiffness (≥ 0)
  Matrix6 inertia = Matrix6::Identity();             ///< Λd(0) ≥ Λc
  Matrix6 damping = Matrix6::Identity() * 50.0;      ///< D(0) > 0
  Matrix6 stiffness = Matrix6::Zero();               ///< Kd(0) ≥ Kc
  TankParameters tank;
  bool use_tank = true;  ///< false: always apply the variable parts (no passivity guarantee; for tests)
};

enum class AdmittanceStatus {
  Ok,            ///< the full model Λd, D, Kd was implemented
  TankEmpty,     ///< the tank could not pay for w: the constant parts only
  BadInput,      ///< dt ≤ 0 or a non-finite input: nothing changed
  BadParameters, ///< setParameters: not symmetric positive (semi)definite, or below Λc / Kc
};

/// The energies of the run so far (J), for audits and plots.
struct EnergyAudit {
  double from_environment = 0.0;  ///< Σ F_extᵀ Δx̃: energy the environment put in (negative: received)
  double dissipated = 0.0;        ///< Σ δ
  double injected_by_w = 0.0;     ///< Σ wᵀΔx̃: energy the variable parts took from the system
  double stored = 0.0;            ///< H_c now: ½ ẋ̃ᵀΛc ẋ̃ + ½ x̃ᵀKc x̃
  double tank = 0.0;              ///< T now
  double resync_removed = 0.0;    ///< Σ stored energy the re-syncs removed (negative: the tank paid it in)
};

/// Model/Data in one object: parameters set at configure (and changed at run time by
/// setParameters), a fixed-size state; step() is noexcept and allocation-free.
class VariableAdmittance {
 public:
  /// @throws std::invalid_argument naming the parameter, its value and unit and the expected range
  /// (for diagonal matrices the entry, e.g. "damping[3] = -1 N·m·s/rad: must be > 0") when a matrix
  /// is not symmetric positive definite (Λc, D) or semidefinite (Kc), Λd < Λc, Kd < Kc, or the tank
  /// bounds are wrong.
  explicit VariableAdmittance(const AdmittanceParameters& parameters);

  /// New Λd, D, Kd (a configuration): checked, applied from the next step; the state (hence the
  /// commanded pose) does not jump. Real-time safe; BadParameters leaves the old ones.
  AdmittanceStatus setParameters(const Matrix6& inertia, const Matrix6& damping, const Matrix6& stiffness) noexcept;

  /// One control period of `dt` s. `wrench` is the measured external wrench in the base frame
  /// (N, N·m, about the tool point), `reference` and `reference_twist` the trajectory's set-point
  /// (base frame). Writes the admittance's pose and twist.
  AdmittanceStatus step(const KDL::Frame& reference, const KDL::Twist& reference_twist, const KDL::Wrench& wrench,
                        double dt, KDL::Frame& pose, KDL::Twist& twist) noexcept;

  /// The reference jumped from `old_reference` to `new_reference` (a new trajectory that starts
  /// elsewhere, e.g. at the measured pose): x̃ takes the jump, so the output pose of the next step
  /// continues from where it was instead of jumping with the reference; the spring then pulls
  /// the pose toward the new reference through the model's dynamics. ẋ̃ and the tank are kept
  /// (the jump is the task's input, not an interaction). Real-time safe.
  void rebase(const KDL::Frame& old_reference, const KDL::Frame& new_reference) noexcept;

  /// The robot holds at `held` (it refused this controller's commands, or something stopped it:
  /// an IK discontinuity, a state validator, a drive's quick stop, a communication timeout): the
  /// output pose restarts there, at rest and in equilibrium with the measured `wrench` (base
  /// frame, N, N·m, at the tool point). ẋ̃ becomes 0 and x̃ the static displacement Kd x̃ = (F, τ)
  /// (τ in the held pose's axes: the rotation's generalised force to first order in x̃_r; 0 along
  /// a direction without stiffness), so neither the old motion's rate nor the contact force
  /// moves the output away from the held pose afterwards. `reference` is set to the reference
  /// whose output pose is `held`: p_ref = p_held - x̃_p, R_ref = R_held Exp(x̃_r)ᵀ; the caller
  /// steps from it until its set-points follow the robot again. Passive: stored energy the new
  /// state lacks is dissipated; energy it needs more is paid by the tank, and when the tank cannot
  /// (it would go below ε) x̃ = 0 instead (output at the reference, nothing stored). Both are
  /// counted in EnergyAudit::resync_removed. Real-time safe; a non-finite input changes nothing
  /// but the reference (= held).
  void resync(const KDL::Frame& held, const KDL::Wrench& wrench, KDL::Frame& reference) noexcept;

  /// Back to x̃ = 0, ẋ̃ = 0 and the initial tank energy.
  void reset() noexcept;

  const Vector6& error() const noexcept { return x_; }
  const Vector6& errorRate() const noexcept { return v_; }
  double tankEnergy() const noexcept { return tank_; }
  /// Power the last step dissipated that the admittance's own tank did not store (W, >= 0; 0 after
  /// reset and resync): δ/dt while the tank is full (σ = 0) or unused, else 0. It is the robot's
  /// D_s that feeds a teleoperation tank (eq. 4.19): the energy goes to one tank only, so the
  /// two tanks together never claim the same dissipated energy twice.
  double dissipatedPower() const noexcept { return dissipated_power_; }
  const EnergyAudit& audit() const noexcept { return audit_; }

 private:
  double constantEnergy(const Vector6& x, const Vector6& v) const noexcept;
  /// Backward Euler with inertia M and stiffness K; writes x_next, v_next. `factor`: the
  /// factorisation kept for this (M, K) pair.
  struct Factorisation;
  void integrate(const Matrix6& M, const Matrix6& K, const Vector6& force, double dt, Factorisation& factor,
                 Vector6& x_next, Vector6& v_next) const noexcept;

  /// The Cholesky factorisation of the system matrix M + dt·D + dt²·K of one (M, K) pair for the
  /// parameters of `revision` and this dt: while neither changes (every step between
  /// configurations) the matrix is bit for bit the same, so factorising it again would give
  /// exactly this factorisation.
  struct Factorisation {
    Eigen::LLT<Matrix6> llt;
    Vector6 diagonal = Vector6::Zero();  // the system's diagonal, when every matrix is diagonal
    std::uint64_t revision = 0;
    double dt = 0.0;  // s
    bool known = false;
  };
  AdmittanceParameters parameters_;
  /// Λd − Λc and Kd − Kc (eq. 4.11's variable parts), set with the parameters.
  Matrix6 variable_inertia_ = Matrix6::Zero();
  Matrix6 variable_stiffness_ = Matrix6::Zero();
  Factorisation variable_factor_, constant_factor_;
  /// Counts the parameter sets (setParameters): a factorisation of another revision is stale.
  std::uint64_t revision_ = 0;
  /// Every parameter matrix is diagonal (the component's 6-number properties): products and the
  /// solve use the diagonals only (6 instead of 36 multiplications each).
  bool diagonal_ = false;
  bool allDiagonal() const noexcept;
  /// J_l at the rotation part of x_, computed at the end of the last step for the output twist:
  /// the next step's generalised force needs it at the same x_ (reset and rebase change x_ and
  /// clear `error_jacobian_known_`).
  Eigen::Matrix3d error_jacobian_ = Eigen::Matrix3d::Identity();
  bool error_jacobian_known_ = false;
  Vector6 x_ = Vector6::Zero();
  Vector6 v_ = Vector6::Zero();
  double tank_ = 0.0;
  double dissipated_power_ = 0.0;  // W
  EnergyAudit audit_;
};

}  // namespace cobra::control
