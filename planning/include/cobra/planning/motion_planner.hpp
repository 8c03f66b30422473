#pragma once
/// @file
/// planPath (thesis Algorithm 4.1) in the robots' JOINT space: start = the robots' (measured)
/// joints, goal = the two tool poses, turned into joints by the continuity-keeping IK nearest the
/// start on the start's branch; OMPL searches the joints of the robots that move (forward
/// kinematics + FCL per state, no IK), then the path is returned as Cartesian waypoints (what the
/// Cartesian trajectory generator follows) that are verified, and densified where needed, so that
/// the Cartesian interpolation between waypoints is collision-free AND joint-continuous for the
/// control path's IK at the generator's speed limits (README: "Joint-space planning").
/// Scenes whose robot models offer no joint space (stand-in robots of the tests) are planned as before on
/// SE(3)×SE(3) with IK inside the validity check.

#include <array>
#include <span>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cobra/planning/state_validator.hpp"

namespace cobra::planning {

/// Axis-aligned bounds of one tool's position in the world frame [m]. Rotations are unbounded.
struct PositionBounds {
  std::array<double, 3> low{-1.0, -1.0, -1.0};
  std::array<double, 3> high{1.0, 1.0, 1.0};
  bool contains(const KDL::Vector& p) const;
};

/// Every robot's joints concatenated in the scene's robot order (StateValidator::jointOffset), m and rad.
using JointState = std::vector<double>;

/// The OMPL planners planPath() can use: RRTConnect, RRT, PRM, BiTRRT, LazyPRM, LBKPIECE1, BITstar.
const std::vector<std::string>& plannerNames();

/// Planner configuration (the component's properties).
struct PlannerOptions {
  /// One of plannerNames(); RRTConnect by default (the thesis' choice, and the fastest in
  /// bench/planning_bench.cpp: see the README).
  std::string planner = "RRTConnect";
  /// Wall-clock limit of the search [s] (when max_validity_checks is 0).
  double time_limit = 1.0;
  /// Work limit of the search instead of time_limit: the search stops after this many state
  /// validity checks or this many planner iterations, whichever comes first [1] (0: time_limit
  /// applies). Its outcome then depends on the seed alone, not on the machine's speed or load: a
  /// lockstep simulation plans the same on a laptop and on a busy CI machine. About 50,000 checks
  /// take 1 s in the puncturing scene (bench/planning_bench). The iterations bound the lazy
  /// planners (LazyPRM, LBKPIECE1, BITstar), which add samples without checking them and could
  /// otherwise grow their roadmap forever; RRTConnect and RRT check at least one state per
  /// iteration, so the checks bound them first. A lazy planner finishes the path check it is in
  /// (LazyPRM: the candidate paths of one roadmap component) before it stops.
  std::size_t max_validity_checks = 0;
  /// Seed of OMPL's random generators (> 0): same seed, scene and query → same path, for
  /// RRTConnect and RRT. PRM grows its roadmap while another thread looks for a solution, so its
  /// result depends on timing.
  std::uint32_t seed = 1;
  /// Bounds of the first and second tool positions [m].
  PositionBounds first_bounds;
  PositionBounds second_bounds;
  /// Edge check step as a fraction of the space's extent (OMPL's state validity checking
  /// resolution, whose own default is 0.01); smaller finds fewer paths that the dense verification
  /// then rejects, and is slower. 0.004 halves the planning time of the puncturing benchmark
  /// against 0.002 at the same success rate (bench/planning_bench.cpp): the returned path is
  /// guaranteed by the verification below, not by this step. A search re-run after a path failed
  /// the verification checks edges twice as finely as the one before (down to 1/8 of this).
  double edge_resolution = 0.004;
  /// Shorten and smooth the found path (OMPL's PathSimplifier, bounded by `simplify_steps`).
  bool simplify = true;
  /// Number of vertices checked per segment when the final path is verified, at least [1]: the
  /// verification walks each segment in this many steps where the joints' speeds are steady, and
  /// in finer steps (down to 1 ms of the generator's time, the robots' control period) where a
  /// joint's speed changes within a step or nears its limit (near a singular set). A path that
  /// fails the verification is discarded and the search re-run with seed + 1, + 2, ... while
  /// time_limit allows (PathInvalid when none passes).
  std::size_t verify_points_per_segment = 100;
  /// Range of one RRT/RRT-Connect extension in the state-space metric (SE(3): position [m] plus
  /// rotation angle [rad]; joint space: s at the joints' velocity limits); 0 lets OMPL choose.
  double range = 0.0;

  // ---- The Cartesian trajectory generator that follows the path (its properties max_vel,
  // max_ang_vel, time_acc): how fast it may run a segment bounds the joint steps the dense
  // verification accepts.
  /// Maximum velocity of each Cartesian position axis of either tool [m/s].
  double max_linear_velocity = 0.05;
  /// Maximum angular velocity of either tool [rad/s].
  double max_angular_velocity = 0.5;
  /// Blend duration [s]: no segment lasts less.
  double blend_time = 0.2;
  /// Share of each joint's velocity limit a path may need when the generator runs it at the
  /// limits above [1] (its blends pass from one segment's speed to the next monotonically, so a
  /// segment's mean speed bounds them; the rest is for the servo's lag).
  double joint_velocity_margin = 0.8;
  /// Share of the budget (max_validity_checks, else time_limit) the first search spends in a box
  /// around the start and the goal before the whole space is searched [1] (0: the whole space
  /// at once). The box holds, per planning coordinate, the interval between the start's and the
  /// goal's values widened on each side by half its length plus kLocalMargin s at the joint's
  /// velocity limit (within the coordinate's bounds): most queries are solved near the straight
  /// line, where the search's samples land only a small fraction of the time in the whole space.
  double local_search_share = 0.25;
  /// How often a segment that fails the dense verification may be halved (in joint space) [1].
  std::size_t max_subdivisions = 8;
  /// Names of the two tools in messages (the component: "needle", "probe").
  std::array<std::string, 2> tool_names{"first tool", "second tool"};
};

/// Outcome of planPath().
enum class PlanStatus {
  Solved,
  InvalidInput,   ///< NaN/infinite pose or non-orthonormal rotation
  OutOfBounds,    ///< start or goal position outside the bounds
  InvalidStart,   ///< the start state is not valid (see `rejected`)
  InvalidGoal,    ///< the goal state is not valid (see `rejected`)
  NoSolution,     ///< no path within the time limit (the thesis' e_plan_failed)
  PathInvalid,    ///< a path was found but failed the dense verification (lower edge_resolution)
  PlannerError,   ///< OMPL threw (the message says why)
};

/// "solved", "invalid input", ...
const char* toString(PlanStatus status);

/// A planned path: waypoints in the world frame, first = start, last = goal. Between two waypoints
/// the tools move along a straight line with spherical linear interpolation of the rotation (as
/// OMPL's SE(3) interpolation); the trajectory library turns the list into a MultiAxisPath.
struct PlanResult {
  PlanStatus status = PlanStatus::NoSolution;
  /// Solved: the path; PathInvalid: the rejected path (for diagnosis); otherwise empty.
  std::vector<DualPose> waypoints;
  /// InvalidStart/InvalidGoal/PathInvalid: why the state was rejected.
  ValidityResult rejected;
  /// Human-readable cause, naming start/goal and the failed check.
  std::string message;
  /// Time spent in the search and simplification [s].
  double planning_time = 0.0;
  /// State validity checks of the searches (all seeds tried), the unit of max_validity_checks.
  std::size_t validity_checks = 0;
  /// Searches run (joint-space planning: one per seed tried; more than one when a found path
  /// failed the dense verification and the search was re-run with the next seed) [1].
  std::size_t searches = 0;
  /// Joint-space planning, Solved: the joints the control path's IK reaches at each waypoint
  /// (tracked along the verified Cartesian path from the start), one JointState per waypoint.
  std::vector<JointState> joint_waypoints;
  bool solved() const { return status == PlanStatus::Solved; }
};

/// Motion planner over a StateValidator (which it borrows; it must outlive the planner).
/// Not thread-safe: one planPath() at a time.
class MotionPlanner {
 public:
  /// @throws std::invalid_argument for an unknown planner name, a non-positive time limit or seed,
  ///         empty bounds or a resolution outside (0, 1].
  MotionPlanner(StateValidator& validator, PlannerOptions options);
  ~MotionPlanner();
  MotionPlanner(const MotionPlanner&) = delete;
  MotionPlanner& operator=(const MotionPlanner&) = delete;

  /// Algorithm 4.1 from the robots' joints `start` (StateValidator::jointCount() values) to the tool
  /// poses `goal`. Needs a scene whose robot models offer joints (StateValidator::hasJointSpace).
  /// Never throws for bad input: the status and message name the cause; a goal that is
  /// unreachable, or reachable only on another IK branch than the start's, is InvalidGoal naming
  /// the tool (PlannerOptions::tool_names) and why, before any search.
  /// `follow_on`: where the straight motion that follows the goal ends (a motion primitive, see
  /// checkFollowOn), when the query has one: the goal joints are chosen so that it can be made
  /// (RobotModel::inverseGoalAlternative when inverseGoal's cannot make it); the result's last
  /// joints are still to be checked with checkFollowOn, as the path may end them elsewhere.
  PlanResult planPath(const JointState& start, const DualPose& goal,
                      const std::optional<DualPose>& follow_on = std::nullopt);
  /// From tool poses: in joint space the start joints are the IK of `start` from each robot
  /// model's configured seed (on its branch); scenes without joint space plan on SE(3)×SE(3).
  PlanResult planPath(const DualPose& start, const DualPose& goal);

  /// Whether planPath(start, goal) would accept the query and search: the planner's own input,
  /// start, bounds and goal checks (the goal IK of the control path from the start, on its branch:
  /// RobotModel::inverseGoal; the goal state's validity with the robots whose tools stay put held
  /// at the start), without
  /// the search. Solved when accepted (then joint_waypoints is empty and the message says so),
  /// otherwise the status and message planPath would return. Not thread-safe, like planPath.
  PlanResult checkGoal(const JointState& start, const DualPose& goal,
                       const std::optional<DualPose>& follow_on = std::nullopt);
  /// The straight motion that follows a planned path (a motion primitive: e.g. the probe
  /// descending from its approach pose onto the skin, the needle's insertion from above its entry
  /// to its target; the scene's primitive contacts are allowed along it), checked as a returned
  /// path's segments are:
  /// walked densely from `joints` (the path's last joint waypoint, at `from`) to `to` with the
  /// control path's IK, every state valid and every joint step within its velocity limit at the
  /// generator's speeds. Solved, or InvalidGoal with a message naming `to` and why (so that a
  /// goal whose next motion cannot be made fails at plan time, before anything moves).
  PlanResult checkFollowOn(const JointState& joints, const DualPose& from, const DualPose& to);
  /// A straight motion that does not start on the planned path: e.g. where the other robot goes
  /// next while this one waits at its goal (the probe's next approach and descent beside the
  /// needle's waiting pose). `from` is turned into joints by the goal IK nearest `near` (the
  /// start's branch and redundancy rule, as planPath's goal), that state must be valid (the
  /// scene's primitive contacts allowed), then the motion is walked to `to` as checkFollowOn does.
  /// Solved, or InvalidGoal (InvalidInput) with a message naming `from`, `to` and why.
  PlanResult checkMotion(const JointState& near, const DualPose& from, const DualPose& to);

  const PlannerOptions& options() const { return options_; }
  /// Seed of the next planPath() (> 0; an invalid seed throws std::invalid_argument).
  void setSeed(std::uint32_t seed);

 private:
  /// The OMPL part of planPath() (after the input checks) with one seed, until time_limit s after
  /// `started` or max_validity_checks checks since the query began; may throw ompl::Exception.
  PlanResult search(const DualPose& start, const DualPose& goal, std::chrono::steady_clock::time_point started,
                    std::uint32_t seed);
  struct Layout;
  /// planPath(JointState) after its input checks: the goal joints, the search with the next seeds
  /// while a found path fails the verification.
  PlanResult planJoints(const JointState& start, const DualPose& start_poses, const DualPose& goal,
                        const std::optional<DualPose>& follow_on, std::chrono::steady_clock::time_point started);
  /// One joint-space search from `start` to `goal` moving the robots flagged in `moving`, then the
  /// Cartesian waypoints and their verification; `refinement`: how many found paths failed the
  /// verification before (each halves the edge resolution, down to an eighth); `local`: in the
  /// box around start and goal (local_search_share), until that share of the budget is spent. May
  /// throw ompl::Exception.
  PlanResult searchJoints(const JointState& start, const DualPose& start_poses, const JointState& goal,
                          const DualPose& goal_poses, const JointState& search_goal, const std::vector<bool>& moving,
                          std::chrono::steady_clock::time_point started, std::uint32_t seed, std::size_t refinement,
                          bool local);
  /// The joints the search heads for: `goal_joints` when every robot that moves is on its
  /// redundancy rule there (RobotModel::jointsOf of its coordinates), otherwise a valid
  /// configuration on the rule near the goal (the path's last segment then leaves the rule into
  /// the goal, as the controllers do), or the goal's projection on the rule when none is found.
  JointState searchGoal(const JointState& start, const DualPose& start_poses, const DualPose& goal,
                        const JointState& goal_joints, const std::vector<bool>& moving);
  /// planJoints for one choice of goal joints (valid, the motion after them checked): the
  /// searches, then the motion after the goal from where the found path ends (InvalidGoal when
  /// it cannot be made). `any`: whether a robot moves at all.
  PlanResult reachGoal(const JointState& start, const DualPose& start_poses, const DualPose& goal,
                       const JointState& goal_joints, const std::vector<bool>& moving, bool any,
                       const std::optional<DualPose>& follow_on, std::chrono::steady_clock::time_point started);
  /// Half-width added on each side of the local search's box, in s at the velocity limit.
  static constexpr double kLocalMargin = 0.5;
  /// The goal joints nearest `start` (status InvalidGoal with the message when there are none):
  /// StateValidator::inverseGoal's, or its alternative's (`alternative_taken`) when a robot's first
  /// goal is not reachable.
  PlanResult goalJoints(const JointState& start, const DualPose& goal, JointState& goal_joints,
                        bool& alternative_taken);
  /// Validity of a joint state for the search and the verification (counted; the tool bounds too).
  /// `primitive_contacts_apart`: a state of a motion primitive (checkFollowOn, checkMotion), where
  /// the scene's primitive contacts (the needle in the tissue) are allowed.
  ValidityResult checkState(const JointState& q, bool primitive_contacts_apart = false);
  bool insideBounds(const DualPose& tools) const;
  /// "needle", "probe and needle": the tools robot `robot` holds, for messages.
  std::string toolsOf(std::size_t robot) const;
  /// max_velocity_: every joint's velocity limit [m/s, rad/s] from the robot models.
  void setVelocityLimits();
  /// The shortest time the trajectory generator can take from `a` to `b` [s].
  double segmentDuration(const DualPose& a, const DualPose& b) const;
  /// Follows the Cartesian segment a → b with the continuity-keeping IK from joints `q` (updated
  /// to the end's): false with `failure` at the first unreachable, discontinuous or invalid step.
  bool walk(const DualPose& a, const DualPose& b, JointState& q, std::string& failure,
            bool primitive_contacts_apart = false);
  /// Inserts the two waypoints of RobotModel::singularCrossing into segment k when a robot's
  /// planned joints cross a singular set there (not again for a segment that starts at one).
  bool insertCrossing(std::vector<JointState>& planned, std::vector<DualPose>& poses, std::vector<std::size_t>& depth,
                      std::vector<char>& crossing, std::size_t k, std::size_t level);
  /// The dense verification of the planned joints' Cartesian path, halving failing segments in
  /// joint space (the segment into the goal first at `search_goal`, searchGoal's, when that is not
  /// the goal); fills result.waypoints and joint_waypoints, or returns false with `failure`.
  bool verify(std::vector<JointState>& planned, const DualPose& start_poses, const DualPose& goal_poses,
              const JointState& search_goal, Layout& layout, const JointState& start, PlanResult& result, std::string& failure);
  /// True when the query's time or work budget is spent. The planners poll it once per iteration
  /// (OMPL's termination condition): each call for the query that began at `started` counts one
  /// iteration of max_validity_checks.
  bool spent(std::chrono::steady_clock::time_point started) const;
  /// "5.000000 s" or "250000 validity checks or planner iterations": the budget, for messages.
  std::string budget() const;

  StateValidator& validator_;
  PlannerOptions options_;
  JointState max_velocity_;  // per joint of the query: velocity limit [m/s, rad/s]
  DualPose tools_scratch_;
  std::atomic<std::size_t> checks_{0};  // validity checks of the current query (PRM checks from two threads)
  // Planner iterations (spent() calls) of the query that began at polled_query_ (its steady_clock
  // ticks): spent() is what the planners call, so it counts and resets them itself.
  mutable std::atomic<std::size_t> iterations_{0};
  mutable std::atomic<std::chrono::steady_clock::rep> polled_query_{0};
  bool search_disabled_ = false;  // checkGoal(): every budget is spent before the search starts
};

}  // namespace cobra::planning
