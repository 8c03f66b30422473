// Unit tests of isur_continuity.hpp and of the branch-keeping split IK of the two-armed I-SUR
// (IsurSuturingSolver::branch / inverseOnBranch): seeded random targets near a configuration are
// solved on its branch within the velocity bound and reproduce the configuration the forward
// kinematics started from; targets across the Endo Stitch's wrist singularity, needing the
// gripper arm's wrist flip, or beyond max_velocity · dt are refused; bad input, construction
// errors, no allocation.

#include "cobra/kinematics/isur_continuity.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "cobra/kinematics/geometry.hpp"
#include "cobra/test_support/counting_new.hpp"
#include "cobra/test_support/test_support.hpp"
#include "kinematics_test_support.hpp"

namespace cobra::kinematics {
namespace {

using cobra::test_support::allocationsDuring;
using cobra::test_support::messageOf;
using test::filled;
using test::isFilled;

constexpr unsigned kJoints = IsurSuturingSolver::kJoints;
constexpr double kPi = std::numbers::pi;
constexpr double kDt = 0.01;  // s

/// The simulated I-SUR's limits: 0.1 m/s on the sliders, 1.5 rad/s on the revolute joints.
std::vector<double> velocities() {
  std::vector<double> v(kJoints, 1.5);
  v[0] = v[1] = v[2] = 0.1;
  return v;
}

/// A random configuration within the limits (0.1 rad / 0.1 of the slider stroke inside) on the
/// solver's redundancy rule (base q4 = base_angle 0, elbow q6 - q7 = pitch_difference) and at
/// least 0.05 from every singular set (Endo Stitch vertical, gripper arm's wrist aligned, elbow
/// stretched); false when the draw is not such a configuration (the caller draws again).
bool randomOnRule(IsurSuturingSolver& solver, std::mt19937& rng, KDL::JntArray& q) {
  const JointLimits& limits = solver.limits();
  for (unsigned j = 0; j < kJoints; ++j) {
    const double margin = 0.1 * std::min(1.0, limits.upper[j] - limits.lower[j]);
    q(j) = std::uniform_real_distribution<double>(limits.lower[j] + margin, limits.upper[j] - margin)(rng);
  }
  const IsurGeometry geometry;
  const double pitch = q(5) + q(6);
  q(3) = geometry.base_angle;
  q(5) = 0.5 * (pitch + geometry.pitch_difference);
  q(6) = 0.5 * (pitch - geometry.pitch_difference);
  if (!limits.contains(q)) return false;
  KDL::Frame stitch, gripper;
  if (solver.forward(q, stitch, gripper) != IkStatus::Ok) return false;
  return std::abs(std::cos(pitch)) > 0.05 && std::abs(std::sin(q(12))) > 0.05 && std::abs(std::cos(q(10))) > 0.05;
}

double poseError(const KDL::Frame& a, const KDL::Frame& b) {
  return std::max(norm(a.p - b.p), orientationError(a.M, b.M));
}

// 1000 seeded random configurations on the rule, each with a target from a neighbour on the rule
// at most half the velocity bound away per joint: the continuity-ruled split IK solves it on the
// configuration's branch, within the bound, and gives back the neighbour (forward vs inverse).
TEST(ContinuousIsurSuturingIk, TargetsNearAConfigurationAreSolvedOnItsBranchWithinTheBound) {
  IsurSuturingSolver solver;
  ContinuousIsurSuturingIk ik(solver, velocities(), kDt);
  std::mt19937 rng(1717);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const std::vector<double> v = velocities();
  KDL::JntArray q(kJoints), neighbour(kJoints), out(kJoints);
  int trials = 0, solved = 0;
  while (trials < 1000) {
    if (!randomOnRule(solver, rng, q)) continue;
    neighbour = q;
    for (unsigned j = 0; j < kJoints; ++j) neighbour(j) += unit(rng) * 0.5 * v[j] * kDt;
    neighbour(3) = q(3);                              // the base stays on base_angle
    neighbour(6) = neighbour(5) - (q(5) - q(6));      // the elbow on pitch_difference
    if (!solver.limits().contains(neighbour)) continue;
    // A neighbour across a singular boundary (the gripper arm's shoulder: its wrist centre on the
    // first axis) is on another branch: the rule refuses it, rightly (tested below).
    const std::span<const double> from(q.data.data(), kJoints), to(neighbour.data.data(), kJoints);
    if (solver.branch(to) != solver.branch(from)) continue;
    KDL::Frame stitch, gripper;
    if (solver.forward(neighbour, stitch, gripper) != IkStatus::Ok) continue;
    ++trials;
    const IkStatus status = ik.solve(stitch, gripper, q, kDt, out);
    if (status != IkStatus::Ok) {
      ADD_FAILURE() << "trial " << trials << ": " << toString(status) << " (joint " << ik.lastRefusal().joint
                    << ", step " << ik.lastRefusal().step << ", allowed " << ik.lastRefusal().allowed << ")";
      continue;
    }
    ++solved;
    const std::span<const double> before(q.data.data(), kJoints), after(out.data.data(), kJoints);
    EXPECT_TRUE(solver.branch(after).compatibleWith(solver.branch(before))) << "trial " << trials;
    for (unsigned j = 0; j < kJoints; ++j) {
      EXPECT_LE(std::abs(out(j) - q(j)), v[j] * kDt + 1e-12) << "trial " << trials << " joint " << j + 1;
      EXPECT_NEAR(out(j), neighbour(j), 1e-7) << "trial " << trials << " joint " << j + 1;
    }
    KDL::Frame stitch_reached, gripper_reached;
    ASSERT_EQ(solver.forward(out, stitch_reached, gripper_reached), IkStatus::Ok);
    EXPECT_LT(poseError(stitch_reached, stitch), 1e-9) << "trial " << trials;
    EXPECT_LT(poseError(gripper_reached, gripper), 1e-9) << "trial " << trials;
  }
  EXPECT_EQ(solved, 1000);
}

// 300 seeded random configurations with the Endo Stitch 0.01 rad short of vertical; the target
// tilts it 0.01 rad past (everything else equal): refused as a branch change or a swing of yaw
// and roll, the output untouched. The same tilt within the branch is accepted.
TEST(ContinuousIsurSuturingIk, TheEndoStitchAcrossItsWristSingularityIsRefused) {
  IsurSuturingSolver solver;
  ContinuousIsurSuturingIk ik(solver, velocities(), kDt);
  std::mt19937 rng(1718);
  KDL::JntArray q(kJoints), across(kJoints);
  int trials = 0;
  while (trials < 300) {
    if (!randomOnRule(solver, rng, q)) continue;
    const double side = q(5) + q(6) > 0.0 ? 1.0 : -1.0;  // towards +90° or -90°
    const double elbow = q(5) - q(6);
    const double pitch = side * (kPi / 2 - 0.01);
    q(5) = 0.5 * (pitch + elbow);
    q(6) = 0.5 * (pitch - elbow);
    across = q;
    across(5) += side * 0.01;
    across(6) += side * 0.01;
    KDL::Frame stitch_start, gripper_start, stitch, gripper;
    if (!solver.limits().contains(across) || solver.forward(q, stitch_start, gripper_start) != IkStatus::Ok ||
        solver.forward(across, stitch, gripper) != IkStatus::Ok)
      continue;
    ++trials;
    KDL::JntArray out = filled(kJoints, 42.0);
    ASSERT_EQ(ik.solve(stitch, gripper_start, q, kDt, out), IkStatus::Discontinuous) << "trial " << trials;
    EXPECT_TRUE(isFilled(out, 42.0));
    // Within the branch: half-way to the vertical is a small step.
    KDL::JntArray closer = q;
    closer(5) += side * 0.002;
    closer(6) += side * 0.002;
    ASSERT_EQ(solver.forward(closer, stitch, gripper), IkStatus::Ok);
    EXPECT_EQ(ik.solve(stitch, gripper_start, q, kDt, out), IkStatus::Ok) << "trial " << trials;
  }
}

// 300 seeded random configurations with the gripper arm's wrist 0.01 rad from alignment (q13);
// the target needs it 0.01 rad on the other side: on the current branch q12 and q14 turn by π.
TEST(ContinuousIsurSuturingIk, AGripperPoseNeedingTheWristFlipIsRefused) {
  IsurSuturingSolver solver;
  ContinuousIsurSuturingIk ik(solver, velocities(), kDt);
  std::mt19937 rng(1719);
  KDL::JntArray q(kJoints), flipped(kJoints);
  int trials = 0, branch_changes = 0;
  while (trials < 300) {
    if (!randomOnRule(solver, rng, q)) continue;
    q(12) = std::copysign(0.01, q(12));
    flipped = q;
    flipped(12) = -q(12);
    KDL::Frame stitch, gripper, stitch_flipped, gripper_flipped;
    if (solver.forward(q, stitch, gripper) != IkStatus::Ok ||
        solver.forward(flipped, stitch_flipped, gripper_flipped) != IkStatus::Ok)
      continue;
    ++trials;
    KDL::JntArray out = filled(kJoints, 42.0);
    ASSERT_EQ(ik.solve(stitch, gripper_flipped, q, kDt, out), IkStatus::Discontinuous) << "trial " << trials;
    EXPECT_TRUE(isFilled(out, 42.0));
    if (ik.lastRefusal().branch_change) {
      ++branch_changes;
    } else {
      EXPECT_TRUE(ik.lastRefusal().joint == 11 || ik.lastRefusal().joint == 13) << "trial " << trials;
    }
  }
  // The wrist's other side exists on the current branch (q12, q14 turned by π) unless a limit
  // forbids it: each trial is refused one way or the other.
  EXPECT_LT(branch_changes, trials);
}

// Each sub-structure keeps its own branch: asking for the gripper arm's other elbow gives the
// other elbow solution of the same poses (when the limits allow it), never the current one.
TEST(IsurSuturingSolver, InverseOnBranchKeepsEachSubStructuresBranch) {
  IsurSuturingSolver solver;
  std::mt19937 rng(1720);
  KDL::JntArray q(kJoints), out(kJoints);
  int trials = 0, other_elbow = 0;
  while (trials < 300) {
    if (!randomOnRule(solver, rng, q)) continue;
    ++trials;
    const std::span<const double> joints(q.data.data(), kJoints);
    const IkBranch branch = solver.branch(joints);
    EXPECT_EQ(branch.bits & 1u, solver.rightStructure().branch(joints.first(8)).bits);
    KDL::Frame stitch, gripper;
    ASSERT_EQ(solver.forward(q, stitch, gripper), IkStatus::Ok);
    IkBranch flipped = branch;
    flipped.bits ^= 1u << (IsurSuturingSolver::kLeftBranchShift + 1);  // the gripper arm's elbow
    const IkStatus status = solver.inverseOnBranch(stitch, gripper, q, flipped, out);
    if (status == IkStatus::JointLimits || status == IkStatus::Discontinuous) continue;
    ASSERT_EQ(status, IkStatus::Ok) << "trial " << trials;
    ++other_elbow;
    const IkBranch reached = solver.branch(std::span<const double>(out.data.data(), kJoints));
    EXPECT_TRUE(reached.compatibleWith(flipped)) << "trial " << trials;
    for (unsigned j = 0; j < 8; ++j) EXPECT_NEAR(out(j), q(j), 1e-9) << "trial " << trials;  // same Endo Stitch
    KDL::Frame stitch_reached, gripper_reached;
    ASSERT_EQ(solver.forward(out, stitch_reached, gripper_reached), IkStatus::Ok);
    EXPECT_LT(poseError(gripper_reached, gripper), 1e-9) << "trial " << trials;
  }
  EXPECT_GT(other_elbow, 30);
}

TEST(ContinuousIsurSuturingIk, AStepBeyondTheBoundNamesTheJoint) {
  IsurSuturingSolver solver;
  ContinuousIsurSuturingIk ik(solver, velocities(), 1e-3);
  KDL::JntArray q = test::joints({0.1, 0.1, 0.1, 0.0, 0.0, 0.75, 0.45, 0.0, 0.0, 0.5, -0.5, 0.0, 0.5, 0.0});
  KDL::JntArray moved = q;
  moved(9) += 0.01;  // 0.01 rad on q10 in 1 ms: 10 rad/s
  KDL::Frame stitch, gripper;
  ASSERT_EQ(solver.forward(moved, stitch, gripper), IkStatus::Ok);
  KDL::JntArray out(kJoints);
  ASSERT_EQ(ik.solve(stitch, gripper, q, out), IkStatus::Discontinuous);
  EXPECT_FALSE(ik.lastRefusal().branch_change);
  EXPECT_EQ(ik.lastRefusal().joint, 9);
  EXPECT_NEAR(ik.lastRefusal().step, 0.01, 1e-9);
  EXPECT_NEAR(ik.lastRefusal().allowed, 1.5e-3, 1e-12);
  ASSERT_EQ(ik.solve(stitch, gripper, q, 0.01, out), IkStatus::Ok);  // in 10 ms it is within 1.5 rad/s
  EXPECT_NEAR(out(9), moved(9), 1e-9);
}

TEST(ContinuousIsurSuturingIk, BadInputAndConstructionErrors) {
  IsurSuturingSolver solver;
  ContinuousIsurSuturingIk ik(solver, velocities(), kDt);
  KDL::JntArray q = test::joints({0.1, 0.1, 0.1, 0.0, 0.0, 0.75, 0.45, 0.0, 0.0, 0.5, -0.5, 0.0, 0.5, 0.0});
  KDL::Frame stitch, gripper;
  ASSERT_EQ(solver.forward(q, stitch, gripper), IkStatus::Ok);
  KDL::JntArray out(kJoints), short_out(8);
  EXPECT_EQ(ik.solve(stitch, gripper, q, 0.0, out), IkStatus::BadInput);
  EXPECT_EQ(ik.solve(stitch, gripper, q, short_out), IkStatus::BadInput);
  EXPECT_EQ(ik.solve(stitch, gripper, KDL::JntArray(8), out), IkStatus::BadInput);
  KDL::Frame far_gripper = gripper;
  far_gripper.p += KDL::Vector(0.0, 0.0, 2.0);
  EXPECT_EQ(ik.solve(stitch, far_gripper, q, out), IkStatus::Unreachable);  // solver failures pass through

  std::vector<double> zero = velocities();
  zero[8] = 0.0;
  EXPECT_EQ(messageOf([&] { ContinuousIsurSuturingIk(solver, zero, kDt); }),
            "I-SUR suturing: max_velocity of joint 9 is 0 rad/s: give a finite value > 0");
  EXPECT_EQ(messageOf([&] { ContinuousIsurSuturingIk(solver, std::vector<double>(8, 1.0), kDt); }),
            "I-SUR suturing: max_velocity has 8 values; the robot has 14 joints: give one limit per joint (rad/s, "
            "m/s)");
  EXPECT_EQ(messageOf([&] { ContinuousIsurSuturingIk(solver, velocities(), -1.0); }),
            "I-SUR suturing: continuity period is -1 s: give a finite value > 0");
}

TEST(ContinuousIsurSuturingIk, SolveAllocatesNothing) {
  IsurSuturingSolver solver;
  ContinuousIsurSuturingIk ik(solver, velocities(), kDt);
  KDL::JntArray q = test::joints({0.1, 0.1, 0.1, 0.0, 0.0, 0.75, 0.45, 0.0, 0.0, 0.5, -0.5, 0.0, 0.5, 0.0});
  KDL::Frame stitch, gripper;
  ASSERT_EQ(solver.forward(q, stitch, gripper), IkStatus::Ok);
  KDL::JntArray out(kJoints);
  int ok = 0;
  EXPECT_EQ(allocationsDuring([&] {
              for (int i = 0; i < 100; ++i) {
                KDL::Frame target = stitch;
                target.p += KDL::Vector(0.0, 0.0, -1e-5 * i);
                ok += ik.solve(target, gripper, q, out) == IkStatus::Ok ? 1 : 0;
                q = out;
              }
            }),
            0);
  EXPECT_EQ(ok, 100);
}

}  // namespace
}  // namespace cobra::kinematics
