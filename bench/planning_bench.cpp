// Cost of the motion planner's building blocks (thesis §4.5.1, DESIGN §8) on a puncturing-like
// scene: planning/test/data/two_robots.scene (a gantry stand-in for the I-SUR with column, tool
// and needle; a free-flying stand-in for the UR5 with its probe; table and a mesh phantom) plus a
// wall between the start and the goal of the gantry's tool. The stand-in robots' IK costs almost
// nothing, so the figures are those of the FCL side (object updates, broadphase, distances).
//
//  - ValidityCheck/*: StateValidator::check() on 4096 seeded random states inside the planner's
//    bounds (random orientations), cycled; `checks_per_s` is the rate. Target >= 20,000/s.
//    `valid_fraction` says how many of these states were valid.
//  - Plan/<planner>: one benchmark iteration = 100 seeded planning queries (seeds 1..100) of the
//    same start/goal; counters `median_ms`, `p95_ms`, `max_ms` of the planning time and
//    `success_rate` (time limit 0.5 s per query), and `cpu_median_ms`, the median process CPU time
//    per query (the wall-clock figures include waiting for the core on a shared machine).
//    RRT-Connect (the thesis' choice) side by side with plain RRT and PRM, OMPL's defaults
//    otherwise. Target: RRT-Connect median <= 50 ms.
// Validity checks run 10 repetitions (median and max reported); planning runs once (100 queries
// already make the statistics, and RRT can take 100 x 0.5 s).

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
#include "cobra/planning/motion_planner.hpp"

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

SceneDescription benchScene() {
  const std::string dir = std::string(COBRA_SOURCE_DIR) + "/planning/test/data";
  std::ifstream file(dir + "/two_robots.scene");
  std::ostringstream text;
  text << file.rdbuf() << "object wall environment world box 0.04 0.4 0.7 at 0 0 0.35 0 0 0\n";
  return parseScene(text.str(), "two_robots.scene + wall", dir);
}

StateValidator makeValidator() {
  return StateValidator(benchScene(), {{"isur", std::make_shared<test::StandInGantry>(0.5, 0.15, 0.8, 0.1)},
                                       {"ur5", std::make_shared<test::StandInFreeFlyer>(KDL::Vector(0, 0, 0.3), 0.7)}});
}

PlannerOptions plannerOptions(const std::string& planner, std::uint32_t seed) {
  PlannerOptions o;
  o.planner = planner;
  o.seed = seed;
  o.time_limit = kPlanningTimeLimit;
  o.first_bounds = {{-0.45, -0.45, 0.2}, {0.45, 0.45, 0.45}};
  o.second_bounds = {{-0.45, -0.1, 0.2}, {0.45, 0.6, 0.5}};
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

void BM_ValidityCheck(benchmark::State& state) {
  StateValidator validator = makeValidator();
  const PlannerOptions o = plannerOptions("RRTConnect", 1);
  std::mt19937 rng(7);
  std::vector<DualPose> states(4096);
  for (DualPose& q : states) q = {randomPose(rng, o.first_bounds), randomPose(rng, o.second_bounds)};
  std::size_t next = 0, valid = 0, checks = 0;
  for (auto _ : state) {
    const ValidityResult result = validator.check(states[next]);
    benchmark::DoNotOptimize(result);
    valid += result.valid() ? 1 : 0;
    ++checks;
    next = (next + 1) % states.size();
  }
  state.counters["checks_per_s"] = benchmark::Counter(static_cast<double>(checks), benchmark::Counter::kIsRate);
  state.counters["valid_fraction"] = static_cast<double>(valid) / static_cast<double>(checks);
}
BENCHMARK(BM_ValidityCheck)->Name("ValidityCheck/random_states")->Repetitions(kRepetitions)->ReportAggregatesOnly(true)
    ->ComputeStatistics("max", maxOf)->Unit(benchmark::kMicrosecond);

void BM_Plan(benchmark::State& state, const std::string& planner) {
  StateValidator validator = makeValidator();
  const DualPose start{KDL::Frame(KDL::Vector(-0.25, 0, 0.3)), KDL::Frame(KDL::Vector(0, 0.42, 0.3))};
  const DualPose goal{KDL::Frame(KDL::Rotation::RPY(0.3, 0, 0.5), KDL::Vector(0.25, 0, 0.3)),
                      KDL::Frame(KDL::Rotation::RotZ(1.0), KDL::Vector(0.2, 0.42, 0.3))};
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
