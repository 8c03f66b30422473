#pragma once
// Seeded random planning queries on the puncturing and suturing scenes, each configured as its
// deployment configures its planner: shared by planning/test/random_queries_test.cpp (a small
// sample, every path cross-checked) and bench/planning_bench.cpp (RandomQueries*/<planner>:
// 1,000 queries per scene, success and times per planner). The queries are the same for both:
// one generator seeded with 2026 per draw. Two draws:
//  - walkedQueries(): feasible by construction, the acceptance's "random feasible queries": the
//    goal is where the robots' controllers (controllers.hpp) take the tools from the start along
//    a random walk of straight Cartesian segments, every control step accepted by the
//    continuity-keeping IK and every state valid (full clearance), on the start's IK branch with
//    the planner's margins and inside its search bounds;
//  - independentQueries(): start and goal sampled independently (the goal kept when the
//    planner's goal check accepts it): nothing guarantees that a path exists between them (in the
//    suturing scene's 25 cm box many are likely not connected), a second, reported figure.

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <functional>
#include <map>
#include <numbers>
#include <random>
#include <span>
#include <string>
#include <vector>

#include "cobra/planning/motion_planner.hpp"
#include "cobra/planning/robot_adapters.hpp"
#include "controllers.hpp"

namespace cobra::planning::test {

inline constexpr double kQueryPi = std::numbers::pi;

/// The puncturing scene as the deployment configures it: the needle frames have z along the
/// needle (apps/puncturing/puncturing.lua), the phantom at `phantom` (identity: as in the file).
inline SceneDescription puncturingScene(const KDL::Frame& phantom = KDL::Frame::Identity()) {
  SceneDescription scene = loadScene(std::string(COBRA_SOURCE_DIR) + "/planning/test/scenes/puncturing.scene");
  for (RobotPlacement& robot : scene.robots)
    if (robot.name == "isur") robot.setToolFrame(0, KDL::Frame(KDL::Rotation::RPY(0.0, kQueryPi / 2, 0.0)));
  for (ObjectDescription& object : scene.objects)
    if (object.name == "phantom") object.offset = phantom * object.offset;
  return scene;
}

/// The MotionPlanner component's default bounds (components/planning), as the deployment uses them.
inline PlannerOptions deploymentOptions(const std::string& planner) {
  PlannerOptions o;
  o.planner = planner;
  o.first_bounds = {{-0.3, -0.3, 0.0}, {0.3, 0.3, 0.5}};
  o.second_bounds = {{-0.4, -0.5, 0.0}, {0.4, 0.4, 0.6}};
  o.tool_names = {"needle", "probe"};
  return o;
}

/// A valid joint state inside the planner's tool bounds, sampled uniformly in the joint limits
/// (the UR5 within ±π of `near`'s joints when given, so that it stays on one IK branch family).
inline JointState randomValidJoints(std::mt19937& rng, StateValidator& validator, const PlannerOptions& o,
                             const JointState* near = nullptr, bool on_rule = true) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  JointState q(validator.jointCount());
  DualPose tools;
  for (;;) {
    for (std::size_t r = 0; r < validator.scene().robots.size(); ++r) {
      RobotModel& model = validator.model(r);
      const std::size_t n = model.jointCount(), offset = validator.jointOffset(r);
      std::vector<double> lower(n), upper(n), velocity(n);
      model.jointLimits(lower, upper, velocity);
      for (std::size_t j = 0; j < n; ++j) {
        double lo = lower[j], hi = upper[j];
        if (near != nullptr && validator.scene().robots[r].name == "ur5") {
          lo = std::max(lo, (*near)[offset + j] - kQueryPi);
          hi = std::min(hi, (*near)[offset + j] + kQueryPi);
        }
        q[offset + j] = lo + unit(rng) * (hi - lo);
      }
      // Where the robot can be under Cartesian control: its redundancy resolved as its IK
      // resolves it (the I-SUR's base and elbow rule; the identity for the UR5).
      if (!on_rule) continue;
      std::vector<double> coordinates(model.coordinateCount()), projected(n);
      model.coordinatesOf(std::span<const double>(q).subspan(offset, n), coordinates);
      model.jointsOf(coordinates, std::span<const double>(q).subspan(offset, n), projected);
      std::copy(projected.begin(), projected.end(), q.begin() + static_cast<std::ptrdiff_t>(offset));
    }
    if (validator.checkJoints(q).valid() && validator.toolPoses(q, tools) && o.first_bounds.contains(tools.first.p) &&
        o.second_bounds.contains(tools.second.p))
      return q;
  }
}

/// One planning query: start joints, goal tool poses.
struct Query {
  JointState start;
  DualPose goal;
  double max_linear_velocity = 0.05;   // m/s: the trajectory generator of the planner that asks
  double max_angular_velocity = 0.5;   // rad/s
  /// walkedQueries(): the joints at which the controllers came to rest holding the goal (the
  /// planner's goal joints may differ where the I-SUR's elbow left its rule); empty otherwise.
  JointState walked_goal;
};

/// A scene the random queries are drawn on, configured as its deployment configures its planner.
struct RandomScene {
  std::function<SceneDescription()> scene;
  PlannerOptions options;  // bounds, tool names, work limit (the planner name is the benchmark's)
  /// The trajectory generator's speeds [m/s, rad/s] for a query moving tool 0 (needle, Endo
  /// Stitch) or only tool 1 (probe, stick).
  double first_linear = 0.05, first_angular = 0.5, second_linear = 0.05, second_angular = 0.5;
};

/// The puncturing scene as puncturingScene() and deploymentOptions() give it, work limit 10,000;
/// the needle robot's generator (needle_robot.lua) when the needle moves, the probe robot's
/// (probe_robot.lua) otherwise.
inline RandomScene puncturingRandom(const std::string& planner) {
  RandomScene r{[] { return puncturingScene(); }, deploymentOptions(planner), 0.04, 0.15, 0.08, 0.5};
  r.options.max_validity_checks = 10000;
  return r;
}

/// The suturing application's scene (apps/suturing/deployment/suturing.scene, phantom as in the
/// file) and its planner as apps/suturing/deployment/controller.lua configures it: the tool frames
/// of apps/suturing/frames.lua, the tips' bounds over the phantom, work limit 20,000 checks, the
/// generator's 0.02 m/s and 0.3 rad/s.
inline RandomScene suturingRandom(const std::string& planner) {
  RandomScene r;
  r.scene = [] {
    SceneDescription scene = loadScene(std::string(COBRA_SOURCE_DIR) + "/apps/suturing/deployment/suturing.scene");
    constexpr double kLean = 0.6, kTurn = -0.6;  // frames.lua: the stick's datum in the gripper frame
    for (RobotPlacement& robot : scene.robots) {
      robot.setToolFrame(0, KDL::Frame(KDL::Rotation::RPY(kQueryPi, -1.2, 0.0)));
      robot.setToolFrame(1, KDL::Frame(KDL::Rotation::RotY(-kLean) * KDL::Rotation::RotZ(kTurn), KDL::Vector(0, 0, 0.15)));
    }
    return scene;
  };
  r.options.planner = planner;
  r.options.first_bounds = {{0.05, -0.12, 0.05}, {0.3, 0.12, 0.3}};
  r.options.second_bounds = {{0.05, -0.12, 0.05}, {0.3, 0.12, 0.3}};
  r.options.tool_names = {"Endo Stitch", "stick"};
  r.options.max_validity_checks = 20000;
  r.first_linear = r.second_linear = 0.02;
  r.first_angular = r.second_angular = 0.3;
  return r;
}

/// `count` seeded independent queries (the same for every planner): start and goal joint
/// states sampled valid in the planner's bounds, on each robot's redundancy rule; a third moves
/// tool 0 only, a third tool 1 only, a third both (the other tool's goal is its start pose);
/// kept when the planner accepts the query (MotionPlanner::checkGoal) and no joint must turn the
/// long way round (below). `refused` counts the sampled queries dropped, by cause. Nothing makes
/// the goal reachable from the start (see the file comment).
inline std::vector<Query> independentQueries(StateValidator& validator, const RandomScene& setup, std::size_t count,
                                        std::map<std::string, int>& refused) {
  const PlannerOptions& o = setup.options;
  MotionPlanner acceptance(validator, o);
  std::mt19937 rng(2026);
  std::vector<Query> queries;
  while (queries.size() < count) {
    Query query;
    query.start = randomValidJoints(rng, validator, o);
    const JointState goal = randomValidJoints(rng, validator, o, &query.start);
    DualPose start_poses;
    validator.toolPoses(query.start, start_poses);
    validator.toolPoses(goal, query.goal);
    // Which tools move: the first, the second, or both (one in three each).
    const int moving = static_cast<int>(queries.size() % 3);
    if (moving == 1) query.goal.first = start_poses.first;
    if (moving == 0) query.goal.second = start_poses.second;
    // Feasible: the planner accepts the query (its own goal check: the goal IK from the start on
    // the start's branch and redundancy rule, a valid goal state), so a failure is the search's.
    const PlanResult accepted = acceptance.checkGoal(query.start, query.goal);
    if (!accepted.solved()) {
      ++refused[std::string("checkGoal: ") + toString(accepted.status)];
      continue;
    }
    // And no joint of the goal IK is more than half a turn from the start in a joint that spans
    // two turns (the UR5's ±2π): its nearest representative lies past the joint's limit, so
    // the joint would have to turn the long way round, outside the planner's search bounds
    // (start ± π: Ur5Model::coordinateBounds) and for the shoulder lift through the table.
    JointState goal_joints(goal.size()), lower(goal.size()), upper(goal.size()), velocity(goal.size());
    std::size_t robot = 0;
    validator.inverseGoal(query.goal, query.start, goal_joints, robot);
    bool long_way = false;
    for (std::size_t r = 0; r < validator.scene().robots.size(); ++r) {
      const std::size_t offset = validator.jointOffset(r), n = validator.model(r).jointCount();
      validator.model(r).jointLimits(std::span(lower).subspan(offset, n), std::span(upper).subspan(offset, n),
                                     std::span(velocity).subspan(offset, n));
    }
    for (std::size_t j = 0; j < goal.size(); ++j)
      long_way = long_way || (upper[j] - lower[j] > 3.0 * kQueryPi && std::abs(goal_joints[j] - query.start[j]) > kQueryPi);
    if (long_way) {
      ++refused["a joint would turn the long way round"];
      continue;
    }
    const bool first_moves = moving != 1;
    query.max_linear_velocity = first_moves ? setup.first_linear : setup.second_linear;
    query.max_angular_velocity = first_moves ? setup.first_angular : setup.second_angular;
    queries.push_back(query);
  }
  return queries;
}

/// The random walk of walkedQueries(): at most kWalkSegments straight segments, each moving
/// every moving tool by up to kWalkReach (uniform in the ball) and turning it by up to kWalkTurn
/// (a uniform axis, in the tool frame); kWalkTries segments drawn at most per query.
inline constexpr std::size_t kWalkSegments = 4;
inline constexpr double kWalkReach = 0.06;  // m
inline constexpr double kWalkTurn = 0.6;    // rad
inline constexpr int kWalkTries = 24;

/// `pose` moved by a random step of the walk (kWalkReach, kWalkTurn).
inline KDL::Frame walkStep(std::mt19937& rng, const KDL::Frame& pose) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::normal_distribution<double> normal;
  // Braces: the draws in order (a function call's arguments are evaluated in no fixed order).
  KDL::Vector direction{normal(rng), normal(rng), normal(rng)};
  KDL::Vector axis{normal(rng), normal(rng), normal(rng)};
  direction.Normalize();
  axis.Normalize();
  const double reach = kWalkReach * std::cbrt(unit(rng));
  const double turn = kWalkTurn * unit(rng);
  return KDL::Frame(pose.M * KDL::Rotation::Rot2(axis, turn), pose.p + reach * direction);
}

/// Whether joints `q` may be a state of the walk from `start`: for every robot on the start's IK
/// branch with the planner's margins (RobotModel::keepsBranch with the start as both ends) and
/// inside the planner's search bounds for a query from the start to q (RobotModel::
/// coordinateBounds: the UR5 within start ± π, the gripper arm on its elbow and wrist branch).
inline bool walkable(StateValidator& validator, const JointState& q, const JointState& start) {
  for (std::size_t r = 0; r < validator.scene().robots.size(); ++r) {
    RobotModel& model = validator.model(r);
    const std::size_t offset = validator.jointOffset(r), n = model.jointCount(), m = model.coordinateCount();
    const auto robot = [&](const JointState& x) { return std::span<const double>(x).subspan(offset, n); };
    if (!model.keepsBranch(robot(q), robot(start), robot(start))) return false;
    std::vector<double> lower(m), upper(m), at(m);
    model.coordinateBounds(robot(start), robot(q), lower, upper);
    model.coordinatesOf(robot(q), at);
    for (std::size_t i = 0; i < m; ++i)
      if (at[i] < lower[i] - 1e-9 || at[i] > upper[i] + 1e-9) return false;
  }
  return true;
}

/// The controllers follow the Cartesian segment a → b from joints `q` (updated) at the
/// generator's speeds (`query`'s, blend 0.2 s), one kControlPeriod step at a time: false with
/// `why` (no numbers: refusals count by cause) at the first step the controllers refuse, the
/// first invalid state (full clearance) or the first state walkable() refuses.
inline bool followSegment(StateValidator& validator, Controllers& controllers, const Query& query, const DualPose& a,
                          const DualPose& b, const JointState& start, JointState& q, std::string& why) {
  const double duration =
      generatorDuration(query.max_linear_velocity, query.max_angular_velocity, PlannerOptions{}.blend_time, a, b);
  const auto steps = static_cast<std::size_t>(std::ceil(duration / kControlPeriod));
  for (std::size_t i = 1; i <= steps; ++i) {
    const double s = static_cast<double>(i) / static_cast<double>(steps);
    if (!controllers.step({cartesianPoint(a.first, b.first, s), cartesianPoint(a.second, b.second, s)}, q, why)) {
      why = "the controllers refuse a step (" + why + ")";
      return false;
    }
    const ValidityResult state = validator.checkJoints(q);
    if (!state.valid()) {
      why = std::string("a state is not valid (") + toString(state.validity) + ")";
      return false;
    }
    if (!walkable(validator, q, start)) {
      why = "a state leaves the start's IK branch margins or the planner's search bounds";
      return false;
    }
  }
  return true;
}

/// Control steps the controllers may take holding the goal until their joints settle: the
/// I-SUR's IK returns a joint left off its redundancy rule (the elbow, after the delta's stroke
/// or a pitch limit moved it) by at most 5e-4 rad per solve (kinematics/isur.cpp), 2.5 rad here.
inline constexpr std::size_t kSettleSteps = 5000;

/// The controllers hold the tool poses `goal` from joints `q` (updated) until no joint moves
/// more than 1e-5 (m, rad) over a step (far below the rule's return of 5e-4 per solve; above the
/// 2.4e-6 rad to which the I-SUR's search of the elbow split at the delta's stroke resolves, whose
/// answer may jitter by that much from one solve to the next): where the robots come to rest at
/// the end of a motion, which the
/// planner's goal joints must be (a joint on its way back to the rule is not where the robot
/// stays). False with `why` when a step is refused, a state is not valid or they do not settle.
inline bool settle(StateValidator& validator, Controllers& controllers, const DualPose& goal, JointState& q,
                   std::string& why) {
  JointState before;
  for (std::size_t i = 0; i < kSettleSteps; ++i) {
    before = q;
    if (!controllers.step(goal, q, why)) {
      why = "the controllers refuse a step holding the goal (" + why + ")";
      return false;
    }
    const ValidityResult state = validator.checkJoints(q);
    if (!state.valid()) {
      why = std::string("a state is not valid where the controllers settle at the goal (") + toString(state.validity) + ")";
      return false;
    }
    double moved = 0.0;
    for (std::size_t j = 0; j < q.size(); ++j) moved = std::max(moved, std::abs(q[j] - before[j]));
    if (moved < 1e-5) return true;
  }
  why = "the controllers do not settle at the goal";
  return false;
}

/// `count` seeded queries feasible by construction (the same for every planner): the start as
/// independentQueries() samples it (valid, inside the planner's tool bounds, on each robot's
/// redundancy rule); the goal the end of a random walk from it (kWalkSegments segments drawn
/// by walkStep() for the tools that move, each kept when followSegment() follows it from where
/// the previous one ended and its end lies inside the planner's tool bounds, else drawn again,
/// kWalkTries draws at most); a third of the queries move tool 0 only, a third tool 1 only, a
/// third both (the other tool's goal is its start pose exactly). A start from which no segment is
/// followed is drawn again, and so is one where the controllers, holding the walk's end, do not
/// come to rest in valid states (settle()). The controllers followed the walk, so a path the
/// controllers follow exists; the planner's goal check is not consulted (a refusal is the
/// planner's failure).
/// `refused` counts the refused segments and starts, by cause.
inline std::vector<Query> walkedQueries(StateValidator& validator, const RandomScene& setup, std::size_t count,
                                        std::map<std::string, int>& refused) {
  const PlannerOptions& o = setup.options;
  Controllers controllers(validator);
  std::mt19937 rng(2026);
  std::vector<Query> queries;
  while (queries.size() < count) {
    Query query;
    const int moving = static_cast<int>(queries.size() % 3);  // 0: tool 0, 1: tool 1, 2: both
    const bool first_moves = moving != 1;
    query.max_linear_velocity = first_moves ? setup.first_linear : setup.second_linear;
    query.max_angular_velocity = first_moves ? setup.first_angular : setup.second_angular;
    query.start = randomValidJoints(rng, validator, o);
    DualPose at;
    validator.toolPoses(query.start, at);
    JointState q = query.start;
    std::size_t segments = 0;
    for (int draw = 0; draw < kWalkTries && segments < kWalkSegments; ++draw) {
      DualPose target = at;
      if (moving != 1) target.first = walkStep(rng, at.first);
      if (moving != 0) target.second = walkStep(rng, at.second);
      if (!o.first_bounds.contains(target.first.p) || !o.second_bounds.contains(target.second.p)) {
        ++refused["walk segment: its end outside the planner's tool bounds"];
        continue;
      }
      JointState walked = q;
      std::string why;
      if (!followSegment(validator, controllers, query, at, target, query.start, walked, why)) {
        ++refused["walk segment: " + why];
        continue;
      }
      q = walked;
      at = target;
      ++segments;
    }
    if (segments == 0) {
      ++refused["start: no walk segment followed from it"];
      continue;
    }
    std::string why;
    if (!settle(validator, controllers, at, q, why)) {
      ++refused["walk: " + why];
      continue;
    }
    query.goal = at;
    query.walked_goal = q;
    queries.push_back(query);
  }
  return queries;
}

}  // namespace cobra::planning::test
