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
//  - RandomQueries/<planner>, RandomQueriesSuturing/<planner>: 1,000 seeded random feasible
//    queries on the puncturing scene and on the suturing application's scene
//    (planning/test/random_queries.hpp, walkedQueries: feasible by construction, the goal the end
//    of a random walk of the tools from a valid start on the robots' redundancy rule, every step
//    followed by the controllers' continuity-keeping IK, every state valid, on the start's IK
//    branch and inside the planner's search bounds; a third moves tool 0, a third tool 1, a third
//    both), each scene's planner as its deployment configures it (puncturing: work limit 10,000
//    checks or iterations; suturing: 20,000); `success_rate` (over every query: a goal the
//    planner refuses is a failure), `no_path`, `path_invalid`, `refused` (queries),
//    `median_ms`, `p95_ms`, `max_ms` and `cpu_median_ms` (process CPU time: wall-clock times
//    include waiting for a shared core), `searches_per_query`, `re_searched` (queries
//    re-searched after a failed verification), `sampled_refused` (walk segments and starts
//    drawn again, by cause on stderr, with each failure's message by count and the failed queries'
//    indices: query i is planned with seed i + 1). RRTConnect, BiTRRT,
//    LazyPRM, LBKPIECE1 and BIT* side by side on the same queries; after the run a table of
//    success, median, p95 and worst per planner and draw goes to stdout.
//  - RandomQueriesIndependent/RRTConnect, RandomQueriesSuturingIndependent/RRTConnect: the
//    default planner on the independent draw (independentQueries: start and goal sampled apart,
//    kept when the planner's goal check accepts the goal; a path need not exist), the second,
//    reported figure.
// Validity checks run 10 repetitions (median and max reported); planning runs once.

#include <benchmark/benchmark.h>

#include <algorithm>
#include <cctype>
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

#include "../planning/test/random_queries.hpp"
#include "../planning/test/stand_in_robots.hpp"
#include "../test_support/include/cobra/test_support/counting_new.hpp"
#include "cobra/core/core.hpp"
#include "cobra/planning/motion_planner.hpp"
#include "cobra/planning/robot_adapters.hpp"
#include "app_speed.hpp"

namespace {

using namespace cobra::planning;
using namespace cobra::planning::test;

constexpr int kRepetitions = 10;
constexpr std::size_t kRandomQueries = 1000;
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

StateValidator makeValidator(SceneDescription scene) {
  RobotModels models = makeRobotModels(scene);
  return StateValidator(std::move(scene), std::move(models));
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
    states.joints.push_back(randomValidJoints(rng, validator, o, nullptr, false));
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

/// `message` with every number replaced by '#': failures of one kind count together.
std::string reasonOf(const std::string& message) {
  std::string reason;
  for (std::size_t i = 0; i < message.size(); ++i) {
    const bool digit = std::isdigit(static_cast<unsigned char>(message[i])) != 0;
    if (!digit && !(message[i] == '.' && i > 0 && std::isdigit(static_cast<unsigned char>(message[i - 1])) != 0) &&
        !(message[i] == '-' && i + 1 < message.size() && std::isdigit(static_cast<unsigned char>(message[i + 1])) != 0)) {
      reason += message[i];
    } else if (reason.empty() || reason.back() != '#') {
      reason += '#';
    }
  }
  return reason;
}

/// One row of the summary table printed after the run.
struct RandomRow {
  std::string name;
  double success = 0.0, median = 0.0, p95 = 0.0, worst = 0.0;
  std::size_t queries = 0;
};
std::vector<RandomRow>& randomRows() {
  static std::vector<RandomRow> rows;
  return rows;
}

/// The queries of one scene and draw, drawn once for every planner (they do not depend on it).
const std::vector<Query>& drawnQueries(const std::string& scene_name, bool walked, StateValidator& validator,
                                       const RandomScene& setup, std::map<std::string, int>& refused) {
  struct Drawn {
    std::vector<Query> queries;
    std::map<std::string, int> refused;
  };
  static std::map<std::string, Drawn> cache;
  const std::string key = scene_name + (walked ? "/walked" : "/independent");
  auto found = cache.find(key);
  if (found == cache.end()) {
    Drawn drawn;
    drawn.queries = walked ? walkedQueries(validator, setup, kRandomQueries, drawn.refused)
                           : independentQueries(validator, setup, kRandomQueries, drawn.refused);
    found = cache.emplace(key, std::move(drawn)).first;
  }
  refused = found->second.refused;
  return found->second.queries;
}

void BM_Random(benchmark::State& state, const std::string& scene_name, bool walked, const RandomScene& setup) {
  StateValidator validator = makeValidator(setup.scene());
  std::map<std::string, int> refused;
  const std::vector<Query>& queries = drawnQueries(scene_name, walked, validator, setup, refused);
  std::vector<double> times_ms, cpu_ms;
  std::map<PlanStatus, int> outcomes;
  std::map<std::string, std::vector<std::size_t>> reasons;  // failure cause -> the queries' indices
  std::size_t searches = 0, researched = 0;
  for (auto _ : state) {
    std::uint32_t seed = 1;
    for (std::size_t index = 0; index < queries.size(); ++index) {
      const Query& query = queries[index];
      PlannerOptions o = setup.options;
      o.seed = seed++;
      // The trajectory generator's speeds of the planner that would ask.
      o.max_linear_velocity = query.max_linear_velocity;
      o.max_angular_velocity = query.max_angular_velocity;
      MotionPlanner motion_planner(validator, o);
      const double cpu_before = processCpuSeconds();
      const PlanResult result = motion_planner.planPath(query.start, query.goal);
      cpu_ms.push_back(1e3 * (processCpuSeconds() - cpu_before));
      times_ms.push_back(1e3 * result.planning_time);
      ++outcomes[result.status];
      searches += result.searches;
      researched += result.searches > 1 ? 1 : 0;
      if (!result.solved()) reasons[std::string(toString(result.status)) + ": " + reasonOf(result.message)].push_back(index);
    }
  }
  const double success = static_cast<double>(outcomes[PlanStatus::Solved]) / static_cast<double>(queries.size());
  state.counters["median_ms"] = quantile(times_ms, 0.5);
  state.counters["p95_ms"] = quantile(times_ms, 0.95);
  state.counters["max_ms"] = maxOf(times_ms);
  state.counters["cpu_median_ms"] = quantile(cpu_ms, 0.5);
  state.counters["success_rate"] = success;
  randomRows().push_back({(walked ? "walked " : "independent ") + scene_name + " / " + setup.options.planner, success,
                          quantile(times_ms, 0.5), quantile(times_ms, 0.95), maxOf(times_ms), queries.size()});
  // Why the others failed: no path within the work limit, or every path found failed the dense
  // verification; anything else is the planner refusing the query at plan time (its goal check:
  // on the walked draw a goal the controllers reached).
  state.counters["no_path"] = outcomes[PlanStatus::NoSolution];
  state.counters["path_invalid"] = outcomes[PlanStatus::PathInvalid];
  state.counters["refused"] = static_cast<double>(queries.size()) - outcomes[PlanStatus::Solved] -
                              outcomes[PlanStatus::NoSolution] - outcomes[PlanStatus::PathInvalid];
  // How much of the work went into re-runs after a path failed the verification.
  state.counters["searches_per_query"] = static_cast<double>(searches) / static_cast<double>(queries.size());
  state.counters["re_searched"] = static_cast<double>(researched);
  // Samples drawn again (walk segments and starts, or refused independent goals), by cause.
  int sampled_refused = 0;
  std::string refusals;
  for (const auto& [why, count] : refused) {
    sampled_refused += count;
    refusals += std::string(refusals.empty() ? "" : ", ") + std::to_string(count) + " " + why;
  }
  state.counters["sampled_refused"] = sampled_refused;
  // The failures' causes (numbers as '#'), most frequent first, each with its first queries'
  // indices (a query's seed is its index + 1: random_queries_test.cpp replays it), to stderr.
  std::vector<std::pair<int, std::string>> causes;
  for (const auto& [reason, indices] : reasons) {
    std::string listed;
    for (std::size_t i = 0; i < indices.size() && i < 20; ++i) listed += (i == 0 ? "" : " ") + std::to_string(indices[i]);
    if (indices.size() > 20) listed += " ...";
    causes.emplace_back(static_cast<int>(indices.size()), reason + " [queries " + listed + "]");
  }
  std::sort(causes.rbegin(), causes.rend());
  std::fprintf(stderr, "RandomQueries %s %s/%s: %zu queries (%d samples drawn again: %s)\n",
               walked ? "walked" : "independent", scene_name.c_str(), setup.options.planner.c_str(), queries.size(),
               sampled_refused, refusals.c_str());
  for (const auto& [count, reason] : causes) std::fprintf(stderr, "  %4d x %s\n", count, reason.c_str());
}

#define COBRA_RANDOM_QUERIES(PLANNER)                                                                        \
  BENCHMARK_CAPTURE(BM_Random, PLANNER, std::string("puncturing"), true, puncturingRandom(#PLANNER))         \
      ->Name("RandomQueries/" #PLANNER)->Iterations(1)->Unit(benchmark::kMillisecond);                       \
  BENCHMARK_CAPTURE(BM_Random, suturing_##PLANNER, std::string("suturing"), true, suturingRandom(#PLANNER))  \
      ->Name("RandomQueriesSuturing/" #PLANNER)->Iterations(1)->Unit(benchmark::kMillisecond)
COBRA_RANDOM_QUERIES(RRTConnect);
COBRA_RANDOM_QUERIES(BiTRRT);
COBRA_RANDOM_QUERIES(LazyPRM);
COBRA_RANDOM_QUERIES(LBKPIECE1);
COBRA_RANDOM_QUERIES(BITstar);
BENCHMARK_CAPTURE(BM_Random, independent, std::string("puncturing"), false, puncturingRandom("RRTConnect"))
    ->Name("RandomQueriesIndependent/RRTConnect")->Iterations(1)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Random, suturing_independent, std::string("suturing"), false, suturingRandom("RRTConnect"))
    ->Name("RandomQueriesSuturingIndependent/RRTConnect")->Iterations(1)->Unit(benchmark::kMillisecond);

}  // namespace

// BENCHMARK_MAIN, then the random queries' figures side by side (when any ran).
int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  if (randomRows().empty()) return 0;
  std::printf("\n%-44s %8s %9s %10s %10s %10s\n", "random queries: draw scene / planner", "queries", "success",
              "median ms", "p95 ms", "worst ms");
  for (const RandomRow& row : randomRows())
    std::printf("%-44s %8zu %8.1f%% %10.1f %10.1f %10.1f\n", row.name.c_str(), row.queries, 100.0 * row.success,
                row.median, row.p95, row.worst);
  return 0;
}

