// Cost of one 6-D admittance step (target <= 2 us, so 10 kHz is possible): cobra's
// tank-based variable admittance (full 6x6 matrices, backward Euler with an LLT solve, SO(3)
// output, energy audit) against the obvious peer, a fixed diagonal admittance integrated with
// semi-implicit Euler and no tank, in the same run. 10 repetitions; median and max.
// ScheduledStepLatency times every single step (steady_clock, ~20 ns of its own) of a run with an
// aggressive random schedule of Λd and Kd against a stiff wall, so the tank-empty path (a second
// solve with the constant parts) is exercised; p50/p99/max of each run are counters. Its max_ns is
// wall time: on a loaded machine without SCHED_FIFO it shows preemptions, not the controller.

#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cstddef>
#include <random>
#include <vector>

#include "cobra/control/variable_admittance.hpp"
#include "median_and_worst.hpp"

namespace {

using namespace cobra::control;

using cobra::bench::maxOf;
void configure(benchmark::internal::Benchmark* b) {
  b->Repetitions(10)->ReportAggregatesOnly(true)->ComputeStatistics("max", maxOf)->MinTime(0.05);
}

Matrix6 diagonal(double translation, double rotation) {
  Vector6 d;
  d << translation, translation, translation, rotation, rotation, rotation;
  return d.asDiagonal();
}

void TankVariableAdmittance(benchmark::State& state) {
  AdmittanceParameters p;
  p.constant_inertia = diagonal(1.0, 0.05);
  p.constant_stiffness = diagonal(100.0, 2.0);
  p.inertia = diagonal(3.0, 0.1);
  p.stiffness = diagonal(500.0, 10.0);
  p.damping = diagonal(40.0, 1.0);
  VariableAdmittance a(p);
  KDL::Frame pose;
  KDL::Twist twist;
  const KDL::Frame reference(KDL::Rotation::RPY(0.1, 0.2, 0.3), KDL::Vector(0.3, 0.1, 0.2));
  int i = 0;
  for (auto _ : state) {
    const double f = (++i % 100) * 0.05;
    const KDL::Wrench wrench(KDL::Vector(f, -f, 0.5), KDL::Vector(0.01, 0, -0.02));
    a.step(reference, KDL::Twist::Zero(), wrench, 1e-3, pose, twist);
    benchmark::DoNotOptimize(pose);
  }
}

void ScheduledStepLatency(benchmark::State& state) {
  using Clock = std::chrono::steady_clock;
  AdmittanceParameters p;
  p.constant_inertia = diagonal(1.0, 0.05);
  p.constant_stiffness = diagonal(100.0, 2.0);
  p.stiffness = diagonal(500.0, 10.0);
  p.damping = diagonal(20.0, 1.0);
  VariableAdmittance a(p);
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> stiffness(100.0, 20000.0), inertia(1.0, 100.0);
  std::vector<double> step_ns(20000);
  KDL::Frame pose = KDL::Frame::Identity();
  KDL::Twist twist;
  for (auto _ : state) {
    a.reset();
    for (std::size_t i = 0; i < step_ns.size(); ++i) {
      if (i % 10 == 0)
        a.setParameters(diagonal(inertia(rng), 0.05), diagonal(20.0, 1.0), diagonal(stiffness(rng), 2.0));
      const double x = pose.p.x();
      const double f = (x > 0.004 ? -3000.0 * (x - 0.004) : 0.0) + (i % 2000 < 50 ? 15.0 : 0.0);  // wall + push, N
      const auto start = Clock::now();
      a.step(KDL::Frame::Identity(), KDL::Twist::Zero(), KDL::Wrench(KDL::Vector(f, 0, 0), KDL::Vector::Zero()), 1e-3,
             pose, twist);
      step_ns[i] = std::chrono::duration<double, std::nano>(Clock::now() - start).count();
    }
  }
  std::sort(step_ns.begin(), step_ns.end());
  state.counters["p50_ns"] = step_ns[step_ns.size() / 2];
  state.counters["p99_ns"] = step_ns[step_ns.size() * 99 / 100];
  state.counters["max_ns"] = step_ns.back();
}

/// The peer: m a + d v + k x = F per axis, semi-implicit Euler, no tank, no SO(3).
void PlainDiagonalAdmittance(benchmark::State& state) {
  double x[6] = {}, v[6] = {};
  const double m = 3.0, d = 40.0, k = 500.0, dt = 1e-3;
  int i = 0;
  for (auto _ : state) {
    const double f = (++i % 100) * 0.05;
    const double force[6] = {f, -f, 0.5, 0.01, 0.0, -0.02};
    for (int j = 0; j < 6; ++j) {
      v[j] += dt * (force[j] - d * v[j] - k * x[j]) / m;
      x[j] += dt * v[j];
    }
    benchmark::DoNotOptimize(x);
  }
}

}  // namespace

BENCHMARK(TankVariableAdmittance)->Apply(configure);
BENCHMARK(PlainDiagonalAdmittance)->Apply(configure);
BENCHMARK(ScheduledStepLatency)
    ->Repetitions(10)
    ->ReportAggregatesOnly(true)
    ->ComputeStatistics("max", maxOf)
    ->Iterations(1);
BENCHMARK_MAIN();
