#pragma once
// Shared by the planning tests: independent re-walks of a solved path, densely through the
// validator, and with the continuity-keeping IK (what the control path does when it follows the
// path).

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <span>
#include <utility>
#include <vector>

#include "cobra/planning/motion_planner.hpp"

namespace cobra::planning {

/// Linear position, rotation about the fixed axis of R0^-1 R1 (the geodesic OMPL's slerp follows).
inline KDL::Frame interpolate(const KDL::Frame& a, const KDL::Frame& b, double s) {
  KDL::Vector axis;
  const double angle = (a.M.Inverse() * b.M).GetRotAngle(axis);
  return KDL::Frame(angle > 0.0 ? a.M * KDL::Rotation::Rot2(axis, s * angle) : a.M, a.p + (b.p - a.p) * s);
}

/// Every segment of a solved path valid at 100 points (KDL interpolation, independent of OMPL's),
/// checked in order from the first waypoint (the IK warm-starts from the previous point).
inline void expectDenselyValid(StateValidator& validator, const PlanResult& result) {
  ASSERT_GE(result.waypoints.size(), 2u);
  constexpr int kPointsPerSegment = 100;
  for (std::size_t i = 0; i + 1 < result.waypoints.size(); ++i) {
    for (int k = 0; k <= kPointsPerSegment; ++k) {
      const double t = k / double(kPointsPerSegment);
      const DualPose& a = result.waypoints[i];
      const DualPose& b = result.waypoints[i + 1];
      const DualPose q{interpolate(a.first, b.first, t), interpolate(a.second, b.second, t)};
      const ValidityResult check = validator.check(q, true);
      ASSERT_TRUE(check.valid()) << "segment " << i << " t=" << t << ": " << describe(check);
    }
  }
}

/// An independent re-walk of a solved path at 3x the planner's verification density: every
/// state valid and every joint step of the continuity-keeping IK within the velocity limits at
/// the generator's speeds (the planner's own rule, checked at other points). `worst_step`, when
/// given, receives the largest joint step of the re-walk as a share of its velocity limit's step.
inline void expectFollowable(StateValidator& validator, const PlannerOptions& o, const PlanResult& result,
                             const JointState& start, double* worst_step = nullptr) {
  ASSERT_TRUE(result.solved()) << result.message;
  ASSERT_EQ(result.joint_waypoints.size(), result.waypoints.size());
  std::vector<double> velocity(validator.jointCount()), lower(validator.jointCount()), upper(validator.jointCount());
  for (std::size_t r = 0; r < validator.scene().robots.size(); ++r) {
    const std::size_t n = validator.model(r).jointCount(), at = validator.jointOffset(r);
    validator.model(r).jointLimits(std::span(lower).subspan(at, n), std::span(upper).subspan(at, n),
                                   std::span(velocity).subspan(at, n));
  }
  JointState q = start, next(q.size());
  constexpr int kSteps = 300;
  for (std::size_t k = 0; k + 1 < result.waypoints.size(); ++k) {
    const DualPose& a = result.waypoints[k];
    const DualPose& b = result.waypoints[k + 1];
    double duration = o.blend_time;
    for (const auto& [from, to] : {std::pair{&a.first, &b.first}, std::pair{&a.second, &b.second}}) {
      for (int i = 0; i < 3; ++i) duration = std::max(duration, std::abs(to->p(i) - from->p(i)) / o.max_linear_velocity);
      KDL::Vector axis;
      duration = std::max(duration, (from->M.Inverse() * to->M).GetRotAngle(axis) / o.max_angular_velocity);
    }
    for (int i = 1; i <= kSteps; ++i) {
      const double s = static_cast<double>(i) / kSteps;
      std::size_t robot = 0;
      ASSERT_EQ(validator.inverseNear({interpolate(a.first, b.first, s), interpolate(a.second, b.second, s)}, q, next,
                                      robot),
                Reachability::Reachable)
          << "segment " << k << " at " << s;
      for (std::size_t j = 0; j < q.size(); ++j) {
        const double allowed = velocity[j] * duration / kSteps;
        ASSERT_LE(std::abs(next[j] - q[j]), allowed * 1.05) << "joint " << j << " of segment " << k << " at " << s;
        if (worst_step != nullptr) *worst_step = std::max(*worst_step, std::abs(next[j] - q[j]) / allowed);
      }
      q = next;
      ASSERT_TRUE(validator.checkJoints(q).valid()) << describe(validator.checkJoints(q, true));
    }
    for (std::size_t j = 0; j < q.size(); ++j) EXPECT_NEAR(q[j], result.joint_waypoints[k + 1][j], 1e-6);
  }
}

}  // namespace cobra::planning
