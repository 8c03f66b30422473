#pragma once
/// @file
/// Needle-tissue interaction (thesis §4.2: skin contact, layers, tumour, iceball) after Okamura,
/// Simone and O'Leary (IEEE TBME 2004): before a membrane ruptures it pushes back with
/// f = k1·x + k2·x² (x = how far the tip is past the undeformed boundary, m); at the tissue's
/// puncture force it ruptures and the force drops; afterwards the tip meets a constant cutting
/// force while it advances and the shaft a friction proportional to its length in each tissue,
/// f = L·(c·tanh(v/v_s) + b·v) (Karnopp-style: Coulomb smoothed over the band v_s, plus
/// viscous). Pushing the tip sideways off the insertion channel meets k_lat·offset. Touching a
/// forbidden region gives a penalty force and a flag. A cryoablation iceball grows around the
/// tip and traps the needle until it has thawed.
///
/// All positions and forces are in the phantom frame P (phantom.hpp); the needle is straight,
/// given by its tip frame whose z-axis is the needle axis pointing forwards.

#include <cstdint>

#include <kdl/frames.hpp>

#include "cobra/sim/phantom.hpp"

namespace cobra::sim {

/// Cryoablation iceball. Radius law (ASSUMPTION, first-order approach to a plateau, the shape of
/// published cryoprobe isotherm growth curves, which level off within ~10 min): while freezing
/// dr/dt = (r_max - r)/τ_freeze; while thawing dr/dt = -r/τ_thaw. The needle is trapped while
/// r > release_radius; trapped, it is held at the point where it was caught by hold_stiffness.
struct IceballModel {
  double max_radius = 0.015;       ///< m, > 0: plateau radius (ASSUMPTION, 0 °C isotherm of a 17G probe)
  double freeze_time_constant = 120.0;  ///< s, > 0 (ASSUMPTION)
  double thaw_time_constant = 60.0;     ///< s, > 0 (ASSUMPTION: active helium thaw is faster)
  double release_radius = 0.002;   ///< m, > 0: below this the needle slides free
  double hold_stiffness = 2.0e4;   ///< N/m, > 0: force per metre the trapped needle is moved (ASSUMPTION)
  double extraction_threshold = 20.0;  ///< N, > 0: force above which a pulled needle is reported as trapped-and-pulled
};

/// Needle and contact parameters.
struct NeedleModel {
  double friction_velocity_band = 1e-3;  ///< m/s, > 0: v_s of the smoothed Coulomb friction
  IceballModel iceball;
};

/// @throws std::invalid_argument naming the parameter and its expected range.
void validate(const NeedleModel& model);

/// Flags of one step.
enum NeedleFlag : std::uint32_t {
  kSkinContact = 1U << 0,       ///< the tip is at or below the skin
  kSkinPunctured = 1U << 1,     ///< the needle is through the skin
  kPunctureEvent = 1U << 2,     ///< a membrane (skin, layer or tumour) ruptured in this step
  kInTumour = 1U << 3,          ///< the tip is inside the punctured tumour
  kForbiddenContact = 1U << 4,  ///< the tip is inside a forbidden region
  kFreezing = 1U << 5,          ///< a freeze cycle is running
  kTrapped = 1U << 6,           ///< the iceball holds the needle
  kExtractionOverThreshold = 1U << 7,  ///< trapped and pulled with more than extraction_threshold
};

/// What the needle feels, frame P.
struct NeedleForces {
  KDL::Vector force;             ///< N: total force of the tissue on the needle
  double axial = 0.0;            ///< N: -force·axis (positive = resisting insertion)
  double membrane = 0.0;         ///< N: membrane (pre-puncture) part, >= 0
  double cutting = 0.0;          ///< N: cutting part, >= 0
  double friction = 0.0;         ///< N: friction along the axis (opposes the motion: sign of v)
  KDL::Vector lateral;           ///< N: lateral channel force
  KDL::Vector penalty;           ///< N: forbidden-region penalty force
  KDL::Vector ice;               ///< N: iceball holding force
  double inserted_length = 0.0;  ///< m: shaft length below the skin entry point
  int layer = -1;                ///< index of the layer holding the tip, -1 above the skin
  int forbidden_region = -1;     ///< index of the forbidden region touched, -1 for none
  double iceball_radius = 0.0;   ///< m
  std::uint32_t flags = 0;       ///< NeedleFlag bits
};

/// Needle in a phantom: the scenario and the needle model plus the state (punctured membranes,
/// channel, iceball). `step` is noexcept and allocates nothing. The model has no randomness.
class NeedleTissueModel {
 public:
  /// @throws std::invalid_argument when the scenario or the needle model is invalid.
  NeedleTissueModel(PhantomScenario scenario, NeedleModel needle = NeedleModel{});

  /// Advances by `dt` (s, > 0; other values are ignored) with the needle tip at `tip` (frame P).
  const NeedleForces& step(double dt, const KDL::Frame& tip) noexcept;

  /// Starts a freeze cycle around the tip's current position.
  void startFreeze() noexcept;
  /// Stops freezing; the iceball thaws.
  void startThaw() noexcept;

  const NeedleForces& forces() const noexcept { return out_; }
  const PhantomScenario& scenario() const noexcept { return scenario_; }

 private:
  void updateIceball(double dt, const KDL::Vector& tip) noexcept;

  PhantomScenario scenario_;
  NeedleModel needle_;
  std::vector<double> layer_top_;   // m, depth of each layer's top, plus the bottom of the last
  std::size_t punctured_layers_ = 0;
  bool tumour_punctured_ = false;
  KDL::Vector entry_, channel_axis_;
  KDL::Vector previous_tip_;
  bool has_previous_ = false;
  bool freezing_ = false;
  bool iceball_started_ = false;
  double ice_radius_ = 0.0;
  bool trapped_ = false;
  KDL::Vector trap_point_;
  NeedleForces out_;
};

}  // namespace cobra::sim
