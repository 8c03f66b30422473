#include "cobra/planning/motion_planner.hpp"

#include "planner_support.hpp"

#include <ompl/base/spaces/SE3StateSpace.h>
#include <ompl/geometric/SimpleSetup.h>
#include <ompl/geometric/planners/prm/PRM.h>
#include <ompl/geometric/planners/rrt/RRT.h>
#include <ompl/geometric/planners/rrt/RRTConnect.h>
#include <ompl/util/Console.h>
#include <ompl/util/RandomNumbers.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cmath>
#include <stdexcept>

namespace cobra::planning {

namespace ob = ompl::base;
namespace og = ompl::geometric;

bool PositionBounds::contains(const KDL::Vector& p) const {
  for (int i = 0; i < 3; ++i)
    if (!(p(i) >= low[static_cast<std::size_t>(i)] && p(i) <= high[static_cast<std::size_t>(i)])) return false;
  return true;
}

const char* toString(PlanStatus status) {
  switch (status) {
    case PlanStatus::Solved: return "solved";
    case PlanStatus::InvalidInput: return "invalid input";
    case PlanStatus::OutOfBounds: return "out of bounds";
    case PlanStatus::InvalidStart: return "invalid start";
    case PlanStatus::InvalidGoal: return "invalid goal";
    case PlanStatus::NoSolution: return "no solution";
    case PlanStatus::PathInvalid: return "path invalid";
    case PlanStatus::PlannerError: return "planner error";
  }
  return "unknown";
}

namespace {

using SE3State = ob::SE3StateSpace::StateType;

void toOmpl(const KDL::Frame& frame, SE3State& state) {
  state.setXYZ(frame.p.x(), frame.p.y(), frame.p.z());
  auto& rotation = state.rotation();
  frame.M.GetQuaternion(rotation.x, rotation.y, rotation.z, rotation.w);
}

KDL::Frame toKdl(const SE3State& state) {
  const auto& r = state.rotation();
  return KDL::Frame(KDL::Rotation::Quaternion(r.x, r.y, r.z, r.w),
                    KDL::Vector(state.getX(), state.getY(), state.getZ()));
}

void toOmpl(const DualPose& q, ob::State& state) {
  auto& compound = *state.as<ob::CompoundState>();
  toOmpl(q.first, *compound.as<SE3State>(0));
  toOmpl(q.second, *compound.as<SE3State>(1));
}

DualPose toDualPose(const ob::State& state) {
  const auto& compound = *state.as<ob::CompoundState>();
  return {toKdl(*compound.as<SE3State>(0)), toKdl(*compound.as<SE3State>(1))};
}

std::shared_ptr<ob::SE3StateSpace> makeSE3(const PositionBounds& bounds) {
  auto space = std::make_shared<ob::SE3StateSpace>();
  ob::RealVectorBounds real(3);
  for (std::size_t i = 0; i < 3; ++i) {
    real.setLow(static_cast<unsigned>(i), bounds.low[i]);
    real.setHigh(static_cast<unsigned>(i), bounds.high[i]);
  }
  space->setBounds(real);
  return space;
}

void checkBounds(const PositionBounds& bounds, const char* which) {
  for (std::size_t i = 0; i < 3; ++i)
    if (!(bounds.low[i] < bounds.high[i]) || !std::isfinite(bounds.low[i]) || !std::isfinite(bounds.high[i]))
      throw std::invalid_argument(std::string("motion planner: ") + which +
                                  " bounds must be finite with low < high on every axis [m]");
}

}  // namespace

MotionPlanner::MotionPlanner(StateValidator& validator, PlannerOptions options)
    : validator_(validator), options_(std::move(options)) {
  const std::vector<std::string>& names = plannerNames();
  if (std::find(names.begin(), names.end(), options_.planner) == names.end()) {
    std::string list;
    for (const std::string& name : names) list += (list.empty() ? "" : ", ") + name;
    throw std::invalid_argument("motion planner: unknown planner '" + options_.planner + "': use " + list);
  }
  if (options_.max_validity_checks == 0 && (!(options_.time_limit > 0.0) || !std::isfinite(options_.time_limit)))
    throw std::invalid_argument("motion planner: time_limit must be a positive number of seconds");
  if (options_.seed == 0) throw std::invalid_argument("motion planner: seed must be > 0 (OMPL ignores 0)");
  if (!(options_.edge_resolution > 0.0 && options_.edge_resolution <= 1.0))
    throw std::invalid_argument("motion planner: edge_resolution must be in (0, 1] (fraction of the space extent)");
  for (const auto& [value, what] : {std::pair{options_.max_linear_velocity, "max_linear_velocity (m/s)"},
                                    std::pair{options_.max_angular_velocity, "max_angular_velocity (rad/s)"},
                                    std::pair{options_.blend_time, "blend_time (s)"},
                                    std::pair{options_.joint_velocity_margin, "joint_velocity_margin"}})
    if (!(value > 0.0) || !std::isfinite(value))
      throw std::invalid_argument(std::string("motion planner: ") + what + " must be a positive number");
  if (options_.verify_points_per_segment == 0)
    throw std::invalid_argument("motion planner: verify_points_per_segment must be >= 1");
  if (!(options_.local_search_share >= 0.0 && options_.local_search_share < 1.0))
    throw std::invalid_argument("motion planner: local_search_share must be in [0, 1) (a share of the budget)");
  if (!(options_.range >= 0.0) || !std::isfinite(options_.range))
    throw std::invalid_argument("motion planner: range must be >= 0 (0 = OMPL's default)");
  checkBounds(options_.first_bounds, "first tool");
  checkBounds(options_.second_bounds, "second tool");
}

MotionPlanner::~MotionPlanner() = default;

void MotionPlanner::setSeed(std::uint32_t seed) {
  if (seed == 0) throw std::invalid_argument("motion planner: the seed must be > 0");
  options_.seed = seed;
}

bool MotionPlanner::spent(std::chrono::steady_clock::time_point started) const {
  if (search_disabled_) return true;
  if (options_.max_validity_checks > 0) {
    // A new query (PRM polls from two threads: one of them resets, a lost count is harmless).
    const std::chrono::steady_clock::rep query = started.time_since_epoch().count();
    std::chrono::steady_clock::rep seen = polled_query_.load(std::memory_order_relaxed);
    if (seen != query && polled_query_.compare_exchange_strong(seen, query, std::memory_order_relaxed))
      iterations_.store(0, std::memory_order_relaxed);
    const std::size_t iterations = iterations_.fetch_add(1, std::memory_order_relaxed) + 1;
    return checks_.load(std::memory_order_relaxed) >= options_.max_validity_checks ||
           iterations > options_.max_validity_checks;
  }
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count() >= options_.time_limit;
}

std::string MotionPlanner::budget() const {
  if (options_.max_validity_checks > 0)
    return std::to_string(options_.max_validity_checks) + " validity checks or planner iterations";
  return std::to_string(options_.time_limit) + " s";
}

PlanResult MotionPlanner::checkGoal(const JointState& start, const DualPose& goal,
                                    const std::optional<DualPose>& follow_on) {
  // planPath itself with a search that stops before its first iteration: the checks are the
  // planner's own by construction, not a copy that could drift from them.
  search_disabled_ = true;
  PlanResult result;
  try {
    result = planPath(start, goal, follow_on);
  } catch (...) {
    search_disabled_ = false;
    throw;
  }
  search_disabled_ = false;
  if (result.status == PlanStatus::NoSolution || result.status == PlanStatus::Solved) {
    result = PlanResult{};
    result.status = PlanStatus::Solved;
    result.message = "accepted: the planner would search for a path";
  }
  return result;
}

PlanResult MotionPlanner::planPath(const DualPose& start, const DualPose& goal) {
  if (validator_.hasJointSpace()) {
    // The start joints: each robot's IK of its start tools from its configured seed.
    JointState joints(validator_.jointCount());
    std::size_t robot = 0;
    const Reachability reached = isFinitePose(start)
                                     ? validator_.inverseNear(start, {}, joints, robot)
                                     : Reachability::Unreachable;
    if (reached != Reachability::Reachable) {
      PlanResult result;
      result.status = isFinitePose(start) ? PlanStatus::InvalidStart : PlanStatus::InvalidInput;
      result.message = isFinitePose(start) ? "start state is not valid: robot '" +
                                                 validator_.scene().robots[robot].name +
                                                 "' has no IK solution on its configured seed's branch"
                                           : "start pose has a NaN/infinite value or a non-orthonormal rotation";
      return result;
    }
    return planPath(joints, goal);
  }
  const auto started = std::chrono::steady_clock::now();
  checks_.store(0, std::memory_order_relaxed);
  PlanResult result;
  const auto finish = [&](PlanStatus status, std::string message) {
    return detail::finished(std::move(result), status, std::move(message), started);
  };
  validator_.resetWarmStart();  // the query's answer must not depend on the checks before it
  if (!isFinitePose(start) || !isFinitePose(goal))
    return finish(PlanStatus::InvalidInput, std::string(isFinitePose(start) ? "goal" : "start") +
                                                " pose has a NaN/infinite value or a non-orthonormal rotation");
  for (const auto& [pose, name] : {std::pair{&start, "start"}, std::pair{&goal, "goal"}}) {
    if (!options_.first_bounds.contains(pose->first.p) || !options_.second_bounds.contains(pose->second.p))
      return finish(PlanStatus::OutOfBounds, std::string(name) + " position is outside the planner's bounds");
  }
  for (const auto& [pose, name] : {std::pair{&start, "start"}, std::pair{&goal, "goal"}}) {
    result.rejected = validator_.check(*pose, true);
    if (!result.rejected.valid())
      return finish(pose == &start ? PlanStatus::InvalidStart : PlanStatus::InvalidGoal,
                    std::string(name) + " state is not valid: " + describe(result.rejected));
  }

  try {
    // A path the dense verification rejects (it crossed a thin invalid region between two edge
    // checks) is discarded and the search re-run with the next seed while the budget lasts: the
    // sequence of seeds is fixed, so the outcome stays reproducible.
    std::uint32_t seed = options_.seed;
    for (;;) {
      PlanResult attempt = search(start, goal, started, seed);
      attempt.validity_checks = checks_.load(std::memory_order_relaxed);
      if (attempt.status != PlanStatus::PathInvalid || spent(started) || seed == UINT32_MAX) return attempt;
      ++seed;
    }
  } catch (const std::exception& error) {  // OMPL reports setup problems by throwing
    return finish(PlanStatus::PlannerError, std::string("OMPL failed: ") + error.what());
  }
}

PlanResult MotionPlanner::search(const DualPose& start, const DualPose& goal,
                                 std::chrono::steady_clock::time_point started, std::uint32_t seed) {
  PlanResult result;
  const auto finish = [&](PlanStatus status, std::string message) {
    return detail::finished(std::move(result), status, std::move(message), started);
  };
  const detail::OmplLogLevel quiet(ompl::msg::LOG_NONE);
  // Re-seeding OMPL's seed generator before any generator of this query exists makes the sequence
  // of seeds, hence samples, the same for the same query (OMPL logs an error we silence above).
  validator_.resetWarmStart();
  ompl::RNG::setSeed(seed);
  auto space = std::make_shared<ob::CompoundStateSpace>();
  space->addSubspace(makeSE3(options_.first_bounds), 1.0);
  space->addSubspace(makeSE3(options_.second_bounds), 1.0);
  og::SimpleSetup setup(space);
  setup.setStateValidityChecker([this](const ob::State* state) {
    checks_.fetch_add(1, std::memory_order_relaxed);
    return validator_.isStateValid(toDualPose(*state));
  });
  setup.getSpaceInformation()->setStateValidityCheckingResolution(options_.edge_resolution);
  ob::ScopedState<> start_state(space), goal_state(space);
  toOmpl(start, *start_state.get());
  toOmpl(goal, *goal_state.get());
  setup.setStartAndGoalStates(start_state, goal_state);
  const std::optional<og::PathGeometric> found =
      detail::solve(setup, options_, ob::PlannerTerminationCondition([&] { return spent(started); }));
  if (!found) return finish(PlanStatus::NoSolution, "no path found by " + options_.planner + " within " + budget());
  const og::PathGeometric& path = *found;
  for (unsigned i = 0; i < path.getStateCount(); ++i) result.waypoints.push_back(toDualPose(*path.getState(i)));

  // Verify every segment densely: edges were checked at edge_resolution, the contract is stronger.
  // The walk starts from the start state's IK solution, as the robots would move along the path.
  validator_.resetWarmStart();
  result.rejected = validator_.check(start);
  ob::State* between = space->allocState();
  const double steps = static_cast<double>(options_.verify_points_per_segment);
  for (unsigned i = 0; i + 1 < path.getStateCount() && result.rejected.valid(); ++i) {
    for (std::size_t k = 1; k < options_.verify_points_per_segment && result.rejected.valid(); ++k) {
      space->interpolate(path.getState(i), path.getState(i + 1), static_cast<double>(k) / steps, between);
      result.rejected = validator_.check(toDualPose(*between));
    }
  }
  space->freeState(between);
  if (!result.rejected.valid())
    return finish(PlanStatus::PathInvalid, "the path crosses an invalid state between waypoints (" +
                                               describe(result.rejected) + "): lower edge_resolution");
  result.waypoints.front() = start;  // exact input poses (OMPL stores them as quaternions)
  result.waypoints.back() = goal;
  return finish(PlanStatus::Solved, "solved by " + options_.planner + " with " +
                                        std::to_string(result.waypoints.size()) + " waypoints");
}

}  // namespace cobra::planning
