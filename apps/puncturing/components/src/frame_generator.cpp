#include "cobra/components/puncturing/frame_generator.hpp"

#include <cstdio>
#include <functional>
#include <stdexcept>

#include "cobra/components/puncturing/navigation_plan.hpp"
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
  addProperty(plan_source_);
  addProperty(navigation_timeout_.range(0.0, 1e6));
  addPort(abdomen_frame_);
  addPort(needle_target_);
  addPort(plan_in_);
  addPort(refusal_);
  addOperation("awaitNavigation", std::function<void()>([this] { navigation_request_.ask(activity()); }),
               "answers e_navigation_received once the plan and the registration are taken (at once with files), "
               "e_navigation_refused, or e_navigation_timeout after navigation_timeout s (why: navigationStatus)",
               core::ExecutionThread::Client);
  addOperation("navigationStatus", std::function<std::string()>([this] { return navigation_status_; }),
               "the navigated plan and registration taken, or why not (one line; '' before)");
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
  if (plan_source_() != "files" && plan_source_() != "navigation")
    return refuse("property plan_source is '" + plan_source_() + "'; expected files or navigation");
  plan_.reset();
  preoperative_.reset();
  navigation_ = {};
  awaiting_ = navigation_refused_ = false;
  navigation_request_.clear();
  navigation_status_.clear();
  needle_ = 0;
  for (const auto& [file, name] : files) {
    if ((*file)().empty() && (file == &preoperative_file_ || !navigated()))
      return refuse(std::string("property ") + name + " is empty; give the path of its file");
  }
  try {
    if (navigated()) {
      preoperative_ = puncturing::parsePreoperative(puncturing::readText(preoperative_file_()), preoperative_file_());
      abdomen_ = preoperative_->abdomen_in_task;
      return true;
    }
    plan_ = puncturing::loadPlan(preoperative_file_(), cryo_plan_file_(), probe_plan_file_());
  } catch (const std::invalid_argument& e) {
    plan_.reset();
    preoperative_.reset();
    return refuse(e.what());
  }
  abdomen_ = plan_->preoperative.abdomen_in_task;
  return true;
}

const KDL::Frame& PuncturingFrameGenerator::abdomen() {
  if (navigated()) return abdomen_;  // the registration the navigated plan was taken with
  KDL::Frame sample;
  if (abdomen_frame_.read(sample) != core::FlowStatus::NoData) abdomen_ = sample;
  return abdomen_;
}

void PuncturingFrameGenerator::answerNavigation(const char* event, std::string status) {
  navigation_status_ = std::move(status);
  awaiting_ = false;
  if (navigated()) std::fprintf(stderr, "[cobra] '%s': %s\n", name().c_str(), navigation_status_.c_str());
  if (std::string_view(event) != "e_navigation_received") refusal_.write(navigation_status_);
  emitEvent(event);
}

void PuncturingFrameGenerator::stepNavigation() {
  if (navigation_request_.take() && !awaiting_) {
    awaiting_ = true;
    awaiting_since_ns_ = now().count();
  }
  if (!navigated()) {
    if (awaiting_) answerNavigation("e_navigation_received", "plan and registration from the files");
    return;
  }
  if (!plan_ && !navigation_refused_ && navigation_.read(plan_in_, abdomen_frame_)) {
    // Taken once (allocates: the plan's needles, probe poses and messages).
    puncturing::PuncturingPlan plan;
    const std::string refusal =
        puncturing_navigation::buildPlan(navigation_.points, navigation_.registration, *preoperative_, plan);
    if (refusal.empty()) {
      plan_ = std::move(plan);
      abdomen_ = plan_->preoperative.abdomen_in_task;
      navigation_status_ = "navigation: " + puncturing_navigation::describe(*plan_);
    } else {
      navigation_refused_ = true;
      navigation_status_ = "navigation refused: " + refusal;
    }
  }
  if (!awaiting_) return;
  if (plan_) return answerNavigation("e_navigation_received", navigation_status_);
  if (navigation_refused_) return answerNavigation("e_navigation_refused", navigation_status_);
  if (static_cast<double>(now().count() - awaiting_since_ns_) * 1e-9 >= navigation_timeout_()) {
    char seconds[32];
    std::snprintf(seconds, sizeof seconds, "%g", navigation_timeout_());
    answerNavigation("e_navigation_timeout", "navigation timed out: " + std::string(navigation_.missing()) +
                                                 " from the navigation within " + seconds + " s");
  }
}

void PuncturingFrameGenerator::readTaskInputs() {
  abdomen();
  if (plan_ && static_cast<std::size_t>(needle_) < plan_->needles.size()) {
    needle_target_.write(abdomen_ * puncturing::needleTargetPose(plan_->needles[static_cast<std::size_t>(needle_)]));
  }
}

void PuncturingFrameGenerator::stepTask() {
  stepNavigation();
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
