#pragma once
/// @file
/// The thesis' Motion Planner (§4.5.1): a Calculation component around planning::MotionPlanner
/// (OMPL in the robots' joint space from their measured joints to Cartesian goals, FCL collision
/// checks, the real I-SUR and UR5 kinematics; planning/README.md).

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <kdl/frames.hpp>
#include <kdl/jntarray.hpp>

#include "cobra/components/motion/path_type.hpp"
#include "cobra/components/planning/planning_scene_component.hpp"
#include "cobra/core/request.hpp"
#include "cobra/planning/motion_planner.hpp"

namespace cobra::components {

/// Interface (thesis names; scene properties: PlanningSceneComponent):
/// - properties `planner` (one of planning::plannerNames(): RRTConnect, RRT, PRM, BiTRRT, LazyPRM,
///   LBKPIECE1, BITstar), `time_limit` (s, wall clock),
///   `max_validity_checks` (1: the work limit of a query instead of time_limit when > 0),
///   `seed` (> 0; a query that failed is retried with the next seed, so asking again after a
///   failure explores differently and the run stays reproducible), `first_bounds_low/high`,
///   `second_bounds_low/high` (3 values each, m: the world box of the needle / probe positions),
///   `edge_resolution` (fraction of the space extent); `max_vel` (m/s per Cartesian axis),
///   `max_ang_vel` (rad/s), `time_acc` (s): those of the CartesianTrajectoryGenerator that follows
///   the path (the joint steps of the path are checked against the robots' joint velocity limits
///   at these speeds); `query_log` (path, "" = none: every planning query from measured joints is
///   appended as one line `start Q1..Qn goal X Y Z QX QY QZ QW X Y Z QX QY QZ QW # outcome`, the
///   format bench/planning_bench.cpp replays; read when a plan is asked);
/// - ports in: `isurMeasJoints`, `UR5MeasJoints` (KDL.JntArray: the measured joints, I-SUR
///   [q1 q2 q3 m, q4..q8 rad; 14 on the suturing scene], UR5 [6 rad]; the start state when those
///   of every robot of the scene have data (the suturing scene: the I-SUR's only): the path starts
///   on the robots' actual IK branches), `isurMeasPose`, `UR5MeasPose` (KDL.Frame, world, m: the
///   start state without joints, solved by IK from the models' seeds; event ports: a new sample
///   triggers the distance report), `goalPoses` (TGL.MultiAxisPath: one waypoint per goal
///   ALTERNATIVE, the preferred first, each of 14 values: the needle then the probe goal, each
///   x y z [m] qx qy qz qw, world frame: the encoding of path_type.hpp; or of 28 + 28·k values:
///   the goal pair, the pair where the straight motion after it (a motion primitive) takes the
///   tools (the goal again: none), then k later straight motions as start and end pairs that the
///   goal must leave room for (e.g. the probe's next approach and descent while the needle waits
///   at this goal). askPlan takes the first alternative whose goal state is valid, whose later
///   motions can be made beside it (MotionPlanner::checkMotion from the measured joints), to
///   which a path is found and whose follow-on can be made (colliding or jumping a joint fails);
///   none: e_plan_failed with each alternative's reason, before anything moves);
///   out: `plannedPath` (TGL.MultiAxisPath, 2 arms, path_type.hpp's encoding: what
///   CartesianTrajectoryGenerator reads), `minDistance` (double, m: the measured state's clearance,
///   the minimum distance over the checked group pairs OUTSIDE the scene's declared contacts
///   (`allow` and `primitive_contact`), what planned paths keep above clearanceThreshold(); NaN
///   when the measured state is not a pose or unreachable), `allowedContactDistance` (double, m:
///   the minimum distance of the scene's allowed contacts, e.g. the probe on the skin: 0 while
///   touching; +inf when none declared; NaN as minDistance), `primitiveContactDistance` (double, m:
///   the same for its primitive contacts, e.g. the needle in the tissue); published when a
///   measured pose arrives at least `clearance_period` s (property, default 0.01) after the last
///   measurement while one of them is connected (a connection is seen within clearance_period), from the joints when known (the same joints as
///   the last measurement: the same values, not measured again);
/// - operations `askPlan()` (void, returns at once: the request runs in this component's next
///   step), `checkDistancePoses(Frame, Frame)` (min distance in m for the two tool poses; NaN
///   when unreachable; runs between two steps, so a caller waits while a plan is being computed),
///   `lastPlanResult()` ("solved: ..." or the reason of the last failure), `clearanceThreshold()`
///   (m: the scene's min_collision_distance after the property override; a state closer than this
///   outside the allowed contacts is invalid for the planner);
/// - events `e_plan_done` (path written on plannedPath), `e_plan_failed` (reason in
///   lastPlanResult() and on stderr: an unreachable goal, or one only another IK branch reaches,
///   names the tool and why, before anything moves).
///
/// Where planning runs: in updateHook, when askPlan() asked for it. Planning takes up to
/// `time_limit` s and allocates, so this component must have a NON-real-time activity of its own:
/// an EventActivity with Scheduler::Other in a threaded deployment (askPlan() triggers it), or
/// period 0 on a LockstepClock (it then steps in the same simulated instant as the component that
/// called askPlan(), after it: simulated time does not advance while it plans, and RRTConnect/RRT
/// are seeded, so a lockstep run is reproducible; with `max_validity_checks` set even a query at
/// its limit fails or succeeds the same on any machine, while `time_limit` depends on the
/// machine's speed and load). startHook refuses a periodic activity.
class MotionPlannerComponent : public PlanningSceneComponent {
 public:
  explicit MotionPlannerComponent(std::string name);
  ~MotionPlannerComponent() override;

 protected:
  bool configureHook() override;
  bool startHook() override;
  void updateHook() override;
  void cleanupHook() override;

  /// For a component that asks more of the same planner (e.g. a whole procedure verified before
  /// it starts, apps/puncturing): the planner as configured (its options are the properties; the
  /// seed of its next query) and its scene's validator; nullptr before configure.
  const planning::MotionPlanner* planner() const { return planner_impl_.get(); }
  planning::StateValidator* validator() { return validator_.get(); }
  /// Reads the joint ports now: every robot's latest measured joints into `q` (the scene's
  /// order); false, with `why` saying what the ports gave, when a robot's are missing.
  bool latestJoints(planning::JointState& q, std::string& why);
  /// A path found before for this query (e.g. when the whole procedure was verified): true with
  /// `result` to take instead of a search (a solved path from `start`, whose tool poses are
  /// `start_poses`, to `goal`: the follow-on check still runs; or a refusal, which fails this
  /// alternative without a search); false to search. `alternative`: the goal's index among the
  /// goal alternatives of the query (0-based, the state table's order). Asked only when the start
  /// is the measured joints. The base finds none.
  virtual bool reusePath(const planning::JointState& start, const planning::DualPose& start_poses,
                         const planning::DualPose& goal, std::size_t alternative, planning::PlanResult& result);

 private:
  void askPlan();
  double checkDistancePoses(KDL::Frame first, KDL::Frame second);
  /// One goal alternative of goalPoses and what it is verified with.
  struct GoalAlternative {
    planning::DualPose goal;
    planning::DualPose follow_on;  // where the straight motion after the goal goes (has_follow_on)
    bool has_follow_on = false;
    /// Later straight motions (start pair, end pair) the goal must leave room for.
    std::vector<std::pair<planning::DualPose, planning::DualPose>> room;
  };
  /// alternatives_ from a goalPoses sample. @throws std::invalid_argument saying what is wrong.
  void readGoal(const trajectory::MultiAxisPath& goal);
  /// One alternative: (with `checked_first`) its goal and room checks, the search, its follow-on.
  planning::PlanResult planAlternative(const GoalAlternative& a, std::size_t index, bool from_joints, bool checked_first);
  /// Appends the query and its outcome to query_log (when set).
  void logQuery(const planning::DualPose& goal, const planning::PlanResult& result) const;
  /// Runs one query from the measured poses to the goal; writes the path or says why not.
  void plan();
  void fail(const std::string& reason);

  core::Property<std::string> planner_{"planner", "RRTConnect", "", "OMPL planner: RRTConnect, RRT, PRM, BiTRRT, LazyPRM, LBKPIECE1 or BITstar "
                                                            "(planning::plannerNames())"};
  core::Property<double> time_limit_{"time_limit", 1.0, "s", "wall-clock limit of one planning query"};
  core::Property<int> max_validity_checks_{"max_validity_checks", 0, "1",
                                           "work limit of one query in state validity checks or planner iterations, "
                                           "instead of time_limit (0: time_limit); the outcome then does not depend "
                                           "on the machine's speed"};
  core::Property<int> seed_{"seed", 1, "1", "seed of OMPL's random generators (> 0): same seed, same path"};
  core::Property<std::vector<double>> first_low_{"first_bounds_low", {-0.3, -0.3, 0.0}, "m",
                                                 "lower corner of the needle (tool 1) position box, world"};
  core::Property<std::vector<double>> first_high_{"first_bounds_high", {0.3, 0.3, 0.5}, "m",
                                                  "upper corner of the needle (tool 1) position box, world"};
  core::Property<std::vector<double>> second_low_{"second_bounds_low", {-0.4, -0.5, 0.0}, "m",
                                                  "lower corner of the probe (tool 2) position box, world"};
  core::Property<std::vector<double>> second_high_{"second_bounds_high", {0.4, 0.4, 0.6}, "m",
                                                   "upper corner of the probe (tool 2) position box, world"};
  core::Property<double> edge_resolution_{"edge_resolution", 0.004, "1",
                                          "edge check step as a fraction of the state space extent"};
  core::Property<double> max_vel_{"max_vel", 0.05, "m/s",
                                  "max velocity per Cartesian axis of the trajectory generator following the path"};
  core::Property<double> max_ang_vel_{"max_ang_vel", 0.5, "rad/s",
                                      "max angular velocity of the trajectory generator following the path"};
  core::Property<double> time_acc_{"time_acc", 0.2, "s", "blend duration of the trajectory generator"};
  core::Property<std::string> query_log_{"query_log", "", "path",
                                         "file every query is appended to (start joints, goal poses, outcome); "
                                         "'' = none"};
  core::Property<double> clearance_period_{
      "clearance_period", 0.01, "s",
      "least time between two clearance measurements of the measured state (minDistance, "
      "allowedContactDistance); 0 = whenever a measured pose changes"};

  core::InputPort<KDL::Frame> isur_meas_{"isurMeasPose", "measured needle tip pose (start state), world", "m"};
  core::InputPort<KDL::Frame> ur5_meas_{"UR5MeasPose", "measured probe tip pose (start state), world", "m"};
  core::InputPort<trajectory::MultiAxisPath> goal_{
      "goalPoses", "goal alternatives, one waypoint each, the preferred first: the needle then the probe goal, "
      "x y z qx qy qz qw each, world; with 28 + 28 k values: then where the straight motion after the goal goes, "
      "and k later motions (start pair, end pair) it must leave room for", "m"};
  core::OutputPort<trajectory::MultiAxisPath> path_out_{
      "plannedPath", "collision-free path, 2 arms, x y z qx qy qz qw per arm per waypoint, world", "m"};
  core::InputPort<KDL::JntArray> isur_joints_{"isurMeasJoints", "measured I-SUR joints (start state): q1..q3 m, q4..q8 rad",
                                              "m, rad"};
  core::InputPort<KDL::JntArray> ur5_joints_{"UR5MeasJoints", "measured UR5 joints (start state)", "rad"};
  core::OutputPort<double> min_distance_{
      "minDistance", "clearance of the measured state outside the declared contacts (NaN: unreachable)", "m"};
  core::OutputPort<double> allowed_distance_{
      "allowedContactDistance", "distance of the scene's allowed contacts in the measured state", "m"};
  core::OutputPort<double> primitive_distance_{
      "primitiveContactDistance",
      "distance of the scene's primitive contacts (made by the motion primitives) in the measured state", "m"};
  core::OutputPort<std::vector<double>> pair_distances_{
      "pairDistances", "clearance of the measured state per pair of groups (operation clearancePairs names them): "
      "its moving object pairs outside the declared contacts (NaN: unreachable)", "m"};

  std::unique_ptr<planning::StateValidator> validator_;
  std::int64_t last_clearance_ns_ = -1;  // when minDistance was last measured (component clock), -1: never
  // The joint state of the last clearance measurement and its result: a robot at rest (its
  // encoders unchanged) is not measured again.
  planning::JointState clearance_joints_;
  planning::StateValidator::Distances clearance_;
  std::vector<double> pair_values_;  // pairDistances' sample, sized at configure
  std::unique_ptr<planning::MotionPlanner> planner_impl_;
  core::PendingRequest plan_request_;
  bool have_isur_ = false;
  bool have_ur5_ = false;
  bool have_goal_ = false;
  bool have_isur_joints_ = false;
  bool have_ur5_joints_ = false;
  KDL::JntArray isur_q_, ur5_q_;
  planning::JointState joints_;  // the scene's joint layout, filled from the two joint ports
  /// Fills joints_ from the latest joint samples; false when they are missing or do not fit.
  bool measuredJoints();
  /// What the joint ports must give for this scene and what they gave (a failure's reason).
  std::string expectedJoints() const;
  planning::DualPose measured_;
  std::vector<GoalAlternative> alternatives_;  // the latest goalPoses, the preferred first
  std::string last_result_;
};

}  // namespace cobra::components
