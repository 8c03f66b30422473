// Cost of the kinematics solvers of cobra::kinematics against KDL's own solvers on the same DH
// chain and the same targets, side by side in the same run (ARCHITECTURE §8).
//
// Every benchmark runs 10 repetitions and reports their median and worst case ("max"); the
// `mean`/`stddev`/`cv` rows come for free. The time column is per call, cycling through 10,000
// targets made from seeded random joint values (seed: the target's joints + up to 0.1 rad noise).
// Groups:
//  - Ur5Fk: closed-form DH product (Ur5Solver::forward) vs KDL::ChainFkSolverPos_recursive.
//  - Ur5Ik: Ur5Solver::inverse (all solutions + nearest to seed), Ur5Solver::allInverse, and
//    KDL's ChainIkSolverPos_NR_JL and ChainIkSolverPos_LMA constructed once with their default
//    tolerances; `solved` = fraction of calls that returned success.
//    `continuous`: ContinuousIk (branch of the seed + velocity check) on the same workload, seeds
//    0.1 rad away and 10 rad/s over 0.02 s. (The closed form before its rewrite, with DH frame
//    products, a libm wrap per joint and std::round/std::ceil in the selection, measured 5.6 us
//    nearest / 4.2 us all eight, CPU median, in the same run as today's 1.73 / 1.30 us.)
//  - Ur5IkCobraKdl: cobra's SerialChainSolver (KDL + exact-residual polish to 1e-9 m / 1e-9 rad).
//  - Puma260Ik: closed form vs KDL LMA on the Puma 260 chain.
//  - LinearDelta: forward (trilateration) and inverse of the I-SUR macro unit (no KDL peer: not a
//    serial chain).
//  - IsurIk: the 8-DOF puncturing decomposition vs KDL's LMA on the equivalent serial chain (delta
//    replaced by three Cartesian joints: what KDL could do if the delta's FK were ignored); and the
//    14-DOF suturing solver (both arms).
//  - LinearDelta: forward and inverse of the I-SUR macro unit; IsurIk: the 8-DOF puncturing solver.

#include <benchmark/benchmark.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <vector>

#include <kdl/chainfksolverpos_recursive.hpp>
#include <kdl/chainiksolverpos_lma.hpp>
#include <kdl/chainiksolverpos_nr_jl.hpp>
#include <kdl/chainiksolvervel_pinv.hpp>

#include "cobra/kinematics/continuity.hpp"
#include "cobra/kinematics/isur.hpp"
#include "cobra/kinematics/linear_delta.hpp"
#include "cobra/kinematics/puma260.hpp"
#include "cobra/kinematics/serial_chain.hpp"
#include "cobra/kinematics/ur5.hpp"
#include "median_and_worst.hpp"

namespace {

using namespace cobra::kinematics;

constexpr int kRepetitions = 10;
constexpr double kMinTimePerRepetition = 0.05;  // s; keeps the whole file well under a minute
constexpr std::size_t kTargets = 10000;

using cobra::bench::maxOf;

/// Median and max over repetitions, aggregates only.
void configure(benchmark::internal::Benchmark* b) {
  b->Repetitions(kRepetitions)
      ->ReportAggregatesOnly(true)
      ->ComputeStatistics("max", maxOf)
      ->MinTime(kMinTimePerRepetition);
}

/// Targets (tool poses), the joints they came from, and seeds near those joints.
struct Workload {
  std::vector<KDL::Frame> targets;
  std::vector<KDL::JntArray> joints;
  std::vector<KDL::JntArray> seeds;
};

Workload makeWorkload(KinematicsSolver& solver, unsigned seed, double margin) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> noise(-0.1, 0.1);
  Workload w;
  const JointLimits& limits = solver.limits();
  while (w.targets.size() < kTargets) {
    KDL::JntArray q(solver.jointCount());
    for (unsigned j = 0; j < q.rows(); ++j) {
      std::uniform_real_distribution<double> value(std::max(limits.lower[j] + margin, -3.0),
                                                   std::min(limits.upper[j] - margin, 3.0));
      q(j) = value(rng);
    }
    KDL::Frame pose;
    if (solver.forward(q, pose) != IkStatus::Ok) continue;
    KDL::JntArray s = q;
    for (unsigned j = 0; j < s.rows(); ++j)
      s(j) =
          std::clamp(s(j) + noise(rng) * (limits.upper[j] - limits.lower[j]) / 6.28, limits.lower[j], limits.upper[j]);
    w.targets.push_back(pose);
    w.joints.push_back(q);
    w.seeds.push_back(s);
  }
  return w;
}

Ur5Solver& ur5() {
  static Ur5Solver solver;
  return solver;
}

const Workload& ur5Workload() {
  static const Workload w = makeWorkload(ur5(), 1, 0.0);
  return w;
}

// ---------------------------------------------------------------------------------------------
// UR5 forward kinematics.

void BM_Ur5Fk_ClosedForm(benchmark::State& state) {
  const Workload& w = ur5Workload();
  KDL::Frame pose;
  std::size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(ur5().forward(w.joints[i], pose));
    benchmark::DoNotOptimize(pose);
    i = (i + 1) % kTargets;
  }
}

void BM_Ur5Fk_KdlRecursive(benchmark::State& state) {
  const Workload& w = ur5Workload();
  KDL::ChainFkSolverPos_recursive fk(ur5().model().chain());
  KDL::Frame pose;
  std::size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(fk.JntToCart(w.joints[i], pose));
    benchmark::DoNotOptimize(pose);
    i = (i + 1) % kTargets;
  }
}

BENCHMARK(BM_Ur5Fk_ClosedForm)->Name("BM_Ur5Fk/closed_form")->Apply(configure);
BENCHMARK(BM_Ur5Fk_KdlRecursive)->Name("BM_Ur5Fk/kdl_recursive")->Apply(configure);

// ---------------------------------------------------------------------------------------------
// UR5 inverse kinematics.

/// Runs `solve(target, seed, out) -> bool` over the workload; reports the fraction solved.
template <class Solve>
void runIk(benchmark::State& state, const Workload& w, unsigned joints, Solve solve) {
  KDL::JntArray out(joints);
  std::size_t i = 0;
  std::int64_t solved = 0;
  for (auto _ : state) {
    solved += solve(w.targets[i], w.seeds[i], out) ? 1 : 0;
    benchmark::DoNotOptimize(out.data.data());
    i = (i + 1) % kTargets;
  }
  state.counters["solved"] =
      static_cast<double>(solved) / static_cast<double>(std::max<std::int64_t>(1, state.iterations()));
}

void BM_Ur5Ik_ClosedForm(benchmark::State& state) {
  runIk(state, ur5Workload(), 6, [](const KDL::Frame& t, const KDL::JntArray& s, KDL::JntArray& out) {
    return ur5().inverse(t, s, out) == IkStatus::Ok;
  });
}

void BM_Ur5Ik_ClosedFormAll(benchmark::State& state) {
  IkSolutionSet solutions;
  runIk(state, ur5Workload(), 6, [&](const KDL::Frame& t, const KDL::JntArray& s, KDL::JntArray&) {
    return ur5().allInverse(t, s, solutions) == IkStatus::Ok;
  });
}

void BM_Ur5Ik_KdlNrJl(benchmark::State& state) {
  const KDL::Chain& chain = ur5().model().chain();
  KDL::JntArray q_min(6);
  KDL::JntArray q_max(6);
  for (unsigned j = 0; j < 6; ++j) {
    q_min(j) = ur5().limits().lower[j];
    q_max(j) = ur5().limits().upper[j];
  }
  KDL::ChainFkSolverPos_recursive fk(chain);
  KDL::ChainIkSolverVel_pinv velocity(chain);
  KDL::ChainIkSolverPos_NR_JL nr(chain, q_min, q_max, fk, velocity);
  runIk(state, ur5Workload(), 6,
        [&](const KDL::Frame& t, const KDL::JntArray& s, KDL::JntArray& out) { return nr.CartToJnt(s, t, out) >= 0; });
}

void BM_Ur5Ik_KdlLma(benchmark::State& state) {
  KDL::ChainIkSolverPos_LMA lma(ur5().model().chain());
  runIk(state, ur5Workload(), 6,
        [&](const KDL::Frame& t, const KDL::JntArray& s, KDL::JntArray& out) { return lma.CartToJnt(s, t, out) >= 0; });
}

template <IterativeIk kMethod>
void BM_Ur5Ik_CobraSerialChain(benchmark::State& state) {
  SerialChainSolver solver(ur5().model(), {.method = kMethod});
  runIk(state, ur5Workload(), 6, [&](const KDL::Frame& t, const KDL::JntArray& s, KDL::JntArray& out) {
    return solver.inverse(t, s, out) == IkStatus::Ok;
  });
}

void BM_Ur5Ik_Continuous(benchmark::State& state) {
  ContinuousIk continuous(ur5(), std::vector<double>(6, 10.0), 0.02);
  runIk(state, ur5Workload(), 6, [&](const KDL::Frame& t, const KDL::JntArray& s, KDL::JntArray& out) {
    return continuous.solve(t, s, out) == IkStatus::Ok;
  });
}

BENCHMARK(BM_Ur5Ik_ClosedForm)->Name("BM_Ur5Ik/closed_form_nearest")->Apply(configure);
BENCHMARK(BM_Ur5Ik_Continuous)->Name("BM_Ur5Ik/continuous")->Apply(configure);
BENCHMARK(BM_Ur5Ik_ClosedFormAll)->Name("BM_Ur5Ik/closed_form_all8")->Apply(configure);
BENCHMARK(BM_Ur5Ik_KdlNrJl)->Name("BM_Ur5Ik/kdl_nr_jl")->Apply(configure);
BENCHMARK(BM_Ur5Ik_KdlLma)->Name("BM_Ur5Ik/kdl_lma")->Apply(configure);
BENCHMARK_TEMPLATE(BM_Ur5Ik_CobraSerialChain, IterativeIk::NewtonRaphsonJL)
    ->Name("BM_Ur5IkCobraKdl/nr_jl_polished")
    ->Apply(configure);
BENCHMARK_TEMPLATE(BM_Ur5Ik_CobraSerialChain, IterativeIk::LevenbergMarquardt)
    ->Name("BM_Ur5IkCobraKdl/lma_polished")
    ->Apply(configure);

// ---------------------------------------------------------------------------------------------
// Puma 260 inverse kinematics.

Puma260Solver& puma() {
  static Puma260Solver solver;
  return solver;
}

const Workload& pumaWorkload() {
  static const Workload w = makeWorkload(puma(), 2, 0.1);
  return w;
}

void BM_Puma260Ik_ClosedForm(benchmark::State& state) {
  runIk(state, pumaWorkload(), 6, [](const KDL::Frame& t, const KDL::JntArray& s, KDL::JntArray& out) {
    return puma().inverse(t, s, out) == IkStatus::Ok;
  });
}

void BM_Puma260Ik_KdlLma(benchmark::State& state) {
  KDL::ChainIkSolverPos_LMA lma(puma().model().chain());
  runIk(state, pumaWorkload(), 6,
        [&](const KDL::Frame& t, const KDL::JntArray& s, KDL::JntArray& out) { return lma.CartToJnt(s, t, out) >= 0; });
}

BENCHMARK(BM_Puma260Ik_ClosedForm)->Name("BM_Puma260Ik/closed_form_nearest")->Apply(configure);
BENCHMARK(BM_Puma260Ik_KdlLma)->Name("BM_Puma260Ik/kdl_lma")->Apply(configure);

// ---------------------------------------------------------------------------------------------
// Linear delta and I-SUR.

LinearDeltaSolver& delta() {
  static LinearDeltaSolver solver;
  return solver;
}

void BM_LinearDelta_Forward(benchmark::State& state) {
  const Workload w = makeWorkload(delta(), 3, 0.0);
  KDL::Frame pose;
  std::size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(delta().forward(w.joints[i], pose));
    benchmark::DoNotOptimize(pose);
    i = (i + 1) % kTargets;
  }
}

void BM_LinearDelta_Inverse(benchmark::State& state) {
  runIk(state, makeWorkload(delta(), 3, 0.0), 3, [](const KDL::Frame& t, const KDL::JntArray& s, KDL::JntArray& out) {
    return delta().inverse(t, s, out) == IkStatus::Ok;
  });
}

BENCHMARK(BM_LinearDelta_Forward)->Name("BM_LinearDelta/forward")->Apply(configure);
BENCHMARK(BM_LinearDelta_Inverse)->Name("BM_LinearDelta/inverse")->Apply(configure);

IsurPuncturingSolver& isur() {
  static IsurPuncturingSolver solver;
  return solver;
}

const Workload& isurWorkload() {
  static const Workload w = makeWorkload(isur(), 4, 0.05);
  return w;
}

void BM_IsurIk_Decomposition(benchmark::State& state) {
  runIk(state, isurWorkload(), 8, [](const KDL::Frame& t, const KDL::JntArray& s, KDL::JntArray& out) {
    return isur().inverse(t, s, out) == IkStatus::Ok;
  });
}

/// KDL peer: the same robot with the delta replaced by Cartesian joints [q4, x, y, z, q5..q8].
void BM_IsurIk_KdlLmaCartesianMacro(benchmark::State& state) {
  const KDL::Chain chain = cartesianMacroChain(isur().geometry().micro);
  KDL::ChainIkSolverPos_LMA lma(chain);
  // Seeds in the chain's coordinates: the delta's platform position instead of the slider travels.
  const Workload& w = isurWorkload();
  Workload cartesian;
  for (std::size_t i = 0; i < kTargets; ++i) {
    KDL::JntArray s(8);
    KDL::Vector p;
    isur().macro().forwardPosition(std::span<const double, 3>(w.seeds[i].data.data(), 3), p);
    s(0) = w.seeds[i](3);
    s(1) = p.x();
    s(2) = p.y();
    s(3) = p.z();
    for (unsigned j = 4; j < 8; ++j) s(j) = w.seeds[i](j);
    cartesian.targets.push_back(w.targets[i]);
    cartesian.seeds.push_back(s);
  }
  runIk(state, cartesian, 8,
        [&](const KDL::Frame& t, const KDL::JntArray& s, KDL::JntArray& out) { return lma.CartToJnt(s, t, out) >= 0; });
}

void BM_IsurSuturingIk(benchmark::State& state) {
  IsurSuturingSolver suturing;
  std::mt19937 rng(5);
  std::vector<KDL::Frame> stitch(kTargets);
  std::vector<KDL::Frame> gripper(kTargets);
  std::vector<KDL::JntArray> seeds;
  for (std::size_t i = 0; i < kTargets; ++i) {
    KDL::JntArray q(14);
    for (unsigned j = 0; j < 14; ++j) {
      const double lo = suturing.limits().lower[j];
      const double hi = suturing.limits().upper[j];
      q(j) = std::uniform_real_distribution<double>(lo + 0.1 * (hi - lo), hi - 0.1 * (hi - lo))(rng);
    }
    suturing.forward(q, stitch[i], gripper[i]);
    seeds.push_back(q);
  }
  KDL::JntArray out(14);
  std::size_t i = 0;
  std::int64_t solved = 0;
  for (auto _ : state) {
    solved += suturing.inverse(stitch[i], gripper[i], seeds[i], out) == IkStatus::Ok ? 1 : 0;
    benchmark::DoNotOptimize(out.data.data());
    i = (i + 1) % kTargets;
  }
  state.counters["solved"] =
      static_cast<double>(solved) / static_cast<double>(std::max<std::int64_t>(1, state.iterations()));
}

BENCHMARK(BM_IsurIk_Decomposition)->Name("BM_IsurIk/puncturing_decomposition")->Apply(configure);
BENCHMARK(BM_IsurIk_KdlLmaCartesianMacro)->Name("BM_IsurIk/kdl_lma_cartesian_macro")->Apply(configure);
BENCHMARK(BM_IsurSuturingIk)->Name("BM_IsurIk/suturing_14dof")->Apply(configure);

}  // namespace

BENCHMARK_MAIN();
