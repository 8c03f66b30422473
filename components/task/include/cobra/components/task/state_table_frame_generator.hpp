#pragma once
/// @file
/// The Frame Generator of a two-arm task (thesis §4.5.5, after it §5.5): on request, the goal poses
/// of both arms for the task's current state, from a state table (cobra/task/state_table.hpp). A
/// thin adapter over cobra::task: the table, its goal alternatives and their checks are the
/// library's; this component maps them onto ports, properties and a request.
///
/// Every task configures it with its table file. The datums every table has are resolved here:
/// `hold` (the arm's measured pose) and the table's own `pose`s. A task whose goals need data of
/// its own (a plan, a stitch) derives from it and resolves its vocabulary's datums
/// (resolveTaskDatum), the way apps/puncturing's and apps/suturing's Frame Generators do in their
/// packages. Registered as "StateTableFrameGenerator" in the package "cobra_task" with the arms
/// `arm1` and `arm2`, for tasks whose goals are fixed poses and holds.

#include <array>
#include <string>
#include <string_view>
#include <vector>

#include <kdl/frames.hpp>

#include "cobra/components/motion/path_type.hpp"
#include "cobra/core/component.hpp"
#include "cobra/core/event.hpp"
#include "cobra/core/request.hpp"
#include "cobra/task/goals.hpp"
#include "cobra/task/state_table.hpp"

namespace cobra::components {

/// Bridge.
///
/// Interface:
/// - property `state_table_file` (path; read at configure: a bad file refuses configure with
///   "component 'X': FILE:LINE: message");
/// - inputs `currentTaskState` (TaskState: the chart's active state) and one measured pose per
///   arm (KDL.Frame, m, world; the task names them, e.g. `needleMeasPose`; `arm1MeasPose` and
///   `arm2MeasPose` for the generic one);
/// - outputs `desiredPoses` (TGL.MultiAxisPath, two waypoints [measured pair, goal pair], 7 values
///   per arm, x y z qx qy qz qw, arm 0 first, as path_type.hpp encodes them: the
///   CartesianTrajectoryGenerator's plannedPath; its goal is the row's first alternative) and
///   `goalPoses` (the MotionPlanner's goalPoses: one waypoint per goal alternative of the row, the
///   preferred first; 14 values (the goal pair) for a row without then_* or room_for_*, otherwise
///   28 + 28 per room_for_*: the goal pair, where the straight motion after it goes (then_*; the
///   goal again for an arm without one), and per room_for_* that arm's later motion as its start
///   pair and end pair with the other arm at its goal; left out when the task says the motion
///   will not come);
/// - operations `askCurrentGoal()` (a void request answered in this component's next step with
///   e_goal_ready or e_no_data), `lastFailure()` (why the last e_no_data: the state, the table's
///   line, the datum; at most task::FailureText::kCapacity characters; run in this component's
///   activity between two steps, so it reads the text the step wrote without a race).
///
/// Real time: updateHook allocates nothing, blocks on nothing, throws nothing and writes nothing
/// to stderr, as long as the task's datums resolve without allocating: desiredPoses, the goal of a
/// row without checks and the goalPoses of every row with checks (one path per such row, its
/// waypoints reserved for every room_for_* coming) are preallocated at configure and refilled in
/// place; e_no_data's reason is written into a fixed buffer (task::FailureText). What a
/// connection does with a path is the channel's: it copy-assigns it into its slots, which
/// allocates when a path has more waypoints than the slot held before.
class StateTableFrameGenerator : public core::Component, protected task::DatumSource {
 public:
  /// The generic generator: arms `arm1` and `arm2`, datums `hold` and the table's poses.
  explicit StateTableFrameGenerator(std::string name);

  const task::StateTable& table() const { return table_; }
  /// Its type's name ("StateTableFrameGenerator", "PuncturingFrameGenerator").
  const std::string& kind() const { return kind_; }
  const task::TableVocabulary& vocabulary() const { return vocabulary_; }
  /// The request askCurrentGoal (from any thread): answered in the next step.
  void askCurrentGoal() { goal_request_.ask(activity()); }

 protected:
  /// One arm's measured-pose input port: its name and documentation.
  struct MeasuredPort {
    std::string name, doc;
  };

  /// A task's Frame Generator: `kind` is its type's name ("PuncturingFrameGenerator"), `doc`
  /// describes it, `vocabulary` gives its table's words, `measured` its arms' input ports.
  StateTableFrameGenerator(std::string name, std::string kind, std::string doc, task::TableVocabulary vocabulary,
                           std::array<MeasuredPort, 2> measured);

  // What a task adds (all optional but resolveTaskDatum, for a vocabulary with datums).
  /// At configure, before the table is read: the task's own files and properties.
  /// False (after refuse("why")) refuses configure.
  virtual bool configureTask() { return true; }
  /// In the step of an answer, before anything else: read the task's own inputs.
  virtual void readTaskInputs() {}
  /// In the step of an answer, once the task state is known, before its row is looked up.
  virtual void taskStateRead(std::string_view /*path*/) {}
  /// In every step, before a pending askCurrentGoal is answered: the task's own requests.
  virtual void stepTask() {}
  /// The pose (m, rad, world) of a datum of the vocabulary's own (not hold, not a table pose) for
  /// `arm`, before its offset. Must allocate nothing when it resolves.
  virtual Outcome resolveTaskDatum(const task::Datum& datum, std::size_t arm, KDL::Frame& pose, const char*& why);
  /// Forgets what the answers saw (measured poses, task state, last failure) and a pending request.
  void resetAnswers();
  /// Answers e_no_data with `reason` (kept for lastFailure(), truncated to its buffer). Real-time safe.
  void noData(std::string_view reason) noexcept;
  const std::string& tableFile() const { return state_table_file_(); }
  /// The last task state read (in the step of an answer).
  const core::TaskState& taskState() const { return state_; }

  bool configureHook() override;
  void updateHook() override;

 private:
  Outcome resolve(const task::Datum& datum, std::size_t arm, KDL::Frame& pose, const char*& why) final;
  void answer();
  /// Answers e_no_data with what failure_text_ holds.
  void noData() noexcept;
  /// failure_text_ = "task state 'S' (FILE:LINE): ", the start of a failure of `row`.
  void startRowFailure(const task::StateRow& row) noexcept;

  std::string kind_;
  task::TableVocabulary vocabulary_;
  std::array<MeasuredPort, 2> measured_names_;
  std::array<std::string, 2> hold_why_;  // "no pose on <port> yet", per arm

  core::Property<std::string> state_table_file_{"state_table_file", "", "", "state -> goal datum of each arm"};
  core::InputPort<core::TaskState> task_state_{"currentTaskState", "the task chart's active state", ""};
  std::array<core::InputPort<KDL::Frame>, 2> measured_ports_;
  core::OutputPort<trajectory::MultiAxisPath> desired_poses_;
  core::OutputPort<trajectory::MultiAxisPath> goal_poses_;

  task::StateTable table_;
  core::TaskState state_;
  std::array<KDL::Frame, 2> measured_, goal_pair_;  // goal_pair_: the row's first alternative
  std::array<bool, 2> have_measured_{false, false};
  trajectory::MultiAxisPath desired_, goal_;  // preallocated: 2 x 14 and 1 x 14 values
  // The goalPoses of row i of table_ when it has checks (empty otherwise): goalAlternatives
  // waypoints, each reserved for checkedGoalValues values at configure.
  std::vector<trajectory::MultiAxisPath> checked_goals_;
  task::GoalFailure failure_;
  task::FailureText failure_text_;  // why the last e_no_data ("" after an answer)
  core::PendingRequest goal_request_;
};

}  // namespace cobra::components
