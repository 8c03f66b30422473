#include "cobra/components/puncturing/frame_generator.hpp"

#include <functional>
#include <stdexcept>

#include "cobra/puncturing/procedure.hpp"

namespace cobra::components {

PuncturingFrameGenerator::PuncturingFrameGenerator(std::string name)
    : StateTableFrameGenerator(std::move(name), "PuncturingFrameGenerator",
                               "Puncturing Frame Generator (thesis §4.5.5): the goal poses of needle and probe for the "
                               "current task state, from the preoperative data, the cryoablation and probe plans and "
                               "a state table",
                               puncturing::puncturingVocabulary(),
                               {MeasuredPort{"needleMeasPose", "measured needle tip pose, world"},
                                MeasuredPort{"USMeasPose", "measured probe pose, world"}}) {
  addProperty(preoperative_file_);
  addProperty(cryo_plan_file_);
  addProperty(probe_plan_file_);
  addProperty(arm_);
  addPort(abdomen_frame_);
  addPort(needle_target_);
  addOperation("nextNeedle", std::function<void()>([this] { next_needle_request_.ask(activity()); }),
               "moves on to the next planned needle in this component's next step; answers e_needle_selected, "
               "or e_all_needles_done after the last one",
               core::ExecutionThread::Client);
  addOperation("currentNeedle", std::function<int()>([this] { return needle_; }),
               "index of the current needle (0-based; needleCount() when all are done)");
  addOperation("needleCount",
               std::function<int()>([this] { return plan_ ? static_cast<int>(plan_->needles.size()) : 0; }),
               "number of planned needles");
  addOperation("plannedTarget", &PuncturingFrameGenerator::plannedTarget, this,
               "planned tip pose of needle i (0-based) in the world frame, with the latest abdomenFrame (m)")
      .arg("i", "1", "needle index, 0-based");
}

bool PuncturingFrameGenerator::configureTask() {
  if (arm_() != "needle" && arm_() != "probe")
    return refuse("property arm is '" + arm_() + "'; expected needle or probe");
  const std::pair<const core::Property<std::string>*, const char*> files[] = {
      {&preoperative_file_, "preoperative_info_file"}, {&cryo_plan_file_, "cryo_plan_file"},
      {&probe_plan_file_, "US_pose_plan_file"}};
  for (const auto& [file, name] : files) {
    if ((*file)().empty()) return refuse(std::string("property ") + name + " is empty; give the path of its file");
  }
  try {
    plan_ = puncturing::loadPlan(preoperative_file_(), cryo_plan_file_(), probe_plan_file_());
  } catch (const std::invalid_argument& e) {
    plan_.reset();
    return refuse(e.what());
  }
  needle_ = 0;
  abdomen_ = plan_->preoperative.abdomen_in_task;
  return true;
}

const KDL::Frame& PuncturingFrameGenerator::abdomen() {
  KDL::Frame sample;
  if (abdomen_frame_.read(sample) != core::FlowStatus::NoData) abdomen_ = sample;
  return abdomen_;
}

void PuncturingFrameGenerator::readTaskInputs() {
  abdomen();
  if (plan_ && static_cast<std::size_t>(needle_) < plan_->needles.size()) {
    needle_target_.write(abdomen_ * puncturing::needleTargetPose(plan_->needles[static_cast<std::size_t>(needle_)]));
  }
}

void PuncturingFrameGenerator::stepTask() {
  // A chart moving on to the next needle asks for that needle's goals after.
  if (next_needle_request_.take()) advanceNeedle();
}

task::DatumSource::Outcome PuncturingFrameGenerator::resolveTaskDatum(const task::Datum& datum, std::size_t,
                                                                      KDL::Frame& out, const char*& why) {
  if (!plan_) {
    why = "no plan loaded";
    return Outcome::Missing;
  }
  return puncturing::resolvePlanDatum(*plan_, abdomen_, static_cast<std::size_t>(needle_), datum, out, why);
}

void PuncturingFrameGenerator::advanceNeedle() {
  if (!plan_) return;
  const int count = static_cast<int>(plan_->needles.size());
  if (needle_ < count) ++needle_;
  emitEvent(needle_ >= count ? "e_all_needles_done" : "e_needle_selected");
}

KDL::Frame PuncturingFrameGenerator::plannedTarget(int index) {
  if (!plan_) throw std::invalid_argument("not configured: no plan loaded");
  if (index < 0 || static_cast<std::size_t>(index) >= plan_->needles.size())
    throw std::invalid_argument("needle " + std::to_string(index) + " is not planned; the plan has " +
                                std::to_string(plan_->needles.size()) + " needles (0-based)");
  return abdomen() * puncturing::needleTargetPose(plan_->needles[static_cast<std::size_t>(index)]);
}

}  // namespace cobra::components
