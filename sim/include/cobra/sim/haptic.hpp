#pragma once
/// @file
/// The surgeon's side of teleoperation (thesis §4.3.4): a Phantom Omni haptic master held by a
/// human hand. The hand is a mass-spring-damper pulled towards the pose the surgeon wants; the
/// device adds its apparent mass and backdrive friction, renders the commanded force up to its
/// maximum, keeps the stylus inside its workspace and reads it with its position resolution.
/// Translation only (the Omni actuates its first three joints only). Frame D: the device's base
/// frame, origin at the centre of the force-feedback workspace.

#include <cstdint>

#include <kdl/frames.hpp>

namespace cobra::sim {

/// Phantom Omni (thesis §4.3.4 table) plus the hand holding it.
struct HapticMasterModel {
  KDL::Vector workspace_half_extent{0.080, 0.060, 0.035};  ///< m, > 0: half of 160 x 120 x 70 mm
  double position_resolution = 0.055e-3;  ///< m, >= 0: 0.055 mm (450 dpi)
  double max_force = 3.3;                 ///< N, > 0: maximum exertable force at the nominal position
  double continuous_force = 0.88;         ///< N, > 0: above it the force is flagged (motor heating)
  double backdrive_friction = 0.26;       ///< N, >= 0: Coulomb, smoothed over friction_velocity_band
  double device_mass = 0.045;             ///< kg, > 0: apparent mass at the tip
  KDL::Vector max_stiffness{1260.0, 2310.0, 1020.0};  ///< N/m, > 0: renderable stiffness per axis (table: > 1.26, 2.31, 1.02 N/mm)
  // The hand: ASSUMPTIONS of the order of measured human arm endpoint impedance (Tsuji et al.,
  // Biol. Cybern. 1995: stiffness 100-1000 N/m, damping 5-20 N·s/m, mass 1-2 kg).
  double hand_mass = 1.5;                 ///< kg, > 0
  double hand_stiffness = 400.0;          ///< N/m, > 0: pull towards the target
  double hand_damping = 25.0;             ///< N·s/m, > 0
  double friction_velocity_band = 1e-3;   ///< m/s, > 0
};

/// @throws std::invalid_argument naming the parameter and its expected range.
void validate(const HapticMasterModel& model);

/// Flags of one step.
enum HapticFlag : std::uint32_t {
  kForceSaturated = 1U << 0,     ///< the commanded force exceeded max_force and was scaled down
  kOverContinuous = 1U << 1,     ///< the rendered force exceeds continuous_force
  kWorkspaceLimit = 1U << 2,     ///< the stylus is at the workspace boundary
};

/// Hand + device, frame D. `step` is noexcept and allocates nothing; no randomness.
class HapticMaster {
 public:
  /// @throws std::invalid_argument when the model is invalid or `initial` is outside the workspace.
  explicit HapticMaster(const HapticMasterModel& model, const KDL::Vector& initial = KDL::Vector::Zero());

  /// Where the surgeon wants the stylus (m, frame D).
  void setHandTarget(const KDL::Vector& target) noexcept { target_ = target; }
  /// Force the controller asks the device to render on the hand (N, frame D).
  void setCommandedForce(const KDL::Vector& force) noexcept { commanded_ = force; }
  /// A virtual spring wall of `stiffness` (N/m per axis) clamped to what the device can render.
  KDL::Vector renderableStiffness(const KDL::Vector& stiffness) const noexcept;

  /// Advances by `dt` (s, > 0; other values are ignored); returns HapticFlag bits.
  std::uint32_t step(double dt) noexcept;

  const KDL::Vector& position() const noexcept { return position_; }  ///< m, true stylus position
  const KDL::Vector& velocity() const noexcept { return velocity_; }  ///< m/s
  const KDL::Vector& measured() const noexcept { return measured_; }  ///< m, quantised reading
  const KDL::Vector& renderedForce() const noexcept { return rendered_; }  ///< N, after saturation
  /// Power the device's backdrive friction dissipated over the last step, Σ f_i v_i (W, >= 0: a
  /// velocity that reversed within the step counts 0): the master's own dissipation D_m of a
  /// teleoperation tank (eq. 4.19). The hand's damping is the surgeon's, not counted.
  double dissipatedPower() const noexcept { return dissipated_power_; }

 private:
  HapticMasterModel model_;
  KDL::Vector target_, commanded_, position_, velocity_, measured_, rendered_;
  double dissipated_power_ = 0.0;  // W
};

}  // namespace cobra::sim
