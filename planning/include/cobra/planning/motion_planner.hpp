#pragma once
/// @file
/// planPath(q_start, q_goal) (thesis Algorithm 4.1): OMPL on the compound state space SE(3)×SE(3)
/// with position bounds, SimpleSetup, RRT-Connect by default, the StateValidator as validity
/// checker, path simplification, seeded for reproducible results.

#include <array>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <memory>
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

/// Planner configuration (the component's properties).
struct PlannerOptions {
  /// "RRTConnect" (default, as in the thesis), "RRT" or "PRM".
  std::string planner = "RRTConnect";
  /// Wall-clock limit of the search [s] (when max_validity_checks is 0).
  double time_limit = 1.0;
  /// Work limit of the search instead of time_limit: the search stops after this many state
  /// validity checks [1] (0: time_limit applies). Its outcome then depends on the seed alone, not
  /// on the machine's speed or load: a lockstep simulation plans the same on a laptop and on a
  /// busy CI machine. About 50,000 checks take 1 s in the puncturing scene (bench/planning_bench).
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
  /// guaranteed by the verification below, not by this step.
  double edge_resolution = 0.004;
  /// Shorten and smooth the found path (OMPL's PathSimplifier, bounded by `simplify_steps`).
  bool simplify = true;
  /// Number of vertices checked per segment when the final path is verified [1]. A path that fails
  /// the verification is discarded and the search re-run with seed + 1, + 2, ... while time_limit
  /// allows (PathInvalid when none passes).
  std::size_t verify_points_per_segment = 100;
  /// Range of one RRT/RRT-Connect extension in the state-space metric (position [m] plus rotation
  /// angle [rad]); 0 lets OMPL choose (a fraction of the extent).
  double range = 0.0;
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

  /// Algorithm 4.1. Never throws for bad poses: the status names the cause.
  PlanResult planPath(const DualPose& start, const DualPose& goal);

  const PlannerOptions& options() const { return options_; }
  /// Seed of the next planPath() (> 0; an invalid seed throws std::invalid_argument).
  void setSeed(std::uint32_t seed);

 private:
  /// The OMPL part of planPath() (after the input checks) with one seed, until time_limit s after
  /// `started` or max_validity_checks checks since the query began; may throw ompl::Exception.
  PlanResult search(const DualPose& start, const DualPose& goal, std::chrono::steady_clock::time_point started,
                    std::uint32_t seed);
  /// True when the query's time or work budget is spent.
  bool spent(std::chrono::steady_clock::time_point started) const;
  /// "5.000000 s" or "250000 validity checks": the budget, for messages.
  std::string budget() const;

  StateValidator& validator_;
  PlannerOptions options_;
  std::atomic<std::size_t> checks_{0};  // validity checks of the current query (PRM checks from two threads)
};

}  // namespace cobra::planning
