// Speed of the Puma 260 world in MuJoCo (sim::MujocoPuma260Arm on apps/puma260/world/puma260.xml):
// world steps of 1 ms (two MuJoCo steps of 0.5 ms, six CiA 402 drives closing their loops on
// MuJoCo's joint state) with the tool pressed on the curved surface against the same world off
// the surface, and the analytic arm (sim::Puma260Arm: the drives' own motor models plus analytic
// gravity, no contact) as the peer, side by side in the same run.
//
// Every benchmark runs 10 repetitions and reports their median and worst case ("max"). One
// iteration = 1000 world steps = 1 s of simulated time at 1 kHz; `realtime_factor` = simulated s
// per wall s, `steps_per_s` = world steps per wall s. In each, the six drives are enabled in cyclic
// synchronous position and hold the joint angles of a tool pose (tool pointing down at x = 0.35 m,
// y = 0 m): 0.2 mm below the top of the surface ("contact": `contact_force` N stays > 0) or 10 mm
// above it ("free").

#include <benchmark/benchmark.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include <kdl/frames.hpp>

#include "cobra/kinematics/puma260.hpp"
#include "cobra/sim/mujoco_puma260.hpp"
#include "cobra/sim/puma260_arm.hpp"
#include "median_and_worst.hpp"

namespace {

constexpr int kRepetitions = 10;
constexpr double kMinTimePerRepetition = 0.05;  // s
constexpr double kDt = 1e-3;                    // s, 1 kHz
constexpr int kStepsPerIteration = 1000;
const std::string kModel = std::string(COBRA_SOURCE_DIR) + "/apps/puma260/world/puma260.xml";

using cobra::bench::maxOf;

void configure(benchmark::internal::Benchmark* b) {
  b->Repetitions(kRepetitions)->ReportAggregatesOnly(true)->ComputeStatistics("max", maxOf)->MinTime(kMinTimePerRepetition);
  b->UseRealTime()->Unit(benchmark::kMillisecond);
}

/// Joint angles with the tool tip at (0.35, 0, z) m pointing straight down.
std::array<double, 6> toolDownAt(double z) {
  cobra::kinematics::Puma260Solver solver({}, cobra::kinematics::Puma260Solver::defaultLimits(), KDL::Frame::Identity(),
                                          KDL::Frame(KDL::Vector(0, 0, 0.118)));
  KDL::JntArray seed(6), q(6);
  seed(1) = 1.2;
  seed(2) = -2.4;
  seed(4) = -0.4;
  if (solver.inverse(KDL::Frame(KDL::Rotation::RotX(M_PI), KDL::Vector(0.35, 0.0, z)), seed, q) !=
      cobra::kinematics::IkStatus::Ok)
    throw std::runtime_error("mujoco_bench: no IK solution for the benchmark pose");
  return {q(0), q(1), q(2), q(3), q(4), q(5)};
}

/// Enables the six drives of `arm` in cyclic synchronous position holding `q`, and lets it settle.
void enableAndSettle(cobra::sim::Puma260Plant& arm, const std::array<double, 6>& q) {
  namespace cw = cobra::sim::controlword;
  for (std::uint16_t word : {cw::kShutdown, cw::kSwitchOnCommand, cw::kEnableOperationCommand}) {
    for (int i = 0; i < 6; ++i) {
      arm.drive(i).setControlword(word);
      arm.drive(i).setTargetPosition(q[static_cast<std::size_t>(i)]);
    }
    arm.step(kDt);
    arm.step(kDt);
  }
  for (int k = 0; k < 1000; ++k) arm.step(kDt);
  for (int i = 0; i < 6; ++i) {
    if (arm.drive(i).state() != cobra::sim::Cia402State::OperationEnabled)
      throw std::runtime_error("mujoco_bench: drive " + std::to_string(i) + " is not enabled");
  }
}

void run(benchmark::State& state, cobra::sim::Puma260Plant& arm) {
  for (auto _ : state) {
    for (int i = 0; i < kStepsPerIteration; ++i) arm.step(kDt);
    benchmark::DoNotOptimize(arm.drive(1).position());
  }
  const double steps = static_cast<double>(state.iterations()) * kStepsPerIteration;
  state.counters["realtime_factor"] = benchmark::Counter(steps * kDt, benchmark::Counter::kIsRate);
  state.counters["steps_per_s"] = benchmark::Counter(steps, benchmark::Counter::kIsRate);
}

void BM_MujocoContact(benchmark::State& state) {
  const auto q = toolDownAt(0.1148);
  cobra::sim::MujocoPuma260Arm arm(kModel, cobra::sim::MujocoPuma260Arm::defaultDrives(), q);
  enableAndSettle(arm, q);
  run(state, arm);
  state.counters["contact_force"] = arm.world().contactForce();
  if (arm.world().contactForce() <= 0.0) state.SkipWithError("the tool is not in contact");
}
BENCHMARK(BM_MujocoContact)->Name("Puma260World/1s_at_1kHz/mujoco_tool_on_surface")->Apply(configure);

void BM_MujocoFree(benchmark::State& state) {
  const auto q = toolDownAt(0.125);
  cobra::sim::MujocoPuma260Arm arm(kModel, cobra::sim::MujocoPuma260Arm::defaultDrives(), q);
  enableAndSettle(arm, q);
  run(state, arm);
  state.counters["contact_force"] = arm.world().contactForce();
  if (arm.world().contactForce() != 0.0) state.SkipWithError("the tool touches the surface");
}
BENCHMARK(BM_MujocoFree)->Name("Puma260World/1s_at_1kHz/mujoco_no_contact")->Apply(configure);

void BM_AnalyticArm(benchmark::State& state) {
  const auto q = toolDownAt(0.125);
  cobra::sim::Puma260Arm arm(cobra::sim::Puma260ArmModel::defaults(), q);
  enableAndSettle(arm, q);
  run(state, arm);
}
BENCHMARK(BM_AnalyticArm)->Name("Puma260World/1s_at_1kHz/analytic_arm_peer")->Apply(configure);

}  // namespace

BENCHMARK_MAIN();
