#include "cobra/sim/needle_tissue.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

namespace cobra::sim {
namespace {

void requirePositive(const char* parameter, double value, const char* unit) {
  if (!std::isfinite(value) || value <= 0.0) {
    throw std::invalid_argument(std::string("needle model: ") + parameter + " = " + std::to_string(value) +
                                ", expected > 0 " + unit);
  }
}

double membraneForce(const TissueProperties& t, double x) noexcept { return x > 0.0 ? t.k1 * x + t.k2 * x * x : 0.0; }

/// Closest point of segment a-b to p.
KDL::Vector closestOnSegment(const KDL::Vector& a, const KDL::Vector& b, const KDL::Vector& p) noexcept {
  const KDL::Vector ab = b - a;
  const double len2 = KDL::dot(ab, ab);
  const double s = len2 > 0.0 ? std::clamp(KDL::dot(p - a, ab) / len2, 0.0, 1.0) : 0.0;
  return a + ab * s;
}

}  // namespace

void validate(const NeedleModel& m) {
  requirePositive("friction_velocity_band", m.friction_velocity_band, "m/s");
  requirePositive("iceball.max_radius", m.iceball.max_radius, "m");
  requirePositive("iceball.freeze_time_constant", m.iceball.freeze_time_constant, "s");
  requirePositive("iceball.thaw_time_constant", m.iceball.thaw_time_constant, "s");
  requirePositive("iceball.release_radius", m.iceball.release_radius, "m");
  requirePositive("iceball.hold_stiffness", m.iceball.hold_stiffness, "N/m");
  requirePositive("iceball.extraction_threshold", m.iceball.extraction_threshold, "N");
}

NeedleTissueModel::NeedleTissueModel(PhantomScenario scenario, NeedleModel needle)
    : scenario_(std::move(scenario)), needle_(needle) {
  validate(scenario_);
  validate(needle_);
  for (std::size_t i = 0; i <= scenario_.layers.size(); ++i) layer_top_.push_back(layerTop(scenario_, i));
}

void NeedleTissueModel::startFreeze() noexcept {
  freezing_ = true;
  iceball_started_ = true;
}

void NeedleTissueModel::startThaw() noexcept { freezing_ = false; }

void NeedleTissueModel::updateIceball(double dt, const KDL::Vector& tip) noexcept {
  const IceballModel& ice = needle_.iceball;
  if (freezing_) {
    ice_radius_ = ice.max_radius - (ice.max_radius - ice_radius_) * std::exp(-dt / ice.freeze_time_constant);
  } else {
    ice_radius_ *= std::exp(-dt / ice.thaw_time_constant);
  }
  const bool frozen = iceball_started_ && ice_radius_ > ice.release_radius;
  if (frozen && !trapped_) trap_point_ = tip;
  trapped_ = frozen;
}

const NeedleForces& NeedleTissueModel::step(double dt, const KDL::Frame& tip_frame) noexcept {
  if (!std::isfinite(dt) || dt <= 0.0) return out_;
  const KDL::Vector tip = tip_frame.p;
  const KDL::Vector axis = tip_frame.M.UnitZ();
  const double v_axial = has_previous_ ? KDL::dot(tip - previous_tip_, axis) / dt : 0.0;
  previous_tip_ = tip;
  has_previous_ = true;

  NeedleForces f;
  const double depth = -tip.z();
  if (depth < 0.0 && punctured_layers_ > 0) {  // pulled out: the channel closes behind the needle
    punctured_layers_ = 0;
    tumour_punctured_ = false;
  }
  if (depth >= 0.0) {
    f.flags |= kSkinContact;
    const std::size_t layers = scenario_.layers.size();
    std::size_t in_layer = 0;
    while (in_layer + 1 < layers && depth >= layer_top_[in_layer + 1]) ++in_layer;
    f.layer = static_cast<int>(in_layer);
    // The first membrane not yet ruptured that the tip has pushed past (one rupture per step).
    if (punctured_layers_ <= in_layer) {
      const TissueProperties& t = scenario_.layers[punctured_layers_].tissue;
      const double x = depth - layer_top_[punctured_layers_];
      const double membrane = membraneForce(t, x);
      if (membrane >= t.puncture_force) {
        if (punctured_layers_ == 0) {
          // Entry point: where the axis crosses the skin; the channel runs along the axis.
          entry_ = axis.z() < -1e-9 ? tip - axis * (depth / -axis.z()) : KDL::Vector(tip.x(), tip.y(), 0.0);
          channel_axis_ = axis;
        }
        ++punctured_layers_;
        f.flags |= kPunctureEvent;
      } else {
        f.membrane = membrane;
      }
    }
    const bool skin_through = punctured_layers_ > 0;
    if (skin_through) {
      f.flags |= kSkinPunctured;
      const TissueProperties* cutting_tissue = punctured_layers_ > in_layer ? &scenario_.layers[in_layer].tissue : nullptr;
      const KDL::Vector from_tumour = tip - scenario_.tumour_center;
      const double tumour_gap = scenario_.tumour_radius - from_tumour.Norm();
      if (tumour_gap >= 0.0) {
        if (!tumour_punctured_) {
          const double membrane = membraneForce(scenario_.tumour_tissue, tumour_gap);
          if (membrane >= scenario_.tumour_tissue.puncture_force) {
            tumour_punctured_ = true;
            f.flags |= kPunctureEvent;
          } else {
            f.membrane += membrane;
            cutting_tissue = nullptr;
          }
        }
        if (tumour_punctured_) {
          f.flags |= kInTumour;
          cutting_tissue = &scenario_.tumour_tissue;
        }
      }
      if (cutting_tissue != nullptr && v_axial > 0.0) f.cutting = cutting_tissue->cutting_force;

      // Friction: the shaft from the entry point to the tip, split over the layers by depth.
      const KDL::Vector shaft = tip - entry_;
      f.inserted_length = shaft.Norm();
      const double smooth_sign = std::tanh(v_axial / needle_.friction_velocity_band);
      if (depth > 0.0) {
        for (std::size_t i = 0; i < layers && i < punctured_layers_; ++i) {
          const double overlap = std::min(depth, layer_top_[i + 1]) - layer_top_[i];
          if (overlap <= 0.0) break;
          const double length = f.inserted_length * overlap / depth;
          const TissueProperties& t = scenario_.layers[i].tissue;
          f.friction += length * (t.coulomb_friction * smooth_sign + t.viscous_friction * v_axial);
        }
      }
      // Lateral: the tip's offset from the channel line, restored by the tissue holding the tip.
      const KDL::Vector offset = shaft - channel_axis_ * KDL::dot(shaft, channel_axis_);
      const double lateral_stiffness = tumour_punctured_ && tumour_gap >= 0.0
                                           ? scenario_.tumour_tissue.lateral_stiffness
                                           : scenario_.layers[in_layer].tissue.lateral_stiffness;
      f.lateral = offset * -lateral_stiffness;
    }
  }

  for (std::size_t i = 0; i < scenario_.forbidden.size(); ++i) {
    const ForbiddenRegion& r = scenario_.forbidden[i];
    const KDL::Vector away = tip - closestOnSegment(r.a, r.b, tip);
    const double distance = away.Norm();
    if (distance < r.radius) {
      const KDL::Vector normal = distance > 1e-12 ? away / distance : -axis;
      f.penalty += normal * (scenario_.penalty_stiffness * (r.radius - distance));
      f.flags |= kForbiddenContact;
      if (f.forbidden_region < 0) f.forbidden_region = static_cast<int>(i);
    }
  }

  updateIceball(dt, tip);
  f.iceball_radius = ice_radius_;
  if (freezing_) f.flags |= kFreezing;
  if (trapped_) {
    f.flags |= kTrapped;
    f.ice = (tip - trap_point_) * -needle_.iceball.hold_stiffness;
    if (f.ice.Norm() > needle_.iceball.extraction_threshold) f.flags |= kExtractionOverThreshold;
  }

  const double axial_resistance = f.membrane + f.cutting + f.friction;
  f.force = axis * -axial_resistance + f.lateral + f.penalty + f.ice;
  f.axial = -KDL::dot(f.force, axis);
  out_ = f;
  return out_;
}

}  // namespace cobra::sim
