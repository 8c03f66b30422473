#include "cobra/sim/ultrasound.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace cobra::sim {
namespace {

void requirePositive(const char* parameter, double value, const char* unit, bool zero_allowed = false) {
  if (!std::isfinite(value) || value < 0.0 || (!zero_allowed && value == 0.0)) {
    throw std::invalid_argument(std::string("ultrasound probe: ") + parameter + " = " + std::to_string(value) +
                                ", expected " + (zero_allowed ? ">= 0 " : "> 0 ") + unit);
  }
}

/// True when `p` (frame P) projects inside the image rectangle of `probe`.
bool insideImage(const UltrasoundProbeModel& m, const KDL::Frame& probe, const KDL::Vector& p) noexcept {
  const KDL::Vector local = probe.Inverse(p);
  return local.z() >= 0.0 && local.z() <= m.image_depth && std::abs(local.x()) <= m.image_half_width;
}

}  // namespace

void validate(const UltrasoundProbeModel& m) {
  requirePositive("contact_stiffness", m.contact_stiffness, "N/m");
  requirePositive("min_contact_force", m.min_contact_force, "N", true);
  requirePositive("plane_tolerance", m.plane_tolerance, "m");
  requirePositive("image_depth", m.image_depth, "m");
  requirePositive("image_half_width", m.image_half_width, "m");
  requirePositive("needle_visible_length", m.needle_visible_length, "m");
}

UltrasoundView observe(const UltrasoundProbeModel& m, const PhantomScenario& phantom, const KDL::Frame& probe,
                       const KDL::Frame& needle_tip) noexcept {
  UltrasoundView view;
  const double indentation = -probe.p.z();
  const double force = indentation > 0.0 ? m.contact_stiffness * indentation : 0.0;
  view.contact_force = KDL::Vector(0.0, 0.0, force);
  view.coupled = indentation > 0.0 && force >= m.min_contact_force;

  const KDL::Vector normal = probe.M.UnitY();
  const KDL::Vector tip = needle_tip.p;
  const KDL::Vector back = tip - needle_tip.M.UnitZ() * m.needle_visible_length;
  view.needle_distance = std::max(std::abs(KDL::dot(tip - probe.p, normal)), std::abs(KDL::dot(back - probe.p, normal)));
  view.needle_visible = view.coupled && view.needle_distance <= m.plane_tolerance && insideImage(m, probe, tip);

  const double centre_distance = KDL::dot(phantom.tumour_center - probe.p, normal);
  const KDL::Vector centre_in_plane = phantom.tumour_center - normal * centre_distance;
  view.tumour_visible =
      view.coupled && std::abs(centre_distance) < phantom.tumour_radius && insideImage(m, probe, centre_in_plane);
  return view;
}

}  // namespace cobra::sim
