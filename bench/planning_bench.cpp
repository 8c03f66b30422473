// Cost of the motion planner (thesis §4.5.1, ARCHITECTURE §8) on the shipped puncturing scene
// (planning/test/scenes/puncturing.scene) with the REAL robot models (planning::makeRobotModels: the
// I-SUR puncturing kinematics and the UR5 closed form), and, as a peer, the same FCL work with the
// stand-in robots of the library tests (two_robots.scene + a wall: IK costs nothing there).
//
//  - ValidityCheck/puncturing_random: StateValidator::check() (IK of both robots, then FCL) on 4096
//    seeded random tool poses in the planner's bounds (most are unreachable for the I-SUR and
//    rejected after its IK), cycled; `checks_per_s`, `valid_fraction`, `allocs_per_check`.
//  - ValidityCheck/puncturing_valid: the same on 4096 VALID tool poses (all five group pairs queried).
//  - ValidityCheck/puncturing_joints: StateValidator::checkJoints() on the joint states of those
//    valid poses: what the joint-space planner pays per state (forward kinematics, no IK).
//  - ValidityCheck/stand_in_peer: the library tests' stand-in scene (FCL only).
//  - ScenarioQueries/<scenario>: the planning requests the puncturing procedure of that scenario
//    makes, measured where it makes them: the whole procedure runs kScenarioRuns times as `cobra
//    run apps/puncturing --scenario ...` runs it (cobra::run::runApp: lockstep, seeded, a work
//    limit instead of a time limit, so every run makes the same requests), and every step of a
//    MotionPlanner component (NeedlePlanner, USPlanner) in which it served a request (it emitted
//    e_plan_done or e_plan_failed) is timed by the wall clock. That step is the whole request as
//    the procedure has it served, from the state table's rows through the Frame Generator: the goal
//    alternatives in order, each one's goal check and room_for_* checks, the search, the then_*
//    follow-on check (and the step's clearance measurement, microseconds). Counters: `queries`
//    (requests per procedure), `median_ms`, `p95_ms`, `max_ms` over every request of every run,
//    `cpu_median_ms`, `cpu_max_ms` (the stepping thread's CPU time of those steps: without the time
//    a loaded machine gives to other processes), `success_rate` (e_plan_done over requests); the
//    slowest request's planner and simulated time go to stderr. The count of requests is checked
//    against the events in the run's log.
//  - RandomQueries/<planner>: 1,000 seeded random feasible queries on the puncturing scene (start
//    and goal joint states sampled valid inside the planner's bounds, the goal given as its tool
//    poses; a third moves the needle, a third the probe, a third both; kept only when the planner
//    accepts the query: MotionPlanner::checkGoal), work limit 10,000 checks or iterations;
//    `success_rate`, `no_path`, `path_invalid`, `refused` (queries), `median_ms`, `p95_ms`,
//    `max_ms` and `cpu_median_ms` (process CPU time:
//    wall-clock times include waiting for a shared core). RRTConnect, BiTRRT, LazyPRM, LBKPIECE1
//    and BIT* side by side on the same queries.
// Validity checks run 10 repetitions (median and max reported); planning runs once.

#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <functional>
#include <map>
#include <memory>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <time.h>

#include "../planning/test/stand_in_robots.hpp"
#include "../test_support/include/cobra/test_support/counting_new.hpp"
#include "cobra/core/core.hpp"
#include "cobra/planning/motion_planner.hpp"
#include "cobra/planning/robot_adapters.hpp"
#include "app_speed.hpp"

namespace {

using namespace cobra::planning;

constexpr int kRepetitions = 10;
constexpr int kRandomQueries = 1000;
constexpr int kScenarioRuns = 5;
constexpr double kPi = 3.141592653589793;

using cobra::bench::processCpuSeconds;
using cobra::bench::maxOf;
using cobra::bench::quantile;
using cobra::bench::BM_AppPlanningRequests;

SceneDescription standInScene() {
  const std::string dir = std::string(COBRA_SOURCE_DIR) + "/planning/test/data";
  std::ifstream file(dir + "/two_robots.scene");
  std::ostringstream text;
  text << file.rdbuf() << "object wall environment world box 0.04 0.4 0.7 at 0 0 0.35 0 0 0\n";
  return parseScene(text.str(), "two_robots.scene + wall", dir);
}

/// The puncturing scene as the deployment configures it: the needle frames have z along the
/// needle (apps/puncturing/puncturing.lua), the phantom at `phantom` (identity: as in the file).
SceneDescription puncturingScene(const KDL::Frame& phantom = KDL::Frame::Identity()) {
  SceneDescription scene = loadScene(std::string(COBRA_SOURCE_DIR) + "/planning/test/scenes/puncturing.scene");
  for (RobotPlacement& robot : scene.robots)
    if (robot.name == "isur") robot.setToolFrame(0, KDL::Frame(KDL::Rotation::RPY(0.0, kPi / 2, 0.0)));
  for (ObjectDescription& object : scene.objects)
    if (object.name == "phantom") object.offset = phantom * object.offset;
  return scene;
}

StateValidator makeValidator(SceneDescription scene) {
  RobotModels models = makeRobotModels(scene);
  return StateValidator(std::move(scene), std::move(models));
}

/// The MotionPlanner component's default bounds (components/planning), as the deployment uses them.
PlannerOptions deploymentOptions(const std::string& planner) {
  PlannerOptions o;
  o.planner = planner;
  o.first_bounds = {{-0.3, -0.3, 0.0}, {0.3, 0.3, 0.5}};
  o.second_bounds = {{-0.4, -0.5, 0.0}, {0.4, 0.4, 0.6}};
  o.tool_names = {"needle", "probe"};
  return o;
}

KDL::Frame randomPose(std::mt19937& rng, const PositionBounds& bounds) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::normal_distribution<double> normal;
  KDL::Vector p;
  for (std::size_t i = 0; i < 3; ++i)
    p(static_cast<int>(i)) = bounds.low[i] + unit(rng) * (bounds.high[i] - bounds.low[i]);
  double x = normal(rng), y = normal(rng), z = normal(rng), w = normal(rng);
  const double n = std::sqrt(x * x + y * y + z * z + w * w);
  return KDL::Frame(KDL::Rotation::Quaternion(x / n, y / n, z / n, w / n), p);
}

/// A valid joint state inside the planner's tool bounds, sampled uniformly in the joint limits
/// (the UR5 within ±π of `near`'s joints when given, so that it stays on one IK branch family).
JointState randomValidJoints(std::mt19937& rng, StateValidator& validator, const PlannerOptions& o,
                             const JointState* near = nullptr) {
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
          lo = std::max(lo, (*near)[offset + j] - kPi);
          hi = std::min(hi, (*near)[offset + j] + kPi);
        }
        q[offset + j] = lo + unit(rng) * (hi - lo);
      }
    }
    if (validator.checkJoints(q).valid() && validator.toolPoses(q, tools) && o.first_bounds.contains(tools.first.p) &&
        o.second_bounds.contains(tools.second.p))
      return q;
  }
}

void runChecks(benchmark::State& state, const std::function<bool(std::size_t)>& check, std::size_t count) {
  std::size_t next = 0, valid = 0, checks = 0;
  const long allocations_before = cobra::test_support::newCalls();
  for (auto _ : state) {
    const bool result = check(next);
    benchmark::DoNotOptimize(result);
    valid += result ? 1 : 0;
    ++checks;
    next = (next + 1) % count;
  }
  state.counters["checks_per_s"] = benchmark::Counter(static_cast<double>(checks), benchmark::Counter::kIsRate);
  state.counters["valid_fraction"] = static_cast<double>(valid) / static_cast<double>(checks);
  state.counters["allocs_per_check"] =
      static_cast<double>(cobra::test_support::newCalls() - allocations_before) / static_cast<double>(checks);
}

void BM_ValidityRandom(benchmark::State& state) {
  StateValidator validator = makeValidator(puncturingScene());
  const PlannerOptions o = deploymentOptions("RRTConnect");
  std::mt19937 rng(7);
  std::vector<DualPose> states(4096);
  for (DualPose& q : states) q = {randomPose(rng, o.first_bounds), randomPose(rng, o.second_bounds)};
  runChecks(state, [&](std::size_t i) { return validator.check(states[i]).valid(); }, states.size());
}
BENCHMARK(BM_ValidityRandom)->Name("ValidityCheck/puncturing_random")->Repetitions(kRepetitions)
    ->ReportAggregatesOnly(true)->ComputeStatistics("max", maxOf)->Unit(benchmark::kMicrosecond);

/// 4096 valid joint states and their tool poses.
struct ValidStates {
  std::vector<JointState> joints;
  std::vector<DualPose> poses;
};
ValidStates validStates(StateValidator& validator) {
  const PlannerOptions o = deploymentOptions("RRTConnect");
  std::mt19937 rng(11);
  ValidStates states;
  while (states.joints.size() < 4096) {
    states.joints.push_back(randomValidJoints(rng, validator, o));
    states.poses.emplace_back();
    validator.toolPoses(states.joints.back(), states.poses.back());
  }
  return states;
}

void BM_ValidityValid(benchmark::State& state) {
  StateValidator validator = makeValidator(puncturingScene());
  const ValidStates states = validStates(validator);
  runChecks(state, [&](std::size_t i) { return validator.check(states.poses[i]).valid(); }, states.poses.size());
}
BENCHMARK(BM_ValidityValid)->Name("ValidityCheck/puncturing_valid")->Repetitions(kRepetitions)
    ->ReportAggregatesOnly(true)->ComputeStatistics("max", maxOf)->Unit(benchmark::kMicrosecond);

void BM_ValidityJoints(benchmark::State& state) {
  StateValidator validator = makeValidator(puncturingScene());
  const ValidStates states = validStates(validator);
  runChecks(state, [&](std::size_t i) { return validator.checkJoints(states.joints[i]).valid(); },
            states.joints.size());
}
BENCHMARK(BM_ValidityJoints)->Name("ValidityCheck/puncturing_joints")->Repetitions(kRepetitions)
    ->ReportAggregatesOnly(true)->ComputeStatistics("max", maxOf)->Unit(benchmark::kMicrosecond);

void BM_ValidityStandIn(benchmark::State& state) {
  StateValidator validator(standInScene(),
                           {{"isur", std::make_shared<cobra::planning::test::StandInGantry>(0.5, 0.15, 0.8, 0.1)},
                            {"ur5", std::make_shared<cobra::planning::test::StandInFreeFlyer>(KDL::Vector(0, 0, 0.3), 0.7)}});
  PositionBounds first{{-0.45, -0.45, 0.2}, {0.45, 0.45, 0.45}}, second{{-0.45, -0.1, 0.2}, {0.45, 0.6, 0.5}};
  std::mt19937 rng(7);
  std::vector<DualPose> states(4096);
  for (DualPose& q : states) q = {randomPose(rng, first), randomPose(rng, second)};
  runChecks(state, [&](std::size_t i) { return validator.check(states[i]).valid(); }, states.size());
}
BENCHMARK(BM_ValidityStandIn)->Name("ValidityCheck/stand_in_peer")->Repetitions(kRepetitions)
    ->ReportAggregatesOnly(true)->ComputeStatistics("max", maxOf)->Unit(benchmark::kMicrosecond);

/// The requests the scenario's procedure makes, each timed where it is served (see the file comment).
BENCHMARK_CAPTURE(BM_AppPlanningRequests, two_needles,
                  cobra::bench::AppTask{"apps/puncturing", "apps/puncturing/scenarios/two_needles"}, kScenarioRuns)
    ->Name("ScenarioQueries/two_needles")->Iterations(1)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_AppPlanningRequests, three_needles,
                  cobra::bench::AppTask{"apps/puncturing", "apps/puncturing/scenarios/three_needles"}, kScenarioRuns)
    ->Name("ScenarioQueries/three_needles")->Iterations(1)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_AppPlanningRequests, vertical_needle,
                  cobra::bench::AppTask{"apps/puncturing", "apps/puncturing/scenarios/vertical_needle"}, kScenarioRuns)
    ->Name("ScenarioQueries/vertical_needle")->Iterations(1)->Unit(benchmark::kMillisecond);

/// One planning query: start joints, goal tool poses.
struct Query {
  JointState start;
  DualPose goal;
  double max_linear_velocity = 0.05;   // m/s: the trajectory generator of the planner that asks
  double max_angular_velocity = 0.5;   // rad/s
};

/// kRandomQueries seeded feasible queries (the same for every planner).
std::vector<Query> randomQueries(StateValidator& validator) {
  const PlannerOptions o = deploymentOptions("RRTConnect");
  MotionPlanner acceptance(validator, o);
  std::mt19937 rng(2026);
  std::vector<Query> queries;
  while (queries.size() < static_cast<std::size_t>(kRandomQueries)) {
    Query query;
    query.start = randomValidJoints(rng, validator, o);
    JointState goal = randomValidJoints(rng, validator, o, &query.start);
    // Which robots move: the needle, the probe, or both (one in three each).
    const int moving = static_cast<int>(queries.size() % 3);
    for (std::size_t r = 0; r < validator.scene().robots.size(); ++r) {
      const bool isur = validator.scene().robots[r].name == "isur";
      if ((moving == 0 && !isur) || (moving == 1 && isur))
        std::copy_n(query.start.begin() + static_cast<std::ptrdiff_t>(validator.jointOffset(r)),
                    validator.model(r).jointCount(), goal.begin() + static_cast<std::ptrdiff_t>(validator.jointOffset(r)));
    }
    validator.toolPoses(goal, query.goal);
    // Feasible: the planner accepts the query (its own goal check: the goal IK from the start on
    // the start's branch and redundancy rule, a valid goal state), so a failure is the search's.
    if (!acceptance.checkGoal(query.start, query.goal).solved()) continue;
    const bool needle_moves = moving != 1;
    query.max_linear_velocity = needle_moves ? 0.04 : 0.08;
    query.max_angular_velocity = needle_moves ? 0.15 : 0.5;
    queries.push_back(query);
  }
  return queries;
}

void BM_Random(benchmark::State& state, const std::string& planner) {
  StateValidator validator = makeValidator(puncturingScene());
  const std::vector<Query> queries = randomQueries(validator);
  std::vector<double> times_ms, cpu_ms;
  std::map<PlanStatus, int> outcomes;
  for (auto _ : state) {
    std::uint32_t seed = 1;
    for (const Query& query : queries) {
      PlannerOptions o = deploymentOptions(planner);
      o.max_validity_checks = 10000;
      o.seed = seed++;
      // The trajectory generator's speeds of the planner that would ask (needle_robot.lua and
      // probe_robot.lua): the needle's when the needle moves.
      o.max_linear_velocity = query.max_linear_velocity;
      o.max_angular_velocity = query.max_angular_velocity;
      MotionPlanner motion_planner(validator, o);
      const double cpu_before = processCpuSeconds();
      const PlanResult result = motion_planner.planPath(query.start, query.goal);
      cpu_ms.push_back(1e3 * (processCpuSeconds() - cpu_before));
      times_ms.push_back(1e3 * result.planning_time);
      ++outcomes[result.status];
    }
  }
  state.counters["median_ms"] = quantile(times_ms, 0.5);
  state.counters["p95_ms"] = quantile(times_ms, 0.95);
  state.counters["max_ms"] = maxOf(times_ms);
  state.counters["cpu_median_ms"] = quantile(cpu_ms, 0.5);
  state.counters["success_rate"] = static_cast<double>(outcomes[PlanStatus::Solved]) / static_cast<double>(queries.size());
  // Why the others failed: no path within the work limit, or every path found failed the dense
  // verification; anything else (a refusal at plan time) means the filter above missed a check.
  state.counters["no_path"] = outcomes[PlanStatus::NoSolution];
  state.counters["path_invalid"] = outcomes[PlanStatus::PathInvalid];
  state.counters["refused"] = static_cast<double>(queries.size()) - outcomes[PlanStatus::Solved] -
                              outcomes[PlanStatus::NoSolution] - outcomes[PlanStatus::PathInvalid];
}
BENCHMARK_CAPTURE(BM_Random, RRTConnect, std::string("RRTConnect"))->Name("RandomQueries/RRTConnect")->Iterations(1)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Random, BiTRRT, std::string("BiTRRT"))->Name("RandomQueries/BiTRRT")->Iterations(1)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Random, LazyPRM, std::string("LazyPRM"))->Name("RandomQueries/LazyPRM")->Iterations(1)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Random, LBKPIECE1, std::string("LBKPIECE1"))->Name("RandomQueries/LBKPIECE1")->Iterations(1)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Random, BITstar, std::string("BITstar"))->Name("RandomQueries/BITstar")->Iterations(1)
    ->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
