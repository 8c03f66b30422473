#pragma once
/// @file
/// The puncturing procedure as a walk of its motion states (cobra/task/procedure_walk.hpp): the
/// order in which the two charts (charts/needle_insertion.lua: arm 0, charts/us_positioning.lua:
/// arm 1) run their motion states for a plan of N needles, and the plan's datums for each needle.
/// Declared here once; task_charts_test checks that the charts follow it. Core-free.

#include <cstddef>
#include <string>
#include <vector>

#include <kdl/frames.hpp>

#include "cobra/puncturing/plan.hpp"
#include "cobra/task/procedure_walk.hpp"

namespace cobra::puncturing {

/// The motion states of a nominal procedure of `needles` needles, in the order the charts visit
/// them: the needle robot makes room, then per needle the probe's approach and descent, the
/// needle's approach, descent, puncture, (the probe presses on the skin while the needle goes
/// in) insertion, test pull and extraction, then its way to a needle change pose.
std::vector<task::ProcedureStep> procedureSteps(std::size_t needles);

/// Needle `i`'s datum `datum` (entry, target, probe, next_*: the plan's poses in frame A mapped
/// with `abdomen`, before the datum's offset) into `pose`. A needle past the plan's last is
/// NotComing for a next_* datum and Missing otherwise, with `why` saying so. Allocates nothing.
task::DatumSource::Outcome resolvePlanDatum(const PuncturingPlan& plan, const KDL::Frame& abdomen, std::size_t i,
                                            const task::Datum& datum, KDL::Frame& pose, const char*& why);

/// The plan's datums for a procedure walk, with the abdomen registered at `abdomen` (task frame).
class PlanDatums final : public task::ItemDatumSource {
 public:
  PlanDatums(const PuncturingPlan& plan, const KDL::Frame& abdomen) : plan_(plan), abdomen_(abdomen) {}
  void select(std::size_t needle) override { needle_ = needle; }
  /// "needle n2 (2 of 3)"
  std::string itemName(std::size_t needle) const override;
  Outcome resolve(const task::Datum& datum, std::size_t arm, KDL::Frame& pose, const char*& why) override;

 private:
  const PuncturingPlan& plan_;
  KDL::Frame abdomen_;
  std::size_t needle_ = 0;
};

}  // namespace cobra::puncturing
