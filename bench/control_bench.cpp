// Cost of one 6-D admittance step (issue 6: target <= 2 us, so 10 kHz is possible): cobra's
// tank-based variable admittance (full 6x6 matrices, backward Euler with an LLT solve, SO(3)
// output, energy audit) against the obvious peer, a fixed diagonal admittance integrated with
// semi-implicit Euler and no tank, in the same run. 10 repetitions; median and max.

#include <benchmark/benchmark.h>

#include <algorithm>
#include <vector>

#include "cobra/control/variable_admittance.hpp"

namespace {

using namespace cobra::control;

double maxOf(const std::vector<double>& v) { return *std::max_element(v.begin(), v.end()); }
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
    a.step(reference, KDL::Twist::Zero(), KDL::Wrench(KDL::Vector(f, -f, 0.5), KDL::Vector(0.01, 0, -0.02)), 1e-3, pose, twist);
    benchmark::DoNotOptimize(pose);
  }
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
BENCHMARK_MAIN();
