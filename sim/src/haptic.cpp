#include "cobra/sim/haptic.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace cobra::sim {
namespace {

void requireRange(const char* parameter, double value, bool zero_allowed, const char* unit) {
  if (!std::isfinite(value) || value < 0.0 || (!zero_allowed && value == 0.0)) {
    throw std::invalid_argument(std::string("haptic master: ") + parameter + " = " + std::to_string(value) +
                                ", expected " + (zero_allowed ? ">= 0 " : "> 0 ") + unit);
  }
}

void requireVector(const char* parameter, const KDL::Vector& v, const char* unit) {
  const char* axes[3] = {"x", "y", "z"};
  for (int i = 0; i < 3; ++i) {
    const std::string name = std::string(parameter) + "." + axes[i];
    requireRange(name.c_str(), v(i), false, unit);
  }
}

double quantise(double value, double step) noexcept { return step > 0.0 ? step * std::round(value / step) : value; }

}  // namespace

void validate(const HapticMasterModel& m) {
  requireVector("workspace_half_extent", m.workspace_half_extent, "m");
  requireRange("position_resolution", m.position_resolution, true, "m");
  requireRange("max_force", m.max_force, false, "N");
  requireRange("continuous_force", m.continuous_force, false, "N");
  requireRange("backdrive_friction", m.backdrive_friction, true, "N");
  requireRange("device_mass", m.device_mass, false, "kg");
  requireVector("max_stiffness", m.max_stiffness, "N/m");
  requireRange("hand_mass", m.hand_mass, false, "kg");
  requireRange("hand_stiffness", m.hand_stiffness, false, "N/m");
  requireRange("hand_damping", m.hand_damping, false, "N*s/m");
  requireRange("friction_velocity_band", m.friction_velocity_band, false, "m/s");
}

HapticMaster::HapticMaster(const HapticMasterModel& model, const KDL::Vector& initial)
    : model_(model), target_(initial), position_(initial) {
  validate(model_);
  for (int i = 0; i < 3; ++i) {
    if (!(std::abs(initial(i)) <= model_.workspace_half_extent(i))) {
      throw std::invalid_argument("haptic master: initial position " + std::to_string(initial(i)) + " m on axis " +
                                  std::to_string(i) + " is outside the workspace (+-" +
                                  std::to_string(model_.workspace_half_extent(i)) + " m)");
    }
    measured_(i) = quantise(initial(i), model_.position_resolution);
  }
}

KDL::Vector HapticMaster::renderableStiffness(const KDL::Vector& stiffness) const noexcept {
  KDL::Vector out;
  for (int i = 0; i < 3; ++i) out(i) = std::clamp(stiffness(i), 0.0, model_.max_stiffness(i));
  return out;
}

std::uint32_t HapticMaster::step(double dt) noexcept {
  if (!std::isfinite(dt) || dt <= 0.0) return 0;
  std::uint32_t flags = 0;
  rendered_ = commanded_;
  const double norm = rendered_.Norm();
  if (!(norm <= model_.max_force)) {  // scale, keeping the direction (a NaN command renders nothing)
    rendered_ = std::isfinite(norm) ? rendered_ * (model_.max_force / norm) : KDL::Vector::Zero();
    flags |= kForceSaturated;
  }
  if (rendered_.Norm() > model_.continuous_force) flags |= kOverContinuous;
  const double mass = model_.hand_mass + model_.device_mass;
  double friction_power = 0.0;
  for (int i = 0; i < 3; ++i) {
    const double friction = model_.backdrive_friction * std::tanh(velocity_(i) / model_.friction_velocity_band);
    const double spring = model_.hand_stiffness * (target_(i) - position_(i));
    // Semi-implicit Euler; the damping term implicit so that stiff hands stay stable at 1 kHz.
    double v = (velocity_(i) + dt * (spring + rendered_(i) - friction) / mass) / (1.0 + dt * model_.hand_damping / mass);
    double p = position_(i) + v * dt;
    const double limit = model_.workspace_half_extent(i);
    if (std::abs(p) >= limit) {
      p = std::copysign(limit, p);
      v = 0.0;
      flags |= kWorkspaceLimit;
    }
    position_(i) = p;
    velocity_(i) = v;
    friction_power += friction * v;
    measured_(i) = quantise(p, model_.position_resolution);
  }
  dissipated_power_ = std::max(friction_power, 0.0);
  return flags;
}

}  // namespace cobra::sim
