#include "cobra/puncturing/procedure.hpp"

namespace cobra::puncturing {

namespace {
constexpr std::size_t kNeedleArm = 0, kProbeArm = 1;
}  // namespace

std::vector<task::ProcedureStep> procedureSteps(std::size_t needles) {
  using task::ProcedureStep;
  std::vector<ProcedureStep> steps;
  if (needles == 0) return steps;
  constexpr bool kPlanned = true, kPrimitive = false;
  steps.push_back({"root.MakeRoomForProbe", kNeedleArm, kPlanned, 0});
  for (std::size_t i = 0; i < needles; ++i) {
    steps.push_back({"root.MoveToSkin.Approach", kProbeArm, kPlanned, i});
    steps.push_back({"root.MoveToSkin.Descend", kProbeArm, kPrimitive, i});
    steps.push_back({"root.InsertingNeedles.MoveToSkin.Approach", kNeedleArm, kPlanned, i});
    steps.push_back({"root.InsertingNeedles.MoveToSkin.Descend", kNeedleArm, kPrimitive, i});
    // The needle on the skin (e_needle_skin_reached): the probe presses on it while the needle
    // punctures the skin and goes in.
    steps.push_back({"root.USPositioned.SearchingNeedle", kProbeArm, kPrimitive, i});
    steps.push_back({"root.InsertingNeedles.PenetratingSkin", kNeedleArm, kPrimitive, i});
    steps.push_back({"root.InsertingNeedles.MoveToTumor", kNeedleArm, kPrimitive, i});
    steps.push_back({"root.ExtractingNeedle.VerifyingNeedleTrapped", kNeedleArm, kPrimitive, i});
    steps.push_back({"root.ExtractingNeedle.MoveToExtractionPoint", kNeedleArm, kPrimitive, i});
    steps.push_back({"root.InsertingNeedles.MoveToNeedleChange", kNeedleArm, kPlanned, i});
  }
  return steps;
}

task::DatumSource::Outcome resolvePlanDatum(const PuncturingPlan& plan, const KDL::Frame& abdomen, std::size_t i,
                                            const task::Datum& datum, KDL::Frame& pose, const char*& why) {
  using Outcome = task::DatumSource::Outcome;
  bool next = false;
  planDatum(datum.name, next);
  if (next) ++i;
  if (i >= plan.needles.size()) {
    why = next ? "no needle after the current one" : "no more needles (all planned needles are done)";
    return next ? Outcome::NotComing : Outcome::Missing;
  }
  const std::string_view name = std::string_view(datum.name).substr(next ? 5 : 0);
  if (name == "entry") {
    pose = abdomen * needleEntryPose(plan.needles[i]);
  } else if (name == "target") {
    pose = abdomen * needleTargetPose(plan.needles[i]);
  } else {
    pose = abdomen * plan.probes[i].pose;
  }
  return Outcome::Resolved;
}

std::string PlanDatums::itemName(std::size_t needle) const {
  const std::string name = needle < plan_.needles.size() ? plan_.needles[needle].name : std::string("?");
  return "needle " + name + " (" + std::to_string(needle + 1) + " of " + std::to_string(plan_.needles.size()) + ")";
}

task::DatumSource::Outcome PlanDatums::resolve(const task::Datum& datum, std::size_t, KDL::Frame& pose,
                                               const char*& why) {
  return resolvePlanDatum(plan_, abdomen_, needle_, datum, pose, why);
}

}  // namespace cobra::puncturing
