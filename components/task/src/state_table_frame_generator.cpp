#include "cobra/components/task/state_table_frame_generator.hpp"

#include <functional>
#include <stdexcept>

#include "cobra/task/statements.hpp"

namespace cobra::components {
namespace {

constexpr std::size_t kArms = 2;
static_assert(task::kPoseValues == kValuesPerArm, "the table's goal encoding is the motion components' path encoding");

std::string pairDoc(const task::TableVocabulary& v) {
  return v.arms[0] + " then " + v.arms[1] + ", x y z qx qy qz qw each, world";
}

}  // namespace

StateTableFrameGenerator::StateTableFrameGenerator(std::string name)
    : StateTableFrameGenerator(std::move(name), "StateTableFrameGenerator",
                               "Frame Generator (thesis §4.5.5): the goal poses of two arms for the current task "
                               "state, from a state table of fixed poses and holds",
                               task::TableVocabulary{{"arm1", "arm2"}, {}},
                               {MeasuredPort{"arm1MeasPose", "measured pose of arm1's tool, world"},
                                MeasuredPort{"arm2MeasPose", "measured pose of arm2's tool, world"}}) {}

StateTableFrameGenerator::StateTableFrameGenerator(std::string name, std::string kind, std::string doc,
                                                   task::TableVocabulary vocabulary,
                                                   std::array<MeasuredPort, 2> measured)
    : Component(std::move(name), core::Role::Bridge, std::move(doc)),
      kind_(std::move(kind)),
      vocabulary_(std::move(vocabulary)),
      measured_names_(std::move(measured)),
      measured_ports_{core::InputPort<KDL::Frame>(measured_names_[0].name, measured_names_[0].doc, "m"),
                      core::InputPort<KDL::Frame>(measured_names_[1].name, measured_names_[1].doc, "m")},
      desired_poses_("desiredPoses", "[measured pair, goal pair]: " + pairDoc(vocabulary_), "m"),
      goal_poses_("goalPoses",
                  "goal alternatives, one waypoint each: the goal pair (" + pairDoc(vocabulary_) +
                      "), with the checks of its row (then_*, room_for_*) after it",
                  "m") {
  for (std::size_t a = 0; a < kArms; ++a) hold_why_[a] = "no pose on " + measured_names_[a].name + " yet";
  addProperty(state_table_file_);
  addPort(task_state_);
  addPort(measured_ports_[0]);
  addPort(measured_ports_[1]);
  addPort(desired_poses_);
  addPort(goal_poses_);
  addOperation("askCurrentGoal", std::function<void()>([this] { askCurrentGoal(); }),
               "publishes desiredPoses [measured pair, goal pair] and goalPoses for the task state on "
               "currentTaskState, in this component's next step; answers e_goal_ready or e_no_data (reason: "
               "lastFailure)",
               core::ExecutionThread::Client);
  addOperation("lastFailure", std::function<std::string()>([this] { return std::string(failure_text_.view()); }),
               "why the last askCurrentGoal answered e_no_data (empty when it did not)");
}

bool StateTableFrameGenerator::configureHook() {
  if (!configureTask()) return false;
  if (state_table_file_().empty()) return refuse("property state_table_file is empty; give the path of its file");
  try {
    table_ = task::parseStateTable(task::readText(state_table_file_()), state_table_file_(), vocabulary_);
  } catch (const std::invalid_argument& e) {
    return refuse(e.what());
  }
  resetAnswers();
  desired_ = trajectory::MultiAxisPath(std::vector<std::vector<double>>(2, std::vector<double>(kArms * kValuesPerArm)));
  goal_ = trajectory::MultiAxisPath(std::vector<std::vector<double>>(1, std::vector<double>(kArms * kValuesPerArm)));
  checked_goals_.assign(table_.rows.size(), trajectory::MultiAxisPath());
  for (std::size_t i = 0; i < table_.rows.size(); ++i) {
    const task::StateRow& row = table_.rows[i];
    if (!task::hasChecks(row)) continue;
    std::vector<std::vector<double>> waypoints(task::goalAlternatives(row));
    for (std::vector<double>& values : waypoints) values.reserve(task::checkedGoalValues(row));
    checked_goals_[i] = trajectory::MultiAxisPath(std::move(waypoints));
  }
  desired_poses_.setDataSample(desired_);
  goal_poses_.setDataSample(goal_);
  return true;
}

void StateTableFrameGenerator::resetAnswers() {
  have_measured_ = {false, false};
  state_ = {};
  failure_text_.clear();
  goal_request_.clear();
}

void StateTableFrameGenerator::updateHook() {
  stepTask();
  if (goal_request_.take()) answer();
}

task::DatumSource::Outcome StateTableFrameGenerator::resolveTaskDatum(const task::Datum&, std::size_t, KDL::Frame&,
                                                                      const char*& why) {
  why = "the datum has no source (the generic Frame Generator knows hold and the table's poses only)";
  return Outcome::Missing;
}

task::DatumSource::Outcome StateTableFrameGenerator::resolve(const task::Datum& datum, std::size_t arm,
                                                             KDL::Frame& pose, const char*& why) {
  if (datum.name == "hold") {
    if (!have_measured_[arm]) {
      why = hold_why_[arm].c_str();  // made at construction: nothing allocated here
      return Outcome::Missing;
    }
    pose = measured_[arm];
    return Outcome::Resolved;
  }
  if (const KDL::Frame* fixed = table_.pose(datum.name)) {
    pose = *fixed;
    return Outcome::Resolved;
  }
  return resolveTaskDatum(datum, arm, pose, why);
}

void StateTableFrameGenerator::noData(std::string_view reason) noexcept {
  failure_text_.clear();
  failure_text_ << reason;
  noData();
}

void StateTableFrameGenerator::noData() noexcept { emitEvent("e_no_data"); }

void StateTableFrameGenerator::startRowFailure(const task::StateRow& row) noexcept {
  failure_text_.clear();
  task::rowWhere(state_.path.view(), state_table_file_(), row, failure_text_);
}

void StateTableFrameGenerator::answer() {
  readTaskInputs();
  for (std::size_t a = 0; a < kArms; ++a)
    if (measured_ports_[a].read(measured_[a]) != core::FlowStatus::NoData) have_measured_[a] = true;
  if (task_state_.read(state_) == core::FlowStatus::NoData) {
    noData("no task state on currentTaskState yet");
    return;
  }
  taskStateRead(state_.path.view());
  failure_text_.clear();
  const task::StateRow* row = task::rowFor(table_, state_.path.view(), state_table_file_(), failure_text_);
  if (row == nullptr) {
    noData();
    return;
  }
  if (!task::firstGoal(*row, vocabulary_.arms, *this, goal_pair_, failure_)) {
    startRowFailure(*row);
    failure_.write(failure_text_);
    noData();
    return;
  }
  for (std::size_t a = 0; a < kArms; ++a) {
    if (!have_measured_[a]) {
      startRowFailure(*row);
      failure_text_ << "desiredPoses starts at the measured poses: no pose on " << measured_names_[a].name << " yet";
      noData();
      return;
    }
  }
  for (std::size_t a = 0; a < kArms; ++a) {
    task::encodePose(measured_[a], a, desired_.waypoint(0));
    task::encodePose(goal_pair_[a], a, desired_.waypoint(1));
  }
  if (task::hasChecks(*row)) {
    trajectory::MultiAxisPath& checked = checked_goals_[static_cast<std::size_t>(row - table_.rows.data())];
    // MultiAxisPath's waypoints are one std::vector: refilled in place through the first's address.
    if (!task::checkedGoals(*row, vocabulary_.arms, *this, std::span(&checked.waypoint(0), checked.size()), failure_)) {
      startRowFailure(*row);
      failure_.write(failure_text_);
      noData();
      return;
    }
    desired_poses_.write(desired_);
    goal_poses_.write(checked);
  } else {
    for (std::size_t a = 0; a < kArms; ++a) task::encodePose(goal_pair_[a], a, goal_.waypoint(0));
    desired_poses_.write(desired_);
    goal_poses_.write(goal_);
  }
  emitEvent("e_goal_ready");
}

}  // namespace cobra::components
