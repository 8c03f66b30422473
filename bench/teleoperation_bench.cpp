// Cost of one step of the two-layer teleoperation (Transparency compute + Passivity step, both
// sides) on SE(3) against the translation-only step in the same run: the same layers with the
// rotational gains 0 (rotation uncoupled: no rotation error, no rest rotation), the path a 3-DoF
// master such as the Phantom Omni takes. Each call takes the next of 4096 seeded random
// master/slave pose and twist pairs (master within 2 cm and 0.1 rad of the slave), at 1 kHz time
// steps after an engage with a 3 cm, 0.3 rad offset, so the rest lengths are shrinking over the
// first 2 s and zero after. TeleoperationPerSideStep: the step as deployed, one Passivity layer
// per side (PassivitySide: the master's and the slave's, each paying with its robot's twist, and
// each taking the other's packet), on SE(3). 10 repetitions; median and max ("max": the worst
// repetition's mean).

#include <benchmark/benchmark.h>

#include <random>
#include <vector>

#include "cobra/control/teleoperation.hpp"
#include "median_and_worst.hpp"

namespace {

using namespace cobra::control;

using cobra::bench::maxOf;
void configure(benchmark::internal::Benchmark* b) {
  b->Repetitions(10)->ReportAggregatesOnly(true)->ComputeStatistics("max", maxOf)->MinTime(0.05);
}

struct Sample {
  KDL::Frame master, slave;
  Vector6 master_twist, slave_twist;
};

std::vector<Sample> workload() {
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  auto vector = [&](double scale) { return KDL::Vector(scale * unit(rng), scale * unit(rng), scale * unit(rng)); };
  auto twist = [&] { return (Vector6() << 0.1 * unit(rng), 0.1 * unit(rng), 0.1 * unit(rng), unit(rng), unit(rng), unit(rng)).finished(); };
  std::vector<Sample> samples(4096);
  for (Sample& s : samples) {
    const KDL::Vector r = vector(0.1);
    s.slave = KDL::Frame(KDL::Rotation::RPY(unit(rng), unit(rng), unit(rng)), vector(0.2));
    s.master = KDL::Frame(KDL::Rotation::Rot(r, r.Norm()) * s.slave.M, s.slave.p + vector(0.02));
    s.master_twist = twist();
    s.slave_twist = twist();
  }
  return samples;
}

void run(benchmark::State& state, double rotational_stiffness, double rotational_damping) {
  TransparencyParameters coupling;
  coupling.rotational_stiffness = rotational_stiffness;
  coupling.rotational_damping = rotational_damping;
  TransparencyLayer transparency(coupling);
  PassivityLayer passivity{PassivityParameters{}};
  const std::vector<Sample> samples = workload();
  const KDL::Frame slave = samples[0].slave;
  transparency.engage(0.0, KDL::Frame(slave.M * KDL::Rotation::RotZ(0.3), slave.p + KDL::Vector(0.03, 0, 0)), slave);
  std::size_t i = 0;
  double t = 0.0;
  for (auto _ : state) {
    const Sample& s = samples[i];
    i = (i + 1) % samples.size();
    t += 1e-3;
    Vector6 fm, fs;
    transparency.compute(t, s.master, s.master_twist, s.slave, s.slave_twist, fm, fs);
    const PassivityStep out = passivity.step(1e-3, fm, fs, s.master_twist, s.slave_twist, 0.01, 0.05);
    benchmark::DoNotOptimize(out);
  }
}

/// The deployed step: the Transparency layer (the slave's side) and one PassivitySide per side,
/// each taking the packet the other sent the step before (the link's part is not timed here).
void TeleoperationPerSideStep(benchmark::State& state) {
  TransparencyParameters coupling;
  coupling.rotational_stiffness = 2.0;
  coupling.rotational_damping = 0.1;
  TransparencyLayer transparency(coupling);
  PassivitySide master_side(PassivitySideParameters{}, "master"), slave_side(PassivitySideParameters{}, "slave");
  const std::vector<Sample> samples = workload();
  const KDL::Frame slave = samples[0].slave;
  transparency.engage(0.0, KDL::Frame(slave.M * KDL::Rotation::RotZ(0.3), slave.p + KDL::Vector(0.03, 0, 0)), slave);
  std::size_t i = 0;
  double t = 0.0;
  EnergyPacket to_master, to_slave;
  for (auto _ : state) {
    const Sample& s = samples[i];
    i = (i + 1) % samples.size();
    t += 1e-3;
    master_side.receive(to_master);
    slave_side.receive(to_slave);
    Vector6 fm, fs;
    transparency.compute(t, s.master, s.master_twist, s.slave, s.slave_twist, fm, fs);
    const PassivitySideStep m = master_side.step(1e-3, fm, s.master_twist, 0.01);
    const PassivitySideStep sl = slave_side.step(1e-3, fs, s.slave_twist, 0.05);
    to_slave = m.packet;
    to_master = sl.packet;
    benchmark::DoNotOptimize(m);
    benchmark::DoNotOptimize(sl);
  }
}

void TeleoperationStepSE3(benchmark::State& state) { run(state, 2.0, 0.1); }
void TeleoperationStepTranslationOnly(benchmark::State& state) { run(state, 0.0, 0.0); }

BENCHMARK(TeleoperationStepSE3)->Apply(configure);
BENCHMARK(TeleoperationStepTranslationOnly)->Apply(configure);
BENCHMARK(TeleoperationPerSideStep)->Apply(configure);

}  // namespace

BENCHMARK_MAIN();
