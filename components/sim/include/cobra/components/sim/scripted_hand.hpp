#pragma once
/// @file
/// The scripted surgeon's hand on a simulated master (SimulatedOmniPhantom's stylus orientation,
/// SimulatedLeapMotion's hands): it moves toward a target pose as a first-order system, so that a
/// fault script setting a new target (a step) gives the smooth motion a hand makes, not a jump.

#include <algorithm>
#include <cmath>
#include <kdl/frames.hpp>

namespace cobra::components {

/// A hand pose that follows its target: each step covers the share min(1, dt / time_constant) of
/// the remaining translation (m) and of the remaining rotation angle (rad, about the axis of
/// R⁻¹·R_target, the shortest way). noexcept, no allocation.
class ScriptedHand {
 public:
  ScriptedHand() noexcept = default;
  explicit ScriptedHand(const KDL::Frame& start) noexcept : pose_(start) {}

  void reset(const KDL::Frame& start) noexcept { pose_ = start; }

  /// Advances by dt (s; <= 0 changes nothing) toward `target`; `time_constant` (s, > 0).
  void step(const KDL::Frame& target, double dt, double time_constant) noexcept {
    if (!(dt > 0.0)) return;
    const double share = time_constant > 0.0 ? std::min(1.0, dt / time_constant) : 1.0;
    pose_.p += (target.p - pose_.p) * share;
    const KDL::Vector remaining = (pose_.M.Inverse() * target.M).GetRot();  // rad, hand axes
    const double angle = remaining.Norm();
    if (angle > 1e-12) pose_.M = pose_.M * KDL::Rotation::Rot2(remaining / angle, share * angle);
  }

  const KDL::Frame& pose() const noexcept { return pose_; }

 private:
  KDL::Frame pose_;
};

/// The angular velocity (rad/s, the frames' reference axes) that turns `before` into `after` in dt
/// (s, > 0).
inline KDL::Vector angularVelocity(const KDL::Rotation& before, const KDL::Rotation& after, double dt) noexcept {
  return dt > 0.0 ? (after * before.Inverse()).GetRot() / dt : KDL::Vector::Zero();
}

}  // namespace cobra::components
