// The probe plan from the cryoablation plan: tools/probe_plan.py's geometry in C++.
#include "cobra/puncturing/probe_plan.hpp"

namespace cobra::puncturing {

KDL::Frame probePose(const PlannedNeedle& needle) {
  const KDL::Vector insertion = needle.target - needle.entry;
  // u: the horizontal direction the needle leans to (from its entry towards its tip, seen from above).
  KDL::Vector u(insertion.x(), insertion.y(), 0.0);
  double beyond = kProbeBeyondTip;
  if (u.Norm() < 1e-12 * insertion.Norm()) {
    u = KDL::Vector(0.0, -1.0, 0.0);
    beyond = kProbeBesideVerticalNeedle;
  } else {
    u.Normalize();
  }
  const double reach = KDL::dot(insertion, u);  // m: the tip's horizontal offset from the entry
  KDL::Vector face = needle.entry + u * (reach + beyond);
  face.z(0.0);
  KDL::Vector beam = needle.target - face;
  beam.Normalize();
  KDL::Vector array = u - beam * KDL::dot(u, beam);
  array.Normalize();
  return KDL::Frame(KDL::Rotation(array, beam * array, beam), face);
}

std::vector<PlannedProbe> probePlan(const std::vector<PlannedNeedle>& needles, const PreoperativeInfo& preoperative,
                                    std::string_view cryo_source) {
  PuncturingPlan plan{preoperative, needles, {}};
  plan.probes.reserve(needles.size());
  for (const PlannedNeedle& needle : needles) plan.probes.push_back(PlannedProbe{needle.name, probePose(needle), needle.line});
  validate(plan, cryo_source, cryo_source);
  return std::move(plan.probes);
}

}  // namespace cobra::puncturing
