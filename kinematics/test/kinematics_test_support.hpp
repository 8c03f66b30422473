#pragma once
// Helpers shared by the kinematics tests: joint arrays from lists, random joints in limits, and
// the property checks of the closed-form solvers (UR5, Puma 260): random joints in limits -> FK ->
// all inverse solutions -> KDL's FK of each matches the pose, each labelled with its own branch;
// KDL's LMA lands on one of them.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <random>
#include <span>

#include <kdl/chainfksolverpos_recursive.hpp>

#include "cobra/kinematics/geometry.hpp"
#include "cobra/kinematics/kinematics_solver.hpp"
#include "cobra/kinematics/serial_chain.hpp"

namespace cobra::kinematics::test {

/// A joint array holding `values` (rad / m).
inline KDL::JntArray joints(std::initializer_list<double> values) {
  KDL::JntArray q(static_cast<unsigned>(values.size()));
  unsigned i = 0;
  for (const double v : values) q(i++) = v;
  return q;
}

/// `n` joints, all `value`: the marker the tests use to see that an output was left untouched.
inline KDL::JntArray filled(unsigned n, double value) {
  KDL::JntArray q(n);
  for (unsigned i = 0; i < n; ++i) q(i) = value;
  return q;
}

/// True when every joint of `q` still equals `value` (the output was left untouched).
inline bool isFilled(const KDL::JntArray& q, double value) {
  for (unsigned i = 0; i < q.rows(); ++i) {
    if (q(i) != value) return false;
  }
  return true;
}

inline KDL::JntArray toJnt(std::span<const double> values) {
  KDL::JntArray q(static_cast<unsigned>(values.size()));
  for (unsigned i = 0; i < q.rows(); ++i) q(i) = values[i];
  return q;
}

/// Uniform in [lower + margin, upper - margin] per joint, clipped to ±`range` (rad).
inline KDL::JntArray randomJoints(const JointLimits& limits, std::mt19937& rng, double range, double margin = 0.0) {
  KDL::JntArray q(static_cast<unsigned>(limits.size()));
  for (unsigned i = 0; i < q.rows(); ++i) {
    std::uniform_real_distribution<double> value(std::max(limits.lower[i] + margin, -range),
                                                 std::min(limits.upper[i] - margin, range));
    q(i) = value(rng);
  }
  return q;
}

/// Largest joint difference, each taken modulo 2π (rad).
inline double jointDistanceModulo2Pi(const KDL::JntArray& a, std::span<const double> b) {
  double worst = 0.0;
  for (unsigned i = 0; i < a.rows(); ++i) worst = std::max(worst, std::abs(wrapToPi(a(i) - b[i])));
  return worst;
}

struct RoundTripCounts {
  int poses = 0;
  int with_eight = 0;
};

/// `count` seeded random configurations within the limits (and ±`range`): every solution of
/// allInverse reproduces the pose within `tolerance` (m, rad) through KDL's recursive FK on `chain`
/// and carries the branch `solver.branch` computes from its joints (all distinct),
/// one of them is the original configuration (mod 2π), inverse seeded with the original returns
/// it, and inverse from a seed up to 0.05 rad away returns a configuration reaching the pose and at
/// least as near to the seed as the original.
inline RoundTripCounts checkAnalyticRoundTrips(AnalyticSolver& solver, const KDL::Chain& chain, int count,
                                               unsigned seed, double range, double tolerance = 1e-9) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> noise(-0.05, 0.05);
  KDL::ChainFkSolverPos_recursive kdl(chain);
  IkSolutionSet solutions;
  RoundTripCounts counts;
  for (int i = 0; i < count; ++i) {
    const KDL::JntArray q = randomJoints(solver.limits(), rng, range, 1e-3);
    KDL::Frame target;
    EXPECT_EQ(solver.forward(q, target), IkStatus::Ok);
    EXPECT_EQ(solver.allInverse(target, q, solutions), IkStatus::Ok) << "pose " << i;
    if (solutions.empty()) continue;
    ++counts.poses;
    if (solutions.size() == 8) ++counts.with_eight;
    double nearest = 1e9;
    for (std::size_t s = 0; s < solutions.size(); ++s) {
      KDL::Frame reached;
      EXPECT_GE(kdl.JntToCart(toJnt(solutions[s]), reached), 0);
      EXPECT_LT(norm(reached.p - target.p), tolerance) << "pose " << i << " solution " << s;
      EXPECT_LT(orientationError(reached.M, target.M), tolerance) << "pose " << i << " solution " << s;
      nearest = std::min(nearest, jointDistanceModulo2Pi(q, solutions[s]));
      // The label allInverse gives a solution is the branch the solver computes from its joints,
      // and no two solutions share a branch.
      const IkBranch label = solutions.branch(s);
      const IkBranch computed = solver.branch(solutions[s]);
      EXPECT_EQ(label.bits & ~label.ambiguous, computed.bits & ~label.ambiguous) << "pose " << i << " solution " << s;
      for (std::size_t other = 0; other < s; ++other)
        EXPECT_FALSE(label.ambiguous == 0 && label == solutions.branch(other)) << "pose " << i << " solution " << s;
    }
    EXPECT_LT(nearest, 1e-7) << "pose " << i << ": the original configuration is not among the solutions";

    KDL::JntArray out(solver.jointCount());
    EXPECT_EQ(solver.inverse(target, q, out), IkStatus::Ok);
    for (unsigned j = 0; j < q.rows(); ++j) EXPECT_NEAR(out(j), q(j), 1e-7) << "pose " << i << " joint " << j + 1;

    KDL::JntArray near_seed = q;
    for (unsigned j = 0; j < q.rows(); ++j) near_seed(j) += noise(rng);
    if (solver.inverse(target, near_seed, out) != IkStatus::Ok) {
      ADD_FAILURE() << "pose " << i << ": no solution from a seed near a valid configuration";
      continue;
    }
    KDL::Frame reached;
    solver.forward(out, reached);
    EXPECT_LT(norm(reached.p - target.p), tolerance) << "pose " << i;
    EXPECT_LE((out.data - near_seed.data).norm(), (q.data - near_seed.data).norm() + 1e-7) << "pose " << i;
  }
  return counts;
}

/// `count` seeded random poses: KDL's LMA on the solver's own DH chain, seeded up to 0.1 rad from
/// the configuration, converges (when it does) to one of the analytic solutions (mod 2π, 1e-6 rad).
/// Returns how many poses LMA solved.
inline int checkLmaLandsOnAnalyticSolution(DhAnalyticSolver& solver, int count, unsigned seed, double margin) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> noise(-0.1, 0.1);
  SerialChainSolver lma(solver.model(), {.method = IterativeIk::LevenbergMarquardt});
  IkSolutionSet solutions;
  int compared = 0;
  for (int i = 0; i < count; ++i) {
    const KDL::JntArray q = randomJoints(solver.limits(), rng, 3.14159, margin);
    KDL::Frame target;
    solver.forward(q, target);
    KDL::JntArray start = q;
    for (unsigned j = 0; j < start.rows(); ++j) start(j) += noise(rng);
    KDL::JntArray by_kdl(solver.jointCount());
    if (lma.inverse(target, start, by_kdl) != IkStatus::Ok) continue;
    ++compared;
    EXPECT_EQ(solver.allInverse(target, start, solutions), IkStatus::Ok);
    double nearest = 1e9;
    for (std::size_t s = 0; s < solutions.size(); ++s)
      nearest = std::min(nearest, jointDistanceModulo2Pi(by_kdl, solutions[s]));
    EXPECT_LT(nearest, 1e-6) << "pose " << i;
  }
  return compared;
}

}  // namespace cobra::kinematics::test
