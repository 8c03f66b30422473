// The suturing task (thesis ch. 5, apps/suturing) measured two ways, each beside a peer in the same
// run:
//  - ProcedureSpeed/<scenario>: the whole procedure as `cobra run apps/suturing` runs it (the
//    runner's observers attached); realtime_factor = simulated s per wall s (median, and min = the
//    worst of the repetitions), cpu_realtime_factor = the same per CPU s of the process. Peer: the
//    puncturing task's default procedure (ProcedureSpeed/puncturing_two_needles).
//  - ProcedureRequests/<scenario>: the planning requests the procedure makes, timed where it
//    makes them (app_speed.hpp's BM_AppPlanningRequests, 3 runs).
//  - SuturingQueries/<planner>: planned motions like the default procedure's MoveOverWound, in the
//    robot's joint space as the deployment plans them (from the measured joints): the Endo Stitch
//    from its initial pose to 3 cm above the first stitch's centre, then on to above each next
//    stitch (each query from the joints where the previous path ended), the stick holding;
//    reconstructed from the app's files (the straight cut's four stitches, the robot's initial
//    joints, the app's tool frame and phantom placement) on planning/test/scenes/suturing.scene with the
//    real two-armed I-SUR model, the sequence planned with 5 seeds and the deployment's settings
//    (work limit 20,000 checks); counters median_ms, p95_ms, max_ms, success_rate. RRTConnect (the
//    deployment's) beside BiTRRT on the same queries.

#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>
#include <vector>

#include "cobra/components/planning/planning_scene_component.hpp"
#include "cobra/kinematics/isur.hpp"
#include "cobra/planning/motion_planner.hpp"
#include "cobra/planning/robot_adapters.hpp"
#include "cobra/planning/state_validator.hpp"
#include "app_speed.hpp"

namespace {

constexpr double kPi = 3.14159265358979323846;
const std::string kSource = COBRA_SOURCE_DIR;


// apps/suturing: frames.lua (the tools' frames), suturing.lua (phantom under the wound), deployment/world.lua (base,
// initial joints), scenarios/straight_cut (the wound at (0.178, 0, 0.06), a 40 mm cut along x),
// the StitchPlanner's defaults (8 mm spacing and margins, 2 mm deep), state_table.txt
// (MoveOverWound: centre-0.03), the Frame Generator's pull_offset (0.037 m above the centre).
const KDL::Frame kRightToolFrame(KDL::Rotation::RPY(kPi, -1.2, 0.0));
const KDL::Frame kLeftToolFrame(KDL::Rotation::RotY(-0.6) * KDL::Rotation::RotZ(-0.6), KDL::Vector(0.0, 0.0, 0.15));
const KDL::Frame kBase(KDL::Vector(0.0, 0.0, 1.0));
const double kInitialJoints[14] = {0.0997079, 0.0995231, 0.0998925, 0, 0, 0.75, 0.45, 0,
                                   -0.0755758, 1.01212, -0.823385, 0.541061, -0.755379, 0.171985};

/// The goals: the Endo Stitch 3 cm above each stitch's centre, the stick where it starts.
std::vector<cobra::planning::DualPose> suturingGoals() {
  cobra::kinematics::IsurSuturingSolver solver;
  KDL::JntArray q(14);
  for (unsigned i = 0; i < 14; ++i) q(i) = kInitialJoints[i];
  KDL::Frame right, left;
  (void)solver.forward(q, right, left);
  const KDL::Frame stick = kBase * left * kLeftToolFrame;
  const KDL::Rotation down = KDL::Rotation::RotX(kPi);  // the datums: z into the skin, x along the cut
  std::vector<cobra::planning::DualPose> goals;
  for (int k = 0; k < 4; ++k) {
    const KDL::Vector centre(0.178 - 0.02 + 0.008 * (k + 1), 0.0, 0.06 - 0.002);
    goals.push_back({KDL::Frame(down, centre + KDL::Vector(0.0, 0.0, 0.03)), stick});
  }
  return goals;
}

void BM_SuturingQueries(benchmark::State& state, const std::string& planner_name) {
  cobra::components::PlanningSceneSettings settings;
  settings.scene_file = kSource + "/planning/test/scenes/suturing.scene";
  settings.first_tool_frame = kRightToolFrame;
  settings.second_tool_frame = kLeftToolFrame;
  settings.phantom_pose = KDL::Frame(KDL::Vector(0.178, 0.0, 0.0));
  cobra::planning::SceneDescription scene = cobra::components::buildPlanningScene(settings);
  cobra::planning::RobotModels models = cobra::planning::makeRobotModels(scene);
  cobra::planning::StateValidator validator(std::move(scene), std::move(models));
  cobra::planning::PlannerOptions options;
  options.planner = planner_name;
  options.max_validity_checks = 20000;
  options.first_bounds = {{0.05, -0.12, 0.05}, {0.3, 0.12, 0.3}};
  options.second_bounds = {{0.05, -0.12, 0.05}, {0.3, 0.12, 0.3}};
  options.max_linear_velocity = 0.02;
  options.max_angular_velocity = 0.3;
  const std::vector<cobra::planning::DualPose> goals = suturingGoals();
  std::vector<double> times_ms;
  int solved = 0, asked = 0;
  for (auto _ : state) {
    for (int repetition = 0; repetition < 5; ++repetition) {
      options.seed = static_cast<std::uint32_t>(repetition + 1);
      cobra::planning::MotionPlanner planner(validator, options);
      cobra::planning::JointState start(std::begin(kInitialJoints), std::end(kInitialJoints));
      for (const cobra::planning::DualPose& goal : goals) {
        const auto started = std::chrono::steady_clock::now();
        const cobra::planning::PlanResult result = planner.planPath(start, goal);
        times_ms.push_back(1e3 * std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count());
        ++asked;
        if (result.status == cobra::planning::PlanStatus::Solved) {
          ++solved;
          start = result.joint_waypoints.back();
        } else {
          std::fprintf(stderr, "%s: %s\n", planner_name.c_str(), result.message.c_str());
        }
      }
    }
  }
  std::sort(times_ms.begin(), times_ms.end());
  const auto at = [&](double fraction) {
    return times_ms[std::min(times_ms.size() - 1, static_cast<std::size_t>(fraction * static_cast<double>(times_ms.size())))];
  };
  state.counters["queries"] = static_cast<double>(asked);
  state.counters["success_rate"] = asked > 0 ? static_cast<double>(solved) / asked : 0.0;
  state.counters["median_ms"] = at(0.5);
  state.counters["p95_ms"] = at(0.95);
  state.counters["max_ms"] = times_ms.back();
}
BENCHMARK_CAPTURE(BM_SuturingQueries, RRTConnect, std::string("RRTConnect"))
    ->Name("SuturingQueries/RRTConnect")->Iterations(1)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_SuturingQueries, BiTRRT, std::string("BiTRRT"))
    ->Name("SuturingQueries/BiTRRT")->Iterations(1)->Unit(benchmark::kMillisecond);

}  // namespace

int main(int argc, char** argv) {
  // The whole procedure (app_speed.hpp), the puncturing task's default procedure as the peer.
  for (const char* scenario : {"straight_cut", "slanted_cut"})
    cobra::bench::registerAppSpeed(std::string("ProcedureSpeed/") + scenario,
                                   {"apps/suturing", std::string("apps/suturing/scenarios/") + scenario});
  cobra::bench::registerAppSpeed("ProcedureSpeed/puncturing_two_needles",
                                 {"apps/puncturing", "apps/puncturing/scenarios/two_needles"});
  // The planning requests the procedure itself makes (app_speed.hpp), beside the reconstructed
  // queries that compare planners above.
  for (const char* scenario : {"straight_cut", "slanted_cut"})
    benchmark::RegisterBenchmark((std::string("ProcedureRequests/") + scenario).c_str(),
                                 cobra::bench::BM_AppPlanningRequests,
                                 cobra::bench::AppTask{"apps/suturing", std::string("apps/suturing/scenarios/") + scenario},
                                 3)
        ->Iterations(1)
        ->Unit(benchmark::kMillisecond);
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
