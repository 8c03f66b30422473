// Cost of cobra::trajectory (the thesis' TGL, §3.2.3) against KDL's trajectories, side by side in
// the same run (ARCHITECTURE §8).
//
// Every benchmark runs 10 repetitions and reports their median and worst case ("max") of the mean
// time per iteration; `mean`/`stddev`/`cv` come for free. Times of evaluation benchmarks cycle
// through 1024 precomputed instants spread over the whole trajectory (and slightly beyond its
// ends), so the segment search and branches see realistic, varying input. Groups:
//  - QuinticEval: position, velocity and acceleration of one quintic (order-5 polynomial meeting
//    position/velocity/acceleration at both ends) per iteration: cobra::trajectory::Polynomial
//    (one call returns all of them) vs KDL::VelocityProfile_Spline (Pos + Vel + Acc).
//  - CartesianEval: pose and twist of a 10-waypoint Cartesian path per iteration:
//    cobra::trajectory::CartesianTrajectory (linear segments with quintic blends, orientation on
//    SO(3)) vs KDL::Trajectory_Segment of a Path_RoundedComposite with a VelocityProfile_Trap
//    (Pos + Vel). The two paths differ in geometry (KDL rounds corners with circles in space);
//    what is compared is the cost of one set-point for the same waypoints.
//  - Construction: building a 12-axis 10-waypoint MultiAxisTrajectory (synchronised, quintic
//    blends), and the 10-waypoint Cartesian paths of CartesianEval (cobra vs KDL).
// Target: evaluation well under 1 us, so a 1 kHz generator spends < 0.1 % of its period on it.

#include <benchmark/benchmark.h>

#include <algorithm>
#include <array>
#include <memory>
#include <random>
#include <vector>

#include <kdl/path_roundedcomposite.hpp>
#include <kdl/rotational_interpolation_sa.hpp>
#include <kdl/trajectory_segment.hpp>
#include <kdl/velocityprofile_spline.hpp>
#include <kdl/velocityprofile_trap.hpp>

#include "cobra/trajectory/tgl.hpp"
#include "median_and_worst.hpp"

namespace {

namespace tgl = cobra::trajectory;

constexpr int kRepetitions = 10;
constexpr double kMinTimePerRepetition = 0.05;  // s; keeps the whole file well under a minute
constexpr std::size_t kTimes = 1024;
constexpr int kWaypoints = 10;
constexpr int kAxes = 12;

using cobra::bench::maxOf;

/// Median and max over repetitions, aggregates only.
void configure(benchmark::internal::Benchmark* b) {
  b->Repetitions(kRepetitions)->ReportAggregatesOnly(true)->ComputeStatistics("max", maxOf)->MinTime(kMinTimePerRepetition);
}

/// Evaluation instants over [-1 %, 101 %] of `duration`, shuffled.
std::array<double, kTimes> sampleTimes(double duration) {
  std::array<double, kTimes> times{};
  for (std::size_t i = 0; i < kTimes; ++i) times[i] = duration * (-0.01 + 1.02 * static_cast<double>(i) / kTimes);
  std::shuffle(times.begin(), times.end(), std::mt19937(5));
  return times;
}

/// The same 10 Cartesian waypoints for both libraries: a zig-zag with turning orientation.
std::vector<KDL::Frame> cartesianWaypoints() {
  std::vector<KDL::Frame> frames;
  for (int k = 0; k < kWaypoints; ++k)
    frames.emplace_back(KDL::Rotation::RPY(0.1 * k, 0.05 * (k % 3), -0.15 * k),
                        KDL::Vector(0.05 * k, (k % 2 == 0 ? 0.0 : 0.08), 0.3 + 0.01 * k));
  return frames;
}

const tgl::CartesianLimits kCartesianLimits{0.1, 0.5, 0.2, 0.2};

/// KDL's peer of CartesianTrajectory: rounded composite (radius 0.01 m) with a trapezoidal profile.
std::unique_ptr<KDL::Trajectory_Segment> kdlCartesian(const std::vector<KDL::Frame>& frames) {
  auto* path = new KDL::Path_RoundedComposite(0.01, 0.05, new KDL::RotationalInterpolation_SingleAxis());
  for (const KDL::Frame& f : frames) path->Add(f);
  path->Finish();
  auto* profile = new KDL::VelocityProfile_Trap(kCartesianLimits.max_linear_velocity, 0.5);
  profile->SetProfile(0.0, path->PathLength());
  return std::make_unique<KDL::Trajectory_Segment>(path, profile);
}

tgl::MultiAxisPath multiAxisPath() {
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> position(-1.0, 1.0);
  tgl::MultiAxisPath path;
  for (int k = 0; k < kWaypoints; ++k) {
    std::vector<double> q(kAxes);
    for (double& v : q) v = position(rng);
    path.addWaypoint(q);
  }
  return path;
}

const tgl::AxisLimits kAxisLimits{std::vector<double>(kAxes, 1.0), std::vector<double>(kAxes, 0.2)};

// ---------------------------------------------------------------------------------------------
// QuinticEval

const tgl::State kStart{0.1, 0.5, -1.0}, kEnd{1.3, -0.2, 0.4};
constexpr double kQuinticDuration = 2.0;

void BM_QuinticEval_cobra(benchmark::State& state) {
  const tgl::Polynomial quintic(5, tgl::Conditions(kStart, kEnd), kQuinticDuration);
  const auto times = sampleTimes(kQuinticDuration);
  tgl::State out;
  std::size_t i = 0;
  for (auto _ : state) {
    quintic.evaluate(times[i++ % kTimes], out);
    benchmark::DoNotOptimize(out);
  }
  state.SetItemsProcessed(state.iterations());
}

void BM_QuinticEval_kdl_spline(benchmark::State& state) {
  KDL::VelocityProfile_Spline spline;
  spline.SetProfileDuration(kStart.position, kStart.velocity, kStart.acceleration, kEnd.position, kEnd.velocity,
                            kEnd.acceleration, kQuinticDuration);
  const KDL::VelocityProfile& profile = spline;  // called through the interface, as KDL's users do
  const auto times = sampleTimes(kQuinticDuration);
  std::size_t i = 0;
  for (auto _ : state) {
    const double t = times[i++ % kTimes];
    benchmark::DoNotOptimize(profile.Pos(t));
    benchmark::DoNotOptimize(profile.Vel(t));
    benchmark::DoNotOptimize(profile.Acc(t));
  }
  state.SetItemsProcessed(state.iterations());
}

BENCHMARK(BM_QuinticEval_cobra)->Name("BM_QuinticEval/cobra_polynomial5")->Apply(configure);
BENCHMARK(BM_QuinticEval_kdl_spline)->Name("BM_QuinticEval/kdl_velocityprofile_spline")->Apply(configure);

// ---------------------------------------------------------------------------------------------
// CartesianEval

void BM_CartesianEval_cobra(benchmark::State& state) {
  const tgl::CartesianTrajectory trajectory(cartesianWaypoints(), kCartesianLimits, 5);
  const auto times = sampleTimes(trajectory.duration());
  KDL::Frame pose;
  KDL::Twist twist;
  std::size_t i = 0;
  for (auto _ : state) {
    trajectory.evaluate(times[i++ % kTimes], 0, pose, twist);
    benchmark::DoNotOptimize(pose);
    benchmark::DoNotOptimize(twist);
  }
  state.SetItemsProcessed(state.iterations());
  state.counters["duration_s"] = trajectory.duration();
}

void BM_CartesianEval_kdl(benchmark::State& state) {
  const auto trajectory = kdlCartesian(cartesianWaypoints());
  const auto times = sampleTimes(trajectory->Duration());
  std::size_t i = 0;
  for (auto _ : state) {
    const double t = times[i++ % kTimes];
    KDL::Frame pose = trajectory->Pos(t);
    KDL::Twist twist = trajectory->Vel(t);
    benchmark::DoNotOptimize(pose);
    benchmark::DoNotOptimize(twist);
  }
  state.SetItemsProcessed(state.iterations());
  state.counters["duration_s"] = trajectory->Duration();
}

BENCHMARK(BM_CartesianEval_cobra)->Name("BM_CartesianEval/cobra_cartesian_10_waypoints")->Apply(configure);
BENCHMARK(BM_CartesianEval_kdl)->Name("BM_CartesianEval/kdl_rounded_composite_trap_10_waypoints")->Apply(configure);

// ---------------------------------------------------------------------------------------------
// Construction

void BM_Construct_multi_axis(benchmark::State& state) {
  const tgl::MultiAxisPath path = multiAxisPath();
  for (auto _ : state) {
    tgl::MultiAxisTrajectory trajectory(path, kAxisLimits, 5);
    benchmark::DoNotOptimize(trajectory.duration());
  }
}

void BM_Construct_cartesian_cobra(benchmark::State& state) {
  const auto frames = cartesianWaypoints();
  for (auto _ : state) {
    tgl::CartesianTrajectory trajectory(frames, kCartesianLimits, 5);
    benchmark::DoNotOptimize(trajectory.duration());
  }
}

void BM_Construct_cartesian_kdl(benchmark::State& state) {
  const auto frames = cartesianWaypoints();
  for (auto _ : state) {
    const auto trajectory = kdlCartesian(frames);
    benchmark::DoNotOptimize(trajectory->Duration());
  }
}

BENCHMARK(BM_Construct_multi_axis)->Name("BM_Construct/cobra_multi_axis_12_axes_10_waypoints")->Apply(configure);
BENCHMARK(BM_Construct_cartesian_cobra)->Name("BM_Construct/cobra_cartesian_10_waypoints")->Apply(configure);
BENCHMARK(BM_Construct_cartesian_kdl)->Name("BM_Construct/kdl_rounded_composite_trap_10_waypoints")->Apply(configure);

}  // namespace

BENCHMARK_MAIN();
