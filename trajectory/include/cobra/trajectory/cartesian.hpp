#pragma once
/// @file
/// Synchronised Cartesian paths of KDL::Frame waypoints for one or more arms, the trajectory behind
/// the thesis' Multi-Arm Cartesian Trajectory Generator (§4.5.2): `Frame` set-points plus `Twist`
/// feed-forward. Positions go through MultiAxisTrajectory component by component; orientation is
/// interpolated on SO(3), never per matrix element, with the same timing law.

#include <cstddef>
#include <span>
#include <vector>

#include <kdl/frames.hpp>

#include "cobra/trajectory/multi_axis.hpp"
#include "cobra/trajectory/polynomial.hpp"

namespace cobra::trajectory {

/// Limits of a Cartesian path, the same for every arm (the thesis' `max_vel` and `time_acc`).
struct CartesianLimits {
  /// Maximum velocity of each of x, y and z of an arm's origin (m/s, > 0). The bound is per
  /// component, as for any MultiAxisTrajectory axis: the origin's speed reaches at most sqrt(3) times it.
  double max_linear_velocity = 0.1;
  /// Maximum angular speed about each segment's rotation axis (rad/s, > 0).
  double max_angular_velocity = 0.5;
  /// Duration of each blend of the position components (s, > 0).
  double linear_acceleration_time = 0.2;
  /// Duration of each blend of the orientation (s, > 0).
  double angular_acceleration_time = 0.2;
};

/// One or more arms moving through Frame waypoints, all reaching each waypoint at the same time.
///
/// Each arm contributes four axes to one MultiAxisTrajectory: x, y, z (m) and the cumulative rotation
/// angle s (rad) along the chain of geodesics R_k -> R_k+1 (angle theta_k <= pi about axis u_k, from
/// KDL's GetRotAngle of R_k^-1 R_k+1). The slowest axis of all arms sets each segment's duration.
/// Orientation at time t:
///  - on a segment's linear part and in the first and last blends: R_k Rot(u_k, s(t) - s_k), the
///    geodesic, with the angle following s(t) exactly;
///  - in the blend around an inner waypoint k: Exp(r(t)) R_k with r(t) = a_in sdot_in (t - t_k) +
///    (a_out sdot_out - a_in sdot_in) beta(t - t_k + T_a / 2), where a_in, a_out are the incoming and
///    outgoing world-frame rotation axes, sdot their angular speeds and beta the unit blend of the
///    same order that s(t) uses. This rounds the corner on SO(3) as positions round theirs, with
///    orientation and angular velocity continuous (angular acceleration too for orders 4 and 5).
/// The twist is the velocity of the origin and the angular velocity, both in the base frame (KDL's
/// convention). Model/Data split: immutable; evaluation writes caller-owned frames and twists,
/// never allocates or throws, O(arms * log segments). Outside [0, duration()] it holds the first
/// or last waypoint at zero twist.
class CartesianTrajectory {
 public:
  /// `waypoints[k][arm]` is the pose of `arm` at waypoint k (positions in m). Throws
  /// std::invalid_argument for fewer than 2 waypoints, a waypoint whose arm count differs from
  /// waypoint 0's, a non-finite or non-orthonormal frame, a limit <= 0 or a blend order outside 2..5.
  CartesianTrajectory(const std::vector<std::vector<KDL::Frame>>& waypoints, const CartesianLimits& limits,
                      int blend_order = 5);
  /// One arm.
  CartesianTrajectory(const std::vector<KDL::Frame>& waypoints, const CartesianLimits& limits, int blend_order = 5);

  std::size_t armCount() const noexcept { return arms_.size(); }
  double duration() const noexcept { return axes_.duration(); }
  /// The shared waypoint times t_k (s); see MultiAxisTrajectory::waypointTimes.
  std::span<const double> waypointTimes() const noexcept { return axes_.waypointTimes(); }
  /// The underlying synchronised axes: 4 per arm, x, y, z, s.
  const MultiAxisTrajectory& axes() const noexcept { return axes_; }

  /// Pose and twist of every arm at `t` s. Contract: both spans hold armCount() entries; shorter
  /// spans get the first arms only. Real-time safe.
  void evaluate(double t, std::span<KDL::Frame> poses, std::span<KDL::Twist> twists) const noexcept;
  /// Arm `arm` only (arm < armCount(), unchecked).
  void evaluate(double t, std::size_t arm, KDL::Frame& pose, KDL::Twist& twist) const noexcept;
  /// Arm `arm` with its acceleration too: `acceleration.vel` is the origin's linear acceleration
  /// (m/s^2), `acceleration.rot` the angular acceleration (rad/s^2), both in the base frame (KDL's
  /// convention for accelerations, as in KDL::FrameAcc). Feed-forward and the start state of a
  /// CartesianStop. Real-time safe.
  void evaluate(double t, std::size_t arm, KDL::Frame& pose, KDL::Twist& twist, KDL::Twist& acceleration) const noexcept;

 private:
  struct Geodesic {           // segment k of one arm's orientation
    KDL::Rotation start;      // R_k
    KDL::Vector axis;         // u_k, unit, in R_k's frame
    KDL::Vector world_axis;   // R_k u_k
    double start_angle;       // s_k (rad)
    double angle;             // theta_k (rad, 0..pi)
    double angular_speed;     // sdot on the linear part (rad/s)
  };
  using Arm = std::vector<Geodesic>;

  /// Fills `arms` with each arm's geodesics and returns the x, y, z, s path of all arms.
  static MultiAxisPath geodesics(const std::vector<std::vector<KDL::Frame>>& waypoints, std::vector<Arm>& arms);
  /// Checks the input, fills `arms` and returns the x, y, z, s axes of all arms on one time line.
  static MultiAxisTrajectory synchronisedAxes(const std::vector<std::vector<KDL::Frame>>& waypoints,
                                              const CartesianLimits& limits, int blend_order, std::vector<Arm>& arms);

  KDL::Rotation orientation(const Arm& arm, double t, const State& s, KDL::Vector& angular_velocity,
                            KDL::Vector& angular_acceleration) const noexcept;

  std::vector<Arm> arms_;     // declared before axes_: synchronisedAxes fills it while axes_ is built
  MultiAxisTrajectory axes_;
  double angular_acceleration_time_;
  Polynomial unit_blend_;  // beta: from rest to unit speed in T_a, covering T_a / 2
};

}  // namespace cobra::trajectory
