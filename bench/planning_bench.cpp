// Cost of the motion planner (thesis §4.5.1, ARCHITECTURE §8) on the shipped puncturing scene
// (planning/scenes/puncturing.scene) with the REAL robot models (planning::makeRobotModels: the
// I-SUR puncturing kinematics and the UR5 closed form), and, as a peer, the same FCL work with the
// stand-in robots of the library tests (two_robots.scene + a wall: IK costs nothing there).
//
//  - ValidityCheck/puncturing_random: StateValidator::check() on 4096 seeded random states in the
//    planner's bounds (random orientations: most are unreachable for the I-SUR and rejected after
//    its IK), cycled; `checks_per_s` is the rate (target >= 20,000/s), `valid_fraction` how many
//    were valid, `allocs_per_check` the operator new calls per check (0 on primitive scenes
//    since the distance queries use FCL's own GJK; libccd's allocated ~2 per narrow-phase query).
//  - ValidityCheck/puncturing_valid: the same on 4096 VALID states (needle within 30 deg of
//    vertical, probe pointing down: rejection-sampled), where all five group pairs are queried:
//    the worst case, and the State Validator component's cost per teleoperation set-point.
//  - ValidityCheck/stand_in_peer: the library tests' stand-in scene (FCL only).
//  - Plan/<planner>: one iteration = 100 seeded planning queries (seeds 1..100) moving the probe
//    around the phantom (the query of planning/test/real_robots_test.cpp); counters `median_ms`,
//    `p95_ms`, `max_ms` of the planning time, `success_rate` (time limit 0.5 s per query) and
//    `cpu_median_ms` (process CPU time; wall-clock figures include waiting for a shared core).
//    RRT-Connect (the thesis' choice) side by side with plain RRT and PRM. Target: RRT-Connect
//    median <= 50 ms and 100 % success.
// Validity checks run 10 repetitions (median and max reported); planning runs once.

#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <time.h>

#include "../planning/test/stand_in_robots.hpp"
#include "../test_support/include/cobra/test_support/counting_new.hpp"
#include "cobra/planning/motion_planner.hpp"
#include "cobra/planning/robot_adapters.hpp"

namespace {

using namespace cobra::planning;

constexpr int kRepetitions = 10;
constexpr int kQueries = 100;
constexpr double kPlanningTimeLimit = 0.5;  // s per query

/// CPU time of the whole process [s]: on a shared machine the wall-clock planning time also counts
/// the time other processes hold the cores.
double processCpuSeconds() {
  timespec now{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &now);
  return static_cast<double>(now.tv_sec) + 1e-9 * static_cast<double>(now.tv_nsec);
}

double maxOf(const std::vector<double>& v) { return *std::max_element(v.begin(), v.end()); }

SceneDescription standInScene() {
  const std::string dir = std::string(COBRA_SOURCE_DIR) + "/planning/test/data";
  std::ifstream file(dir + "/two_robots.scene");
  std::ostringstream text;
  text << file.rdbuf() << "object wall environment world box 0.04 0.4 0.7 at 0 0 0.35 0 0 0\n";
  return parseScene(text.str(), "two_robots.scene + wall", dir);
}

StateValidator makeStandInValidator() {
  return StateValidator(standInScene(), {{"isur", std::make_shared<test::StandInGantry>(0.5, 0.15, 0.8, 0.1)},
                                       {"ur5", std::make_shared<test::StandInFreeFlyer>(KDL::Vector(0, 0, 0.3), 0.7)}});
}

PlannerOptions standInOptions() {
  PlannerOptions o;
  o.first_bounds = {{-0.45, -0.45, 0.2}, {0.45, 0.45, 0.45}};
  o.second_bounds = {{-0.45, -0.1, 0.2}, {0.45, 0.6, 0.5}};
  return o;
}

StateValidator makePuncturingValidator() {
  SceneDescription scene = loadScene(std::string(COBRA_SOURCE_DIR) + "/planning/scenes/puncturing.scene");
  RobotModels models = makeRobotModels(scene);
  return StateValidator(std::move(scene), std::move(models));
}

/// The bounds of planning/test/real_robots_test.cpp: needle around the phantom's top, probe around the phantom.
PlannerOptions plannerOptions(const std::string& planner, std::uint32_t seed) {
  PlannerOptions o;
  o.planner = planner;
  o.seed = seed;
  o.time_limit = kPlanningTimeLimit;
  o.first_bounds = {{-0.15, -0.15, 0.15}, {0.15, 0.15, 0.3}};
  o.second_bounds = {{-0.3, -0.3, 0.03}, {0.35, 0.3, 0.35}};
  return o;
}

constexpr double kPi = 3.141592653589793;
KDL::Frame needleDown(double x, double y, double z) { return {KDL::Rotation::RotY(kPi / 2), KDL::Vector(x, y, z)}; }
KDL::Frame probeDown(double x, double y, double z) { return {KDL::Rotation::RotX(kPi), KDL::Vector(x, y, z)}; }

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

void runChecks(benchmark::State& state, StateValidator& validator, const std::vector<DualPose>& states) {
  std::size_t next = 0, valid = 0, checks = 0;
  const long allocations_before = cobra::test_support::newCalls();
  for (auto _ : state) {
    const ValidityResult result = validator.check(states[next]);
    benchmark::DoNotOptimize(result);
    valid += result.valid() ? 1 : 0;
    ++checks;
    next = (next + 1) % states.size();
  }
  state.counters["checks_per_s"] = benchmark::Counter(static_cast<double>(checks), benchmark::Counter::kIsRate);
  state.counters["valid_fraction"] = static_cast<double>(valid) / static_cast<double>(checks);
  state.counters["allocs_per_check"] =
      static_cast<double>(cobra::test_support::newCalls() - allocations_before) / static_cast<double>(checks);
}

void BM_ValidityRandom(benchmark::State& state) {
  StateValidator validator = makePuncturingValidator();
  const PlannerOptions o = plannerOptions("RRTConnect", 1);
  std::mt19937 rng(7);
  std::vector<DualPose> states(4096);
  for (DualPose& q : states) q = {randomPose(rng, o.first_bounds), randomPose(rng, o.second_bounds)};
  runChecks(state, validator, states);
}
BENCHMARK(BM_ValidityRandom)->Name("ValidityCheck/puncturing_random")->Repetitions(kRepetitions)
    ->ReportAggregatesOnly(true)->ComputeStatistics("max", maxOf)->Unit(benchmark::kMicrosecond);

void BM_ValidityValid(benchmark::State& state) {
  StateValidator validator = makePuncturingValidator();
  const PlannerOptions o = plannerOptions("RRTConnect", 1);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> tilt(-0.5, 0.5), yaw(-kPi, kPi), unit(0.0, 1.0);
  std::vector<DualPose> states;
  while (states.size() < 4096) {
    const auto position = [&](const PositionBounds& b) {
      return KDL::Vector(b.low[0] + unit(rng) * (b.high[0] - b.low[0]), b.low[1] + unit(rng) * (b.high[1] - b.low[1]),
                         b.low[2] + unit(rng) * (b.high[2] - b.low[2]));
    };
    const DualPose q{KDL::Frame(KDL::Rotation::RPY(tilt(rng), tilt(rng), 0.0) * needleDown(0, 0, 0).M,
                                position(o.first_bounds)),
                     KDL::Frame(KDL::Rotation::RotZ(yaw(rng)) * probeDown(0, 0, 0).M, position(o.second_bounds))};
    if (validator.isStateValid(q)) states.push_back(q);
  }
  runChecks(state, validator, states);
}
BENCHMARK(BM_ValidityValid)->Name("ValidityCheck/puncturing_valid")->Repetitions(kRepetitions)
    ->ReportAggregatesOnly(true)->ComputeStatistics("max", maxOf)->Unit(benchmark::kMicrosecond);

void BM_ValidityStandIn(benchmark::State& state) {
  StateValidator validator = makeStandInValidator();
  const PlannerOptions o = standInOptions();
  std::mt19937 rng(7);
  std::vector<DualPose> states(4096);
  for (DualPose& q : states) q = {randomPose(rng, o.first_bounds), randomPose(rng, o.second_bounds)};
  runChecks(state, validator, states);
}
BENCHMARK(BM_ValidityStandIn)->Name("ValidityCheck/stand_in_peer")->Repetitions(kRepetitions)
    ->ReportAggregatesOnly(true)->ComputeStatistics("max", maxOf)->Unit(benchmark::kMicrosecond);

void BM_Plan(benchmark::State& state, const std::string& planner) {
  StateValidator validator = makePuncturingValidator();
  const DualPose start{needleDown(0.0, 0.0, 0.2), probeDown(-0.2, 0.0, 0.06)};
  const DualPose goal{needleDown(0.0, 0.0, 0.2), probeDown(0.25, 0.0, 0.06)};
  std::vector<double> times_ms, cpu_ms;
  int solved = 0;
  for (auto _ : state) {
    times_ms.clear();
    cpu_ms.clear();
    solved = 0;
    for (std::uint32_t seed = 1; seed <= kQueries; ++seed) {
      MotionPlanner motion_planner(validator, plannerOptions(planner, seed));
      const double cpu_before = processCpuSeconds();
      const PlanResult result = motion_planner.planPath(start, goal);
      cpu_ms.push_back(1e3 * (processCpuSeconds() - cpu_before));
      times_ms.push_back(1e3 * result.planning_time);
      solved += result.solved() ? 1 : 0;
    }
  }
  std::sort(times_ms.begin(), times_ms.end());
  std::sort(cpu_ms.begin(), cpu_ms.end());
  const auto quantile = [](const std::vector<double>& sorted, double q) {
    return sorted[static_cast<std::size_t>(q * double(sorted.size() - 1))];
  };
  state.counters["median_ms"] = quantile(times_ms, 0.5);
  state.counters["p95_ms"] = quantile(times_ms, 0.95);
  state.counters["max_ms"] = times_ms.back();
  state.counters["cpu_median_ms"] = quantile(cpu_ms, 0.5);
  state.counters["success_rate"] = static_cast<double>(solved) / kQueries;
}
BENCHMARK_CAPTURE(BM_Plan, RRTConnect, std::string("RRTConnect"))->Name("Plan/RRTConnect")->Iterations(1)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Plan, RRT, std::string("RRT"))->Name("Plan/RRT")->Iterations(1)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Plan, PRM, std::string("PRM"))->Name("Plan/PRM")->Iterations(1)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
