#include "cobra/components/suturing/suturing_frame_generator.hpp"

#include <cstdio>
#include <functional>
#include <stdexcept>

namespace cobra::components {
namespace {

constexpr std::size_t kArms = 2;  // arm 0 = right (Endo Stitch), arm 1 = left (stick)

/// The tool's pose at `p` over a stitch frame (x along the cut, z out of the skin): x along the
/// cut, z into the skin.
KDL::Frame toolAt(const KDL::Rotation& stitch, const KDL::Vector& p) {
  return KDL::Frame(stitch * KDL::Rotation::RotX(KDL::PI), p);
}

}  // namespace

const puncturing::TableVocabulary& SuturingFrameGenerator::vocabulary() {
  static const puncturing::TableVocabulary words{
      {"right", "left"}, {"right_edge", "left_edge", "centre", "pull", "aside", "hook", "push"}};
  return words;
}

SuturingFrameGenerator::SuturingFrameGenerator(std::string name)
    : Component(std::move(name), core::Role::Bridge,
                "Suturing Frame Generator (thesis §5.5): the goal poses of the Endo Stitch and the stick for the "
                "current task state, from the current stitch's targets and a state table") {
  addProperty(state_table_file_);
  for (auto* p : {&pull_offset_, &aside_offset_, &hook_offset_, &push_offset_}) addProperty(*p);
  addProperty(right_half_state_);
  addProperty(left_half_state_);
  addPort(task_state_);
  addPort(right_stitch_);
  addPort(left_stitch_);
  addPort(right_meas_);
  addPort(left_meas_);
  addPort(desired_poses_);
  addPort(goal_poses_);
  addOperation("askCurrentGoal", std::function<void()>([this] { askCurrentGoal(); }),
               "publishes desiredPoses [measured pair, goal pair] and goalPoses for the task state on "
               "currentTaskState, in this component's next step; answers e_goal_ready or e_no_data (reason: "
               "lastFailure)",
               core::ExecutionThread::Client);
  addOperation("lastFailure", std::function<std::string()>([this] { return last_failure_; }),
               "why the last askCurrentGoal answered e_no_data (empty when it did not)");
}

bool SuturingFrameGenerator::configureHook() {
  if (state_table_file_().empty()) return refuse("property state_table_file is empty; give the path of its file");
  try {
    table_ = puncturing::parseStateTable(puncturing::readText(state_table_file_()), state_table_file_(), vocabulary());
  } catch (const std::invalid_argument& e) {
    return refuse(e.what());
  }
  desired_ = trajectory::MultiAxisPath(
      std::vector<std::vector<double>>(2, std::vector<double>(kArms * puncturing::kPoseValues)));
  goal_ = trajectory::MultiAxisPath(
      std::vector<std::vector<double>>(1, std::vector<double>(kArms * puncturing::kPoseValues)));
  desired_poses_.setDataSample(desired_);
  goal_poses_.setDataSample(goal_);
  return true;
}

bool SuturingFrameGenerator::startHook() {
  have_stitch_ = have_measured_ = {false, false};
  last_half_ = 0;
  state_ = {};
  last_failure_.clear();
  goal_request_.clear();
  return true;
}

void SuturingFrameGenerator::updateHook() {
  if (goal_request_.take()) answer();
}

puncturing::DatumSource::Outcome SuturingFrameGenerator::resolve(const puncturing::Datum& datum, std::size_t arm,
                                                                 KDL::Frame& pose, const char*& why) {
  if (datum.name == "hold") {
    if (!have_measured_[arm]) {
      why = arm == 0 ? "no pose on rightMeasPose yet" : "no pose on leftMeasPose yet";
      return Outcome::Missing;
    }
    pose = measured_[arm];
    return Outcome::Resolved;
  }
  if (const KDL::Frame* fixed = table_.pose(datum.name)) {
    pose = *fixed;
    return Outcome::Resolved;
  }
  if (!have_stitch_[0] || !have_stitch_[1]) {
    why = "no stitch planned yet (rightStitchPose and leftStitchPose)";
    return Outcome::Missing;
  }
  const KDL::Rotation& frame = stitch_[0].M;
  const KDL::Vector centre = (stitch_[0].p + stitch_[1].p) * 0.5;
  // The last half's frame: y outward from the wound on its side (-y of the stitch frame on the right).
  const auto fromEdge = [&](const KDL::Vector& offset) {
    const double outward = last_half_ == 0 ? -1.0 : 1.0;
    return stitch_[last_half_].p + frame * KDL::Vector(offset.x(), outward * offset.y(), offset.z());
  };
  if (datum.name == "right_edge") pose = toolAt(frame, stitch_[0].p);
  else if (datum.name == "left_edge") pose = toolAt(frame, stitch_[1].p);
  else if (datum.name == "centre") pose = toolAt(frame, centre);
  else if (datum.name == "pull") pose = toolAt(frame, centre + frame * pull_offset_());
  else if (datum.name == "aside") pose = toolAt(frame, centre + frame * aside_offset_());
  else if (datum.name == "hook") pose = toolAt(frame, fromEdge(hook_offset_()));
  else pose = toolAt(frame, fromEdge(push_offset_()));  // "push": the parser admits no other name
  return Outcome::Resolved;
}

void SuturingFrameGenerator::noData(const std::string& reason) {
  last_failure_ = reason;
  std::fprintf(stderr, "[cobra] SuturingFrameGenerator '%s': e_no_data: %s\n", name().c_str(), reason.c_str());
  emitEvent("e_no_data");
}

void SuturingFrameGenerator::answer() {
  if (right_stitch_.read(stitch_[0]) != core::FlowStatus::NoData) have_stitch_[0] = true;
  if (left_stitch_.read(stitch_[1]) != core::FlowStatus::NoData) have_stitch_[1] = true;
  if (right_meas_.read(measured_[0]) != core::FlowStatus::NoData) have_measured_[0] = true;
  if (left_meas_.read(measured_[1]) != core::FlowStatus::NoData) have_measured_[1] = true;
  if (task_state_.read(state_) == core::FlowStatus::NoData) {
    noData("no task state on currentTaskState yet");
    return;
  }
  if (puncturing::pathContains(state_.path.view(), right_half_state_())) last_half_ = 0;
  else if (puncturing::pathContains(state_.path.view(), left_half_state_())) last_half_ = 1;
  std::string no_row;
  const puncturing::StateRow* row = puncturing::rowFor(table_, state_.path.view(), state_table_file_(), no_row);
  if (row == nullptr) {
    noData(no_row);
    return;
  }
  const auto where = [&] { return puncturing::rowWhere(state_.path.view(), state_table_file_(), *row); };
  if (!puncturing::firstGoal(*row, vocabulary().arms, *this, goal_pair_, failure_)) {
    noData(where() + failure_.message());
    return;
  }
  if (!have_measured_[0] || !have_measured_[1]) {
    noData(where() + "desiredPoses starts at the measured poses: no pose on " +
           (have_measured_[0] ? "leftMeasPose" : "rightMeasPose") + " yet");
    return;
  }
  if (puncturing::hasChecks(*row)) {
    std::vector<std::vector<double>> waypoints;
    if (!puncturing::checkedGoals(*row, vocabulary().arms, *this, waypoints, failure_)) {
      noData(where() + failure_.message());
      return;
    }
    goal_poses_.write(trajectory::MultiAxisPath(std::move(waypoints)));
  } else {
    for (std::size_t a = 0; a < kArms; ++a) puncturing::encodePose(goal_pair_[a], a, goal_.waypoint(0));
    goal_poses_.write(goal_);
  }
  for (std::size_t a = 0; a < kArms; ++a) {
    puncturing::encodePose(measured_[a], a, desired_.waypoint(0));
    puncturing::encodePose(goal_pair_[a], a, desired_.waypoint(1));
  }
  last_failure_.clear();
  desired_poses_.write(desired_);
  emitEvent("e_goal_ready");
}

}  // namespace cobra::components
