#include "cobra/components/puncturing/frame_generator.hpp"

#include <algorithm>
#include <array>

#include <cstdio>
#include <stdexcept>

namespace cobra::components {
namespace {

constexpr std::size_t kArms = 2;  // arm 0 = needle, arm 1 = probe
static_assert(puncturing::kPoseValues == kValuesPerArm, "the table's goal encoding is the motion components' path encoding");

}  // namespace

PuncturingFrameGenerator::PuncturingFrameGenerator(std::string name)
    : Component(std::move(name), core::Role::Bridge,
                "Puncturing Frame Generator (thesis §4.5.5): the goal poses of needle and probe for the current task "
                "state, from the preoperative data, the cryoablation and probe plans and a state table") {
  addProperty(preoperative_file_);
  addProperty(cryo_plan_file_);
  addProperty(probe_plan_file_);
  addProperty(state_table_file_);
  addProperty(arm_);
  addPort(abdomen_frame_);
  addPort(task_state_);
  addPort(needle_meas_);
  addPort(us_meas_);
  addPort(desired_poses_);
  addPort(goal_poses_);
  addPort(needle_target_);
  addOperation("askCurrentGoal", std::function<void()>([this] { askCurrentGoal(); }),
               "publishes desiredPoses [measured pair, goal pair], goalPoses and needleTarget for the task state on "
               "currentTaskState, in this component's next step; answers e_goal_ready or e_no_data (reason: "
               "lastFailure)",
               core::ExecutionThread::Client);
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
  addOperation("lastFailure", std::function<std::string()>([this] { return last_failure_; }),
               "why the last askCurrentGoal answered e_no_data (empty when it did not)");
}

bool PuncturingFrameGenerator::configureHook() {
  if (arm_() != "needle" && arm_() != "probe")
    return refuse("property arm is '" + arm_() + "'; expected needle or probe");
  const std::pair<const core::Property<std::string>*, const char*> files[] = {
      {&preoperative_file_, "preoperative_info_file"}, {&cryo_plan_file_, "cryo_plan_file"},
      {&probe_plan_file_, "US_pose_plan_file"}, {&state_table_file_, "state_table_file"}};
  for (const auto& [file, name] : files) {
    if ((*file)().empty()) return refuse(std::string("property ") + name + " is empty; give the path of its file");
  }
  try {
    plan_ = puncturing::loadPlan(preoperative_file_(), cryo_plan_file_(), probe_plan_file_());
    table_ = puncturing::parseStateTable(puncturing::readText(state_table_file_()), state_table_file_());
  } catch (const std::invalid_argument& e) {
    plan_.reset();
    return refuse(e.what());
  }
  needle_ = 0;
  abdomen_ = plan_->preoperative.abdomen_in_task;
  have_measured_ = {false, false};
  state_ = {};
  last_failure_.clear();
  desired_ = trajectory::MultiAxisPath(std::vector<std::vector<double>>(2, std::vector<double>(kArms * kValuesPerArm)));
  goal_ = trajectory::MultiAxisPath(std::vector<std::vector<double>>(1, std::vector<double>(kArms * kValuesPerArm)));
  desired_poses_.setDataSample(desired_);
  goal_poses_.setDataSample(goal_);
  return true;
}

const KDL::Frame& PuncturingFrameGenerator::abdomen() {
  KDL::Frame sample;
  if (abdomen_frame_.read(sample) != core::FlowStatus::NoData) abdomen_ = sample;
  return abdomen_;
}

puncturing::DatumSource::Outcome PuncturingFrameGenerator::resolve(const puncturing::Datum& datum, std::size_t arm,
                                                                   KDL::Frame& out, const char*& why) {
  bool next = false;
  if (datum.name == "hold") {
    if (!have_measured_[arm]) {
      why = arm == 0 ? "no pose on needleMeasPose yet" : "no pose on USMeasPose yet";
      return Outcome::Missing;
    }
    out = measured_[arm];
  } else if (const KDL::Frame* fixed = table_.pose(datum.name)) {
    out = *fixed;
  } else {
    puncturing::planDatum(datum.name, next);
    const auto i = static_cast<std::size_t>(needle_) + (next ? 1 : 0);
    if (i >= plan_->needles.size()) {
      why = next ? "no needle after the current one" : "no more needles (all planned needles are done)";
      return next ? Outcome::NotComing : Outcome::Missing;
    }
    const std::string_view name = std::string_view(datum.name).substr(next ? 5 : 0);
    if (name == "entry") {
      out = abdomen_ * puncturing::needleEntryPose(plan_->needles[i]);
    } else if (name == "target") {
      out = abdomen_ * puncturing::needleTargetPose(plan_->needles[i]);
    } else {
      out = abdomen_ * plan_->probes[i].pose;
    }
  }
  return Outcome::Resolved;
}

void PuncturingFrameGenerator::noData(const std::string& reason) {
  last_failure_ = reason;
  std::fprintf(stderr, "[cobra] PuncturingFrameGenerator '%s' (%s arm): e_no_data: %s\n", name().c_str(),
               arm_().c_str(), reason.c_str());
  emitEvent("e_no_data");
}

void PuncturingFrameGenerator::askCurrentGoal() { goal_request_.ask(activity()); }

void PuncturingFrameGenerator::updateHook() {
  // A chart moving on to the next needle asks for that needle's goals after.
  if (next_needle_request_.take()) advanceNeedle();
  if (goal_request_.take()) answerCurrentGoal();
}

void PuncturingFrameGenerator::answerCurrentGoal() {
  if (!plan_) {
    noData("not configured: no plan loaded");
    return;
  }
  abdomen();
  if (needle_meas_.read(measured_[0]) != core::FlowStatus::NoData) have_measured_[0] = true;
  if (us_meas_.read(measured_[1]) != core::FlowStatus::NoData) have_measured_[1] = true;
  const bool have_needle = static_cast<std::size_t>(needle_) < plan_->needles.size();
  if (have_needle) {
    needle_target_.write(abdomen_ * puncturing::needleTargetPose(plan_->needles[static_cast<std::size_t>(needle_)]));
  }
  if (task_state_.read(state_) == core::FlowStatus::NoData) {
    noData("no task state on currentTaskState yet");
    return;
  }
  std::string no_row;
  const puncturing::StateRow* row = puncturing::rowFor(table_, state_.path.view(), state_table_file_(), no_row);
  if (row == nullptr) {
    noData(no_row);
    return;
  }
  const auto where = [&] { return puncturing::rowWhere(state_.path.view(), state_table_file_(), *row); };
  const std::array<std::string, kArms>& arms = puncturing::puncturingVocabulary().arms;
  if (!puncturing::firstGoal(*row, arms, *this, goal_pair_, failure_)) {
    noData(where() + failure_.message());
    return;
  }
  for (std::size_t a = 0; a < kArms; ++a) {
    if (!have_measured_[a]) {
      noData(std::string("desiredPoses starts at the measured poses: no pose on ") +
             (a == 0 ? "needleMeasPose" : "USMeasPose") + " yet (task state '" + state_.path.str() + "')");
      return;
    }
  }
  if (!puncturing::hasChecks(*row)) {
    for (std::size_t a = 0; a < kArms; ++a) puncturing::encodePose(goal_pair_[a], a, goal_.waypoint(0));
    publish(goal_);
    return;
  }
  std::vector<std::vector<double>> waypoints;
  if (!puncturing::checkedGoals(*row, arms, *this, waypoints, failure_)) {
    noData(where() + failure_.message());
    return;
  }
  publish(trajectory::MultiAxisPath(std::move(waypoints)));
}

void PuncturingFrameGenerator::publish(const trajectory::MultiAxisPath& goal) {
  for (std::size_t a = 0; a < kArms; ++a) {
    puncturing::encodePose(measured_[a], a, desired_.waypoint(0));
    puncturing::encodePose(goal_pair_[a], a, desired_.waypoint(1));
  }
  last_failure_.clear();
  desired_poses_.write(desired_);
  goal_poses_.write(goal);
  emitEvent("e_goal_ready");
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
