// Geometry of the puncturing plan: needle and probe poses, feasibility checks.
#include <algorithm>
#include <cstdio>
#include <numbers>
#include <cmath>
#include <stdexcept>

#include "cobra/puncturing/plan.hpp"

namespace cobra::puncturing {
namespace {

constexpr double kOnSkin = 1e-3;          // m: how far from z = 0 a point "on the skin" may be
constexpr double kPlaneTolerance = 1e-3;  // m: needle points off the probe's imaging plane
constexpr double kMaxTilt = 60.0 * std::numbers::pi / 180.0;     // rad: needle or beam from the vertical
constexpr double kHalfSector = 40.0 * std::numbers::pi / 180.0;  // rad: half opening of the imaging sector
constexpr double kProbeFootprint = 0.02;  // m: probe face centre to needle entry, at least

std::string mm(double metres) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.1f mm", metres * 1000.0);
  return buffer;
}

std::string deg(double radians) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.1f deg", radians * 180.0 / std::numbers::pi);
  return buffer;
}

/// Closest distance between segments p1-q1 and p2-q2 (Ericson, Real-Time Collision Detection 5.1.9).
double segmentDistance(const KDL::Vector& p1, const KDL::Vector& q1, const KDL::Vector& p2, const KDL::Vector& q2) {
  const KDL::Vector d1 = q1 - p1, d2 = q2 - p2, r = p1 - p2;
  const double a = KDL::dot(d1, d1), e = KDL::dot(d2, d2), f = KDL::dot(d2, r);
  double s = 0.0, t = 0.0;
  if (a <= 1e-18 && e <= 1e-18) return (p1 - p2).Norm();
  if (a <= 1e-18) {
    t = std::clamp(f / e, 0.0, 1.0);
  } else {
    const double c = KDL::dot(d1, r);
    if (e <= 1e-18) {
      s = std::clamp(-c / a, 0.0, 1.0);
    } else {
      const double b = KDL::dot(d1, d2), denom = a * e - b * b;
      s = denom > 1e-18 ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
      t = (b * s + f) / e;
      if (t < 0.0) {
        t = 0.0;
        s = std::clamp(-c / a, 0.0, 1.0);
      } else if (t > 1.0) {
        t = 1.0;
        s = std::clamp((b - c) / a, 0.0, 1.0);
      }
    }
  }
  return ((p1 + d1 * s) - (p2 + d2 * t)).Norm();
}

}  // namespace

KDL::Frame needleTargetPose(const PlannedNeedle& needle) {
  KDL::Vector z = needle.target - needle.entry;
  z.Normalize();
  // x: the abdomen's x axis made orthogonal to the needle (its y axis for a needle along x).
  KDL::Vector reference(1, 0, 0);
  if (std::abs(KDL::dot(reference, z)) > 0.9) reference = KDL::Vector(0, 1, 0);
  KDL::Vector x = reference - z * KDL::dot(reference, z);
  x.Normalize();
  const KDL::Vector y = z * x;
  const KDL::Rotation rotation = KDL::Rotation(x, y, z) * KDL::Rotation::RotZ(needle.roll);
  return KDL::Frame(rotation, needle.target);
}

KDL::Frame needleEntryPose(const PlannedNeedle& needle) {
  KDL::Frame pose = needleTargetPose(needle);
  pose.p = needle.entry;
  return pose;
}

bool planDatum(std::string_view name, bool& next) {
  next = name.starts_with("next_");
  if (next) name.remove_prefix(5);
  return name == "entry" || name == "target" || name == "probe";
}

double distanceToRegion(const KDL::Vector& p, const KDL::Vector& q, const ForbiddenRegion& region) {
  return segmentDistance(p, q, region.a, region.b) - region.radius;
}

void validate(const PuncturingPlan& plan, std::string_view cryo_source, std::string_view probe_source,
              double needle_length, double clearance) {
  const PreoperativeInfo& info = plan.preoperative;
  for (const PlannedNeedle& n : plan.needles) {
    const std::string where = std::string(cryo_source) + ":" + std::to_string(n.line) + ": needle '" + n.name + "'";
    auto fail = [&](const std::string& message) { throw std::invalid_argument(where + ": " + message); };
    if (std::abs(n.entry.z()) > kOnSkin) fail("entry z = " + mm(n.entry.z()) + ", expected on the skin (z = 0)");
    const KDL::Vector skin_offset(n.entry.x() - info.entry_center.x(), n.entry.y() - info.entry_center.y(), 0.0);
    if (skin_offset.Norm() > info.entry_radius) {
      fail("entry is " + mm(skin_offset.Norm()) + " from the entry region's centre, outside its radius " +
           mm(info.entry_radius));
    }
    const KDL::Vector axis = (n.target - n.entry) / (n.target - n.entry).Norm();
    const double tilt = std::acos(std::clamp(-axis.z(), -1.0, 1.0));
    if (tilt > kMaxTilt) fail("tilted " + deg(tilt) + " from the vertical, expected a needle from above within 60 deg");
    const double off_centre = (n.target - info.tumour_center).Norm();
    if (off_centre > info.tumour_radius) {
      fail("target is " + mm(off_centre) + " from the tumour centre, outside its radius " + mm(info.tumour_radius));
    }
    const double inserted = (n.target - n.entry).Norm();
    if (inserted > needle_length) fail("inserted length " + mm(inserted) + " exceeds the needle's " + mm(needle_length));
    for (const ForbiddenRegion& r : info.forbidden) {
      const double d = distanceToRegion(n.entry, n.target, r);
      if (d < clearance) fail("passes " + mm(d) + " from forbidden region '" + r.name + "' (at least " + mm(clearance) + ")");
    }
  }
  if (plan.probes.size() != plan.needles.size()) {
    throw std::invalid_argument(std::string(probe_source) + ": " + std::to_string(plan.probes.size()) +
                                " probe pose(s) for " + std::to_string(plan.needles.size()) + " needle(s), expected one each");
  }
  for (std::size_t i = 0; i < plan.probes.size(); ++i) {
    const PlannedProbe& p = plan.probes[i];
    const std::string where = std::string(probe_source) + ":" + std::to_string(p.line) + ": probe for '" + p.needle + "'";
    auto fail = [&](const std::string& message) { throw std::invalid_argument(where + ": " + message); };
    if (p.needle != plan.needles[i].name) {
      fail("expected the probe of needle '" + plan.needles[i].name + "' here (probe poses follow the needles' order)");
    }
    const PlannedNeedle& n = plan.needles[i];
    const KDL::Vector beam = p.pose.M.UnitZ(), normal = p.pose.M.UnitY();
    if (std::abs(p.pose.p.z()) > kOnSkin) fail("z = " + mm(p.pose.p.z()) + ", expected the probe face on the skin (z = 0)");
    const double tilt = std::acos(std::clamp(-beam.z(), -1.0, 1.0));
    if (tilt > kMaxTilt) fail("beam tilted " + deg(tilt) + " from the vertical, expected into the body within 60 deg");
    for (const auto& [what, point] : {std::pair{"entry", n.entry}, std::pair{"target", n.target}}) {
      const double off = KDL::dot(normal, point - p.pose.p);
      if (std::abs(off) > kPlaneTolerance) {
        fail(std::string("the needle's ") + what + " is " + mm(off) + " off the imaging plane (at most 1 mm)");
      }
    }
    const KDL::Vector to_target = p.pose.M.Inverse(n.target - p.pose.p);
    const double angle = std::atan2(to_target.x(), to_target.z());
    if (to_target.z() <= 0.0 || std::abs(angle) > kHalfSector) {
      fail("the target is " + deg(angle) + " off the beam, outside the imaging sector (40 deg)");
    }
    const double gap = (p.pose.p - n.entry).Norm();
    if (gap < kProbeFootprint) fail("the probe sits " + mm(gap) + " from the needle's entry (at least 20 mm)");
  }
}

PuncturingPlan loadPlan(const std::string& preoperative_file, const std::string& cryo_plan_file,
                        const std::string& probe_plan_file) {
  PuncturingPlan plan;
  plan.preoperative = parsePreoperative(readText(preoperative_file), preoperative_file);
  plan.needles = parseCryoPlan(readText(cryo_plan_file), cryo_plan_file);
  plan.probes = parseProbePlan(readText(probe_plan_file), probe_plan_file);
  validate(plan, cryo_plan_file, probe_plan_file);
  return plan;
}

}  // namespace cobra::puncturing
