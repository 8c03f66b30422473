// MotionPlanner in joint space (motion_planner.hpp): goal joints by the continuity-keeping IK
// nearest the start, the OMPL search over the planning coordinates of the robots that move, and
// the dense verification of the Cartesian path that is returned.

#include "cobra/planning/motion_planner.hpp"

#include "planner_support.hpp"

#include <ompl/base/spaces/RealVectorStateSpace.h>
#include <ompl/geometric/PathSimplifier.h>
#include <ompl/geometric/SimpleSetup.h>
#include <ompl/geometric/planners/informedtrees/BITstar.h>
#include <ompl/geometric/planners/kpiece/LBKPIECE1.h>
#include <ompl/geometric/planners/prm/LazyPRM.h>
#include <ompl/geometric/planners/prm/PRM.h>
#include <ompl/geometric/planners/rrt/BiTRRT.h>
#include <ompl/geometric/planners/rrt/RRT.h>
#include <ompl/geometric/planners/rrt/RRTConnect.h>
#include <ompl/util/RandomNumbers.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

namespace cobra::planning {

using detail::interpolate;
using detail::position;

namespace ob = ompl::base;
namespace og = ompl::geometric;

const std::vector<std::string>& plannerNames() {
  static const std::vector<std::string> names{"RRTConnect", "RRT", "PRM", "BiTRRT", "LazyPRM", "LBKPIECE1", "BITstar"};
  return names;
}

namespace detail {

ob::PlannerPtr makePlanner(const PlannerOptions& options, const ob::SpaceInformationPtr& si) {
  const auto ranged = [&](auto planner) {
    if (options.range > 0.0) planner->setRange(options.range);
    return planner;
  };
  if (options.planner == "RRTConnect") return ranged(std::make_shared<og::RRTConnect>(si));
  if (options.planner == "RRT") return ranged(std::make_shared<og::RRT>(si));
  if (options.planner == "BiTRRT") return ranged(std::make_shared<og::BiTRRT>(si));
  if (options.planner == "LBKPIECE1") return ranged(std::make_shared<og::LBKPIECE1>(si));
  if (options.planner == "LazyPRM") {
    // OMPL 1.5's LazyPRM frees its roadmap's states in clear() but not in its destructor (which
    // is defaulted): every planning query leaked all the states it sampled (LeakSanitizer:
    // RealVectorStateSpace::allocState). Clearing before deleting frees them; the planner holds
    // its SpaceInformation, so freeState still has its state space.
    return ranged(std::shared_ptr<og::LazyPRM>(new og::LazyPRM(si), [](og::LazyPRM* planner) {
      planner->clear();
      delete planner;
    }));
  }
  if (options.planner == "BITstar") {
    // Asymptotically optimal: without this it refines until the budget is spent.
    auto planner = std::make_shared<og::BITstar>(si);
    planner->setStopOnSolnImprovement(true);
    return planner;
  }
  return std::make_shared<og::PRM>(si);
}

std::optional<og::PathGeometric> solve(og::SimpleSetup& setup, const PlannerOptions& options,
                                       const ob::PlannerTerminationCondition& stop) {
  setup.setPlanner(makePlanner(options, setup.getSpaceInformation()));
  if (setup.solve(stop) != ob::PlannerStatus::EXACT_SOLUTION) return std::nullopt;
  og::PathGeometric path = setup.getSolutionPath();
  if (options.simplify) {
    og::PathSimplifier simplifier(setup.getSpaceInformation());
    simplifier.reduceVertices(path);
    simplifier.shortcutPath(path);
    simplifier.collapseCloseVertices(path);
  }
  return path;
}

}  // namespace detail

namespace {

/// s: how far off its redundancy rule a moving robot's start may be, as the time its joints take to
/// cover it at their velocity limits (the continuity-keeping controllers leave ~0.04 rad).
constexpr double kStartRuleSlack = 0.25;

/// The first joint (0-based, in the robot) at which robot `r`'s joints in `q` differ from the
/// configuration its planning coordinates stand for (RobotModel::jointsOf of coordinatesOf(q), the
/// redundancy resolved by the rule of the control path's IK from `start`), or -1 when none does.
/// `step` > 0: a joint may differ by `step` × its velocity limit [s] instead of 1e-6 (m, rad).
std::ptrdiff_t offRule(StateValidator& validator, std::size_t r, const JointState& q, const JointState& start,
                       double step = 0.0) {
  RobotModel& model = validator.model(r);
  const std::size_t offset = validator.jointOffset(r), n = model.jointCount();
  std::vector<double> coordinates(model.coordinateCount()), check(n), lower(n), upper(n), velocity(n);
  model.coordinatesOf(std::span<const double>(q).subspan(offset, n), coordinates);
  model.jointsOf(coordinates, std::span<const double>(start).subspan(offset, n), check);
  model.jointLimits(lower, upper, velocity);
  for (std::size_t j = 0; j < n; ++j)
    if (std::abs(check[j] - q[offset + j]) > (step > 0.0 ? step * velocity[j] : 1e-6)) return static_cast<std::ptrdiff_t>(j);
  return -1;
}

bool samePose(const KDL::Frame& a, const KDL::Frame& b) {
  KDL::Vector axis;
  return (a.p - b.p).Norm() < 1e-6 && (a.M.Inverse() * b.M).GetRotAngle(axis) < 1e-6;
}

}  // namespace

/// The coordinates of one query's search: the robots that move, each a block of coordinates
/// (RobotModel::coordinateCount), stored in OMPL divided by their scale (velocity limit).
struct MotionPlanner::Layout {
  struct Block {
    std::size_t robot = 0;          // index in the scene's robots
    std::size_t joint_offset = 0;   // in a JointState
    std::size_t joint_count = 0;
    std::size_t coordinate_offset = 0;  // in the OMPL state
    std::size_t coordinate_count = 0;
  };
  std::vector<Block> blocks;
  std::vector<double> scale;  // per OMPL dimension
  std::vector<double> coordinates;  // scratch: one block's coordinates

  /// Joints of the OMPL state `values` into `q` (which holds the start's joints elsewhere).
  void joints(StateValidator& validator, const double* values, const JointState& start, JointState& q) {
    for (const Block& b : blocks) {
      for (std::size_t i = 0; i < b.coordinate_count; ++i)
        coordinates[i] = values[b.coordinate_offset + i] * scale[b.coordinate_offset + i];
      validator.model(b.robot).jointsOf(std::span<const double>(coordinates.data(), b.coordinate_count),
                                        std::span<const double>(start).subspan(b.joint_offset, b.joint_count),
                                        std::span<double>(q).subspan(b.joint_offset, b.joint_count));
    }
  }
  /// Whether every robot that moves keeps the IK branch of the query (RobotModel::keepsBranch).
  bool keepsBranches(StateValidator& validator, const JointState& q, const JointState& start,
                     const JointState& goal) const {
    for (const Block& b : blocks) {
      const auto robot = [&](const JointState& x) { return std::span<const double>(x).subspan(b.joint_offset, b.joint_count); };
      if (!validator.model(b.robot).keepsBranch(robot(q), robot(start), robot(goal))) return false;
    }
    return true;
  }
  /// OMPL values of joint state `q`.
  void values(StateValidator& validator, const JointState& q, double* values) {
    for (const Block& b : blocks) {
      validator.model(b.robot).coordinatesOf(std::span<const double>(q).subspan(b.joint_offset, b.joint_count),
                                             std::span<double>(coordinates.data(), b.coordinate_count));
      for (std::size_t i = 0; i < b.coordinate_count; ++i)
        values[b.coordinate_offset + i] = coordinates[i] / scale[b.coordinate_offset + i];
    }
  }
};

bool MotionPlanner::insideBounds(const DualPose& tools) const {
  return options_.first_bounds.contains(tools.first.p) && options_.second_bounds.contains(tools.second.p);
}

ValidityResult MotionPlanner::checkState(const JointState& q, bool primitive_contacts_apart) {
  checks_.fetch_add(1, std::memory_order_relaxed);
  ValidityResult result;
  if (!validator_.toolPoses(q, tools_scratch_)) {
    result.validity = Validity::Unreachable;
    return result;
  }
  if (!insideBounds(tools_scratch_)) {
    result.validity = Validity::Unreachable;  // outside the planner's box: not a state it may use
    result.robot = "(outside the planner's tool bounds)";
    return result;
  }
  return validator_.checkJoints(q, false, primitive_contacts_apart);
}

std::string MotionPlanner::toolsOf(std::size_t robot) const {
  std::string names;
  for (const std::size_t tool : validator_.scene().robots[robot].tool_indices)
    names += (names.empty() ? "" : " and ") + options_.tool_names[tool];
  return names;
}

PlanResult MotionPlanner::planPath(const JointState& start, const DualPose& goal,
                                   const std::optional<DualPose>& follow_on) {
  const auto started = std::chrono::steady_clock::now();
  checks_.store(0, std::memory_order_relaxed);
  PlanResult result;
  const auto finish = [&](PlanStatus status, std::string message) {
    return detail::finished(std::move(result), status, std::move(message), started);
  };
  validator_.resetWarmStart();
  if (!validator_.hasJointSpace())
    return finish(PlanStatus::InvalidInput,
                  "the scene's robot models offer no joint space: give the start as tool poses");
  if (start.size() != validator_.jointCount()) {
    std::string layout;
    for (std::size_t r = 0; r < validator_.scene().robots.size(); ++r)
      layout += (layout.empty() ? "" : ", ") + validator_.scene().robots[r].name + " " +
                std::to_string(validator_.model(r).jointCount());
    return finish(PlanStatus::InvalidInput, "start joints: " + std::to_string(validator_.jointCount()) +
                                                " values expected (" + layout + "), got " +
                                                std::to_string(start.size()));
  }
  for (std::size_t j = 0; j < start.size(); ++j)
    if (!std::isfinite(start[j]))
      return finish(PlanStatus::InvalidInput, "start joints: value " + std::to_string(j) + " is not finite");
  if (!isFinitePose(goal))
    return finish(PlanStatus::InvalidInput, "goal pose has a NaN/infinite value or a non-orthonormal rotation");
  if (follow_on && !isFinitePose(*follow_on))
    return finish(PlanStatus::InvalidInput,
                  "the pose the motion after the goal ends at has a NaN/infinite value or a non-orthonormal rotation");
  DualPose start_poses;
  result.rejected = validator_.checkJoints(start, true);
  if (!validator_.toolPoses(start, start_poses) || !result.rejected.valid())
    return finish(PlanStatus::InvalidStart,
                  result.rejected.validity == Validity::Unreachable
                      ? "start joints of robot '" + std::string(result.rejected.robot) + "' are outside its joint limits"
                      : "start state is not valid: " + describe(result.rejected));
  for (const auto& [poses, name] : {std::pair{static_cast<const DualPose*>(&start_poses), "start"}, std::pair{&goal, "goal"}}) {
    if (!options_.first_bounds.contains(poses->first.p))
      return finish(PlanStatus::OutOfBounds, std::string(name) + " position of the " + options_.tool_names[0] + " " +
                                                 position(poses->first) + " is outside the planner's bounds");
    if (!options_.second_bounds.contains(poses->second.p))
      return finish(PlanStatus::OutOfBounds, std::string(name) + " position of the " + options_.tool_names[1] + " " +
                                                 position(poses->second) + " is outside the planner's bounds");
  }
  try {
    PlanResult planned = planJoints(start, start_poses, goal, follow_on, started);
    planned.validity_checks = checks_.load(std::memory_order_relaxed);
    planned.planning_time = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    return planned;
  } catch (const std::exception& error) {  // OMPL reports setup problems by throwing
    return finish(PlanStatus::PlannerError, std::string("OMPL failed: ") + error.what());
  }
}

PlanResult MotionPlanner::goalJoints(const JointState& start, const DualPose& goal, JointState& goal_joints,
                                     bool& alternative_taken) {
  alternative_taken = false;
  PlanResult result;
  result.status = PlanStatus::InvalidGoal;
  goal_joints.assign(start.size(), 0.0);
  std::size_t robot = 0;
  const Reachability reached = validator_.inverseGoal(goal, start, goal_joints, robot);
  if (reached != Reachability::Reachable) {
    // A robot's second goal (RobotModel::inverseGoalAlternative) may be reachable where its first
    // is not: the I-SUR's suturing arm on the start's branch from the Endo Stitch's other goal.
    JointState alternative(start.size());
    std::size_t failed = 0;
    if (validator_.inverseGoalAlternative(goal, start, alternative, failed) == Reachability::Reachable) {
      goal_joints.swap(alternative);
      alternative_taken = true;
      result.status = PlanStatus::Solved;
      return result;
    }
  }
  const auto goal_of = [&](std::size_t r) {
    const RobotPlacement& placement = validator_.scene().robots[r];
    std::string text = toolsOf(r) + " goal ";
    for (const std::size_t tool : placement.tool_indices) text += position(tool == 0 ? goal.first : goal.second) + " ";
    return text;
  };
  if (reached == Reachability::Unreachable) {
    result.message = goal_of(robot) + "is unreachable: robot '" + validator_.scene().robots[robot].name +
                     "' has no inverse kinematics solution for it within its joint limits";
    return result;
  }
  if (reached == Reachability::OtherBranch) {
    result.message = goal_of(robot) + "is reachable only on another IK branch than the start's: robot '" +
                     validator_.scene().robots[robot].name +
                     "' would have to flip its arm (shoulder, elbow or wrist), which no planned path does";
    return result;
  }
  // The goal joints are what the control path's IK answers for the goal from the start
  // (RobotModel::inverseGoal): on the start's redundancy rule where the rule reaches the goal,
  // otherwise the continuity-keeping IK's own resolution, e.g. the I-SUR's elbow q6 - q7 moved off
  // its preferred value where the delta is at the end of its stroke (IsurPuncturingSolver's split
  // search), where the controllers take the robot too. Such a goal is not refused: the search
  // heads for the configuration on the rule nearest it (searchGoal), and the path's last
  // Cartesian segment, into the goal itself, is verified with that IK like every other segment.
  result.status = PlanStatus::Solved;
  return result;
}

PlanResult MotionPlanner::planJoints(const JointState& start, const DualPose& start_poses, const DualPose& goal,
                                     const std::optional<DualPose>& follow_on,
                                     std::chrono::steady_clock::time_point started) {
  JointState goal_joints;
  bool alternative_taken = false;
  PlanResult result = goalJoints(start, goal, goal_joints, alternative_taken);
  if (result.status != PlanStatus::Solved) {
    std::string message = result.message;
    return detail::finished(std::move(result), PlanStatus::InvalidGoal, std::move(message), started);
  }
  // Robots whose tools stay where they are do not move at all (no detour of the probe pressed on
  // the skin while the needle moves): the search leaves their joints at the start's.
  std::vector<bool> moving(validator_.scene().robots.size(), false);
  bool any = false;
  for (std::size_t r = 0; r < moving.size(); ++r) {
    for (const std::size_t tool : validator_.scene().robots[r].tool_indices) {
      const bool first = tool == 0;
      if (!samePose(first ? start_poses.first : start_poses.second, first ? goal.first : goal.second)) moving[r] = true;
    }
    any = any || moving[r];
  }
  const auto holdStill = [&](JointState& q) {
    for (std::size_t r = 0; r < moving.size(); ++r)
      if (!moving[r])
        std::copy_n(start.begin() + static_cast<std::ptrdiff_t>(validator_.jointOffset(r)),
                    validator_.model(r).jointCount(), q.begin() + static_cast<std::ptrdiff_t>(validator_.jointOffset(r)));
  };
  holdStill(goal_joints);
  // A start a little off the I-SUR's redundancy rule is planned from as it is: the robots'
  // controllers keep continuity (kinematics::ContinuousIk), so after a straight motion near the
  // wrist lock they end off the rule a fresh solve gives (by ~0.03-0.04 rad in the elbow), and the
  // next path's first command continues from there; the dense verification walks the path from
  // that start with the same continuity-keeping IK. Refusing those refused procedures the robots
  // follow. Further off than a joint moves in kStartRuleSlack at its velocity limit, the start is
  // not where Cartesian control leaves a robot: refused at once, naming the joint, rather than
  // searched for in vain.
  for (std::size_t r = 0; r < moving.size(); ++r) {
    const std::ptrdiff_t joint = moving[r] ? offRule(validator_, r, start, start, kStartRuleSlack) : -1;
    if (joint >= 0)
      return detail::finished(std::move(result), PlanStatus::InvalidStart,
                              "start joints of robot '" + validator_.scene().robots[r].name + "' (joint " +
                                  std::to_string(joint + 1) + ") are further from where its inverse kinematics "
                                  "resolves its redundancy for the start pose than the joint moves in " +
                                  std::to_string(kStartRuleSlack).substr(0, 4) +
                                  " s: the first Cartesian command of any path would jump them",
                              started);
  }
  // The goal is taken when its state is valid and the straight motion after it (when the query
  // names one) can be made from it, both from the goal joints and from where the found path ends
  // them; otherwise the robot models' second goal for the same tools (RobotModel::
  // inverseGoalAlternative: of the I-SUR's goal on its redundancy rule with the wrist on the other
  // pitch branch and the solver's on the start's branch, the one inverseGoal did not prefer). A
  // search that found no path is not repeated for the second goal (the budget is spent). When
  // neither goal can be taken, the first's failure is reported.
  const auto refusal = [&](const JointState& q, ValidityResult& rejected) {
    rejected = validator_.checkJoints(q, true);
    if (!rejected.valid()) return "goal state is not valid: " + describe(rejected);
    if (!follow_on) return std::string();
    const PlanResult next = checkFollowOn(q, goal, *follow_on);
    return next.solved() ? std::string() : next.message;
  };
  PlanResult first;
  for (int choice = 0; choice < 2; ++choice) {
    if (choice == 1) {
      JointState alternative(goal_joints.size());
      std::size_t robot = 0;
      if (alternative_taken || validator_.inverseGoalAlternative(goal, start, alternative, robot) != Reachability::Reachable)
        break;
      holdStill(alternative);
      goal_joints.swap(alternative);
    }
    PlanResult attempt;
    const std::string refused = refusal(goal_joints, attempt.rejected);
    if (!refused.empty()) {
      attempt.status = PlanStatus::InvalidGoal;
      attempt.message = refused;
    } else {
      attempt = reachGoal(start, start_poses, goal, goal_joints, moving, any, follow_on, started);
    }
    if (attempt.solved()) return attempt;
    if (choice == 0) first = std::move(attempt);
    if (first.status != PlanStatus::InvalidGoal) break;
  }
  const PlanStatus status = first.status;
  std::string message = first.message;
  return detail::finished(std::move(first), status, std::move(message), started);
}

PlanResult MotionPlanner::reachGoal(const JointState& start, const DualPose& start_poses, const DualPose& goal,
                                    const JointState& goal_joints, const std::vector<bool>& moving, bool any,
                                    const std::optional<DualPose>& follow_on,
                                    std::chrono::steady_clock::time_point started) {
  PlanResult result;
  if (!any) {
    result.waypoints = {start_poses, goal};
    result.joint_waypoints = {start, goal_joints};
    return detail::finished(std::move(result), PlanStatus::Solved, "solved: the tools are at the goal already", started);
  }
  setVelocityLimits();
  const JointState search_goal = searchGoal(start, start_poses, goal, goal_joints, moving);
  // A path the dense verification rejects is discarded and the search re-run with the next seed
  // while the budget lasts: the sequence of seeds is fixed, so the outcome stays reproducible.
  // The first search looks in the box around the start and the goal (local_search_share of the
  // budget); when it finds no path there, the whole space is searched with the rest.
  std::uint32_t seed = options_.seed;
  std::size_t refinement = 0;
  bool local = options_.local_search_share > 0.0;
  for (std::size_t searches = 1;; ++searches) {
    PlanResult attempt =
        searchJoints(start, start_poses, goal_joints, goal, search_goal, moving, started, seed, refinement, local);
    attempt.searches = searches;
    const bool last = spent(started) || seed == UINT32_MAX;
    if (!last && local && attempt.status == PlanStatus::NoSolution) {
      local = false;
    } else if (!last && attempt.status == PlanStatus::PathInvalid) {
      local = false;
      ++refinement;
    } else {
      if (attempt.solved() && follow_on && !attempt.joint_waypoints.empty()) {
        // The path may leave the robots elsewhere at the goal than goal_joints (the continuity-
        // keeping IK tracked along it): the motion after it is checked from there too.
        const PlanResult next = checkFollowOn(attempt.joint_waypoints.back(), attempt.waypoints.back(), *follow_on);
        if (!next.solved()) {
          attempt.status = PlanStatus::InvalidGoal;
          attempt.message = next.message + " (from where the found path ends)";
        }
      }
      return attempt;
    }
    ++seed;
  }
}

JointState MotionPlanner::searchGoal(const JointState& start, const DualPose& start_poses, const DualPose& goal,
                                     const JointState& goal_joints, const std::vector<bool>& moving) {
  // Where the control path's IK takes a robot off its redundancy rule at the goal (the I-SUR's
  // elbow moved because the delta is at the end of its stroke), the goal has no planning
  // coordinates: theirs stand for the configuration on the rule with the same sliders and wrist
  // angles (the projection), whose tool lies elsewhere, by up to the upper arm's length times the
  // elbow's move. The search heads for the projection when it is a valid state; otherwise (its
  // tool outside the planner's bounds or in contact) for the configuration on the rule nearest
  // the goal on the straight Cartesian segment from the goal towards the projection's tools, else
  // towards the start's (inside the bounds: both ends are), found by bisection: the nearest pose
  // from which the rule is reachable. The path's last segment then ends in the goal itself,
  // verified like every other: along it the controllers move the elbow off the rule as the delta
  // reaches its stroke, as they did on the way to the goal.
  constexpr int kBisections = 24;  // 2^-24 of the segment: well under a micrometre
  const auto onRule = [&](const JointState& q) {
    for (std::size_t r = 0; r < moving.size(); ++r)
      if (moving[r] && offRule(validator_, r, q, start) >= 0) return false;
    return true;
  };
  if (onRule(goal_joints)) return goal_joints;
  const auto valid = [&](const JointState& q) {
    for (std::size_t r = 0; r < moving.size(); ++r) {
      const std::size_t offset = validator_.jointOffset(r), n = validator_.model(r).jointCount();
      const auto robot = [&](const JointState& x) { return std::span<const double>(x).subspan(offset, n); };
      if (moving[r] && !validator_.model(r).keepsBranch(robot(q), robot(start), robot(goal_joints))) return false;
    }
    return checkState(q).valid();
  };
  JointState projection = goal_joints;
  for (std::size_t r = 0; r < moving.size(); ++r) {
    if (!moving[r]) continue;
    RobotModel& model = validator_.model(r);
    const std::size_t offset = validator_.jointOffset(r), n = model.jointCount();
    std::vector<double> coordinates(model.coordinateCount());
    model.coordinatesOf(std::span<const double>(goal_joints).subspan(offset, n), coordinates);
    model.jointsOf(coordinates, std::span<const double>(start).subspan(offset, n),
                   std::span<double>(projection).subspan(offset, n));
  }
  DualPose projection_poses;
  if (!validator_.toolPoses(projection, projection_poses) || valid(projection)) return projection;
  JointState q(goal_joints.size()), boundary;
  for (const DualPose* far : {static_cast<const DualPose*>(&projection_poses), &start_poses}) {
    const auto onRuleAt = [&](double s) {
      const DualPose pose{interpolate(goal.first, far->first, s), interpolate(goal.second, far->second, s)};
      std::size_t robot = 0;
      return validator_.inverseGoal(pose, start, q, robot) == Reachability::Reachable && onRule(q);
    };
    if (!onRuleAt(1.0)) continue;
    boundary = q;
    double off = 0.0, on = 1.0;
    for (int i = 0; i < kBisections; ++i) {
      const double middle = 0.5 * (off + on);
      if (onRuleAt(middle)) {
        on = middle;
        boundary = q;
      } else {
        off = middle;
      }
    }
    if (valid(boundary)) return boundary;
  }
  return projection;  // not valid: the search reports it
}

PlanResult MotionPlanner::searchJoints(const JointState& start, const DualPose& start_poses, const JointState& goal,
                                       const DualPose& goal_poses, const JointState& search_goal,
                                       const std::vector<bool>& moving,
                                       std::chrono::steady_clock::time_point started, std::uint32_t seed,
                                       std::size_t refinement, bool local) {
  PlanResult result;
  const auto finish = [&](PlanStatus status, std::string message) {
    return detail::finished(std::move(result), status, std::move(message), started);
  };
  const detail::OmplLogLevel quiet(ompl::msg::LOG_NONE);
  ompl::RNG::setSeed(seed);

  Layout layout;
  std::size_t dimensions = 0;
  for (std::size_t r = 0; r < moving.size(); ++r) {
    if (!moving[r]) continue;
    const RobotModel& model = validator_.model(r);
    layout.blocks.push_back({r, validator_.jointOffset(r), model.jointCount(), dimensions, model.coordinateCount()});
    dimensions += model.coordinateCount();
  }
  layout.scale.resize(dimensions);
  layout.coordinates.resize(dimensions);
  ob::RealVectorBounds bounds(static_cast<unsigned>(dimensions));
  for (const Layout::Block& b : layout.blocks) {
    RobotModel& model = validator_.model(b.robot);
    const std::span<const double> robot_start = std::span<const double>(start).subspan(b.joint_offset, b.joint_count);
    std::vector<double> lower(b.coordinate_count), upper(b.coordinate_count), at_start(b.coordinate_count),
        at_goal(b.coordinate_count);
    const std::span<const double> robot_goal = std::span<const double>(search_goal).subspan(b.joint_offset, b.joint_count);
    model.coordinateBounds(robot_start, robot_goal, lower, upper);
    model.coordinateScales(std::span<double>(layout.scale).subspan(b.coordinate_offset, b.coordinate_count));
    model.coordinatesOf(robot_start, at_start);
    model.coordinatesOf(robot_goal, at_goal);
    for (std::size_t i = 0; i < b.coordinate_count; ++i) {
      const double scale = layout.scale[b.coordinate_offset + i];
      if (local) {  // the box around start and goal (PlannerOptions::local_search_share)
        const double widen = 0.5 * std::abs(at_goal[i] - at_start[i]) + kLocalMargin * scale;
        lower[i] = std::max(lower[i], std::min(at_start[i], at_goal[i]) - widen);
        upper[i] = std::min(upper[i], std::max(at_start[i], at_goal[i]) + widen);
      }
      // The start and goal are inside by construction, up to rounding.
      bounds.setLow(static_cast<unsigned>(b.coordinate_offset + i),
                    std::min({lower[i], at_start[i], at_goal[i]}) / scale);
      // A coordinate that may not move (the I-SUR's base turntable) keeps a width OMPL accepts.
      bounds.setHigh(static_cast<unsigned>(b.coordinate_offset + i),
                     std::max({upper[i], at_start[i], at_goal[i], lower[i] + 1e-9}) / scale);
    }
  }
  auto space = std::make_shared<ob::RealVectorStateSpace>(static_cast<unsigned>(dimensions));
  space->setBounds(bounds);
  og::SimpleSetup setup(space);
  JointState sample = start;
  setup.setStateValidityChecker([&](const ob::State* state) {
    layout.joints(validator_, state->as<ob::RealVectorStateSpace::StateType>()->values, start, sample);
    if (layout.keepsBranches(validator_, sample, start, goal)) return checkState(sample).valid();
    checks_.fetch_add(1, std::memory_order_relaxed);  // a state refused: one check of the work limit
    return false;
  });
  // A path that failed the verification may have passed OMPL's edge checks between two of their
  // points (a thin obstacle) and be found again by the next seed (e.g. the straight segment):
  // each re-run checks edges twice as finely, down to an eighth of edge_resolution.
  setup.getSpaceInformation()->setStateValidityCheckingResolution(
      options_.edge_resolution / static_cast<double>(std::size_t{1} << std::min<std::size_t>(refinement, 3)));
  ob::ScopedState<> start_state(space), goal_state(space);
  layout.values(validator_, start, start_state->as<ob::RealVectorStateSpace::StateType>()->values);
  layout.values(validator_, search_goal, goal_state->as<ob::RealVectorStateSpace::StateType>()->values);
  setup.setStartAndGoalStates(start_state, goal_state);
  // The goal as the search holds it (searchGoal: on every robot's redundancy rule). OMPL's
  // planners wait for a valid goal state, sleeping 10 ms per poll of the termination condition
  // until the budget is spent (PlannerInputStates::nextGoal: 100 s for a work limit of 10,000),
  // so an invalid one is answered here, at once.
  layout.joints(validator_, goal_state->as<ob::RealVectorStateSpace::StateType>()->values, start, sample);
  if (!layout.keepsBranches(validator_, sample, start, goal))
    return finish(PlanStatus::NoSolution, "the goal's configuration on the redundancy rule leaves the start's IK branch");
  if (const ValidityResult searched_goal = checkState(sample); !searched_goal.valid())
    return finish(PlanStatus::NoSolution,
                  "the goal's configuration on the redundancy rule is not valid: " + describe(searched_goal));
  // The local search stops when its share of the budget is spent (checks, else time).
  const std::size_t local_checks =
      static_cast<std::size_t>(options_.local_search_share * static_cast<double>(options_.max_validity_checks));
  const auto local_spent = [&] {
    if (!local) return false;
    if (options_.max_validity_checks > 0) return checks_.load(std::memory_order_relaxed) >= local_checks;
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count() >=
           options_.local_search_share * options_.time_limit;
  };
  const std::optional<og::PathGeometric> found = detail::solve(
      setup, options_, ob::PlannerTerminationCondition([&] { return spent(started) || local_spent(); }));
  if (!found) return finish(PlanStatus::NoSolution, "no path found by " + options_.planner + " within " + budget());
  const og::PathGeometric& path = *found;
  std::vector<JointState> planned;
  for (unsigned i = 0; i < path.getStateCount(); ++i) {
    layout.joints(validator_, path.getState(i)->as<ob::RealVectorStateSpace::StateType>()->values, start, sample);
    planned.push_back(sample);
  }
  planned.front() = start;
  // The last segment ends at the goal itself: where searchGoal left the rule it was the search's
  // stand-in for it (near it, on the rule), and the segment into the goal is verified as the
  // controllers would follow it.
  planned.back() = goal;
  std::string failure;
  if (!verify(planned, start_poses, goal_poses, search_goal, layout, start, result, failure))
    return finish(PlanStatus::PathInvalid, "the path cannot be followed: " + failure);
  return finish(PlanStatus::Solved, "solved by " + options_.planner + " with " +
                                        std::to_string(result.waypoints.size()) + " waypoints");
}

bool MotionPlanner::insertCrossing(std::vector<JointState>& planned, std::vector<DualPose>& poses,
                                   std::vector<std::size_t>& depth, std::vector<char>& crossing, std::size_t k,
                                   std::size_t level) {
  if (crossing[k] != 0) return false;  // the segment through a crossing: nothing more to insert
  for (std::size_t r = 0; r < validator_.scene().robots.size(); ++r) {
    RobotModel& model = validator_.model(r);
    const std::size_t at = validator_.jointOffset(r), n = model.jointCount();
    JointState before = planned[k], after = planned[k + 1];
    const auto span = [&](const JointState& q) { return std::span<const double>(q).subspan(at, n); };
    if (!model.singularCrossing(span(planned[k]), span(planned[k + 1]), std::span<double>(before).subspan(at, n),
                                std::span<double>(after).subspan(at, n)))
      continue;
    // The other robots at the same fraction of the segment (the crossing's, from the pitch).
    DualPose before_poses, after_poses;
    if (!validator_.toolPoses(before, before_poses) || !validator_.toolPoses(after, after_poses) ||
        !checkState(before).valid() || !checkState(after).valid())
      return false;
    const auto where = static_cast<std::ptrdiff_t>(k + 1);
    if (before == planned[k]) {  // the segment leaves the singular set at its start: one waypoint
      planned.insert(planned.begin() + where, after);
      poses.insert(poses.begin() + where, after_poses);
      depth.insert(depth.begin() + where, level);
      crossing.insert(crossing.begin() + where, 0);
      crossing[k] = 1;
    } else if (after == planned[k + 1]) {  // it reaches the singular set at its end: one waypoint
      planned.insert(planned.begin() + where, before);
      poses.insert(poses.begin() + where, before_poses);
      depth.insert(depth.begin() + where, level);
      crossing.insert(crossing.begin() + where, 1);
    } else {
      planned.insert(planned.begin() + where, {before, after});
      poses.insert(poses.begin() + where, {before_poses, after_poses});
      depth.insert(depth.begin() + where, {level, level});
      crossing.insert(crossing.begin() + where, {1, 0});
    }
    return true;
  }
  return false;
}

bool MotionPlanner::verify(std::vector<JointState>& planned, const DualPose& start_poses, const DualPose& goal_poses,
                           const JointState& search_goal,
                           Layout& layout, const JointState& start, PlanResult& result, std::string& failure) {
  // Cartesian waypoints: the tool poses of the planned joints, exactly the start and goal at the ends.
  std::vector<DualPose> poses(planned.size());
  for (std::size_t k = 1; k + 1 < planned.size(); ++k) validator_.toolPoses(planned[k], poses[k]);
  poses.front() = start_poses;
  poses.back() = goal_poses;
  std::vector<std::size_t> depth(planned.size(), 0);
  std::vector<char> crossing(planned.size(), 0);  // 1: the segment from this waypoint passes a singular pose
  JointState q = start;
  result.joint_waypoints = {start};
  std::vector<double> a(layout.scale.size()), b(layout.scale.size()), mid(layout.scale.size());
  for (std::size_t k = 0; k + 1 < poses.size();) {
    // A segment crossing, leaving or reaching a robot's singular set (the needle vertical) gets
    // the waypoints that make its Cartesian segment pass through it in one plane before it is
    // walked: the walk's steps are too coarse to see the yaw turn the controller would make
    // within one period there.
    if (insertCrossing(planned, poses, depth, crossing, k, std::max(depth[k], depth[k + 1]) + 1)) continue;
    JointState tracked = q;
    if (walk(poses[k], poses[k + 1], tracked, failure)) {
      q = tracked;
      result.joint_waypoints.push_back(q);
      ++k;
      continue;
    }
    const std::size_t level = std::max(depth[k], depth[k + 1]) + 1;
    // Otherwise halve the segment in joint space (the planned joints' midpoint, whose tool poses
    // become a new waypoint) until it passes or max_subdivisions is reached.
    if (level > options_.max_subdivisions) {
      failure += " (after " + std::to_string(options_.max_subdivisions) + " subdivisions)";
      return false;
    }
    layout.values(validator_, planned[k], a.data());
    layout.values(validator_, planned[k + 1], b.data());
    for (std::size_t i = 0; i < mid.size(); ++i) mid[i] = 0.5 * (a[i] + b[i]);
    JointState middle = start;
    layout.joints(validator_, mid.data(), start, middle);
    DualPose middle_poses;
    bool valid = validator_.toolPoses(middle, middle_poses) && checkState(middle).valid();
    if (!valid && k + 2 == planned.size() && planned[k] != search_goal && planned[k + 1] != search_goal) {
      // The segment into a goal off the redundancy rule: its joint-space midpoint lies halfway to
      // the goal's projection on the rule (searchGoal), often not a valid state; the search's
      // goal, on the rule next to the goal, splits it instead.
      middle = search_goal;
      valid = validator_.toolPoses(middle, middle_poses) && checkState(middle).valid();
    }
    if (!valid) {
      failure += " (the planned midpoint is not valid)";
      return false;
    }
    const auto at = static_cast<std::ptrdiff_t>(k + 1);
    planned.insert(planned.begin() + at, middle);
    poses.insert(poses.begin() + at, middle_poses);
    depth.insert(depth.begin() + at, level);
    crossing.insert(crossing.begin() + at, 0);
  }
  result.waypoints = std::move(poses);
  return true;
}

}  // namespace cobra::planning
