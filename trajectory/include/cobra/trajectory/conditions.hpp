#pragma once
/// @file
/// Boundary conditions of a one-axis motion (the thesis' TGL `Conditions`, §3.2.3) and the state an
/// evaluation writes. Units: an axis is unit-agnostic; positions are in the axis' unit (m for a
/// prismatic or Cartesian axis, rad for a revolute one), velocities in that unit per s,
/// accelerations per s^2 and jerks per s^3. Times are in s everywhere in cobra::trajectory.

namespace cobra::trajectory {

/// Position and its first three time derivatives at one instant (units: see the file comment).
/// Also the output of every evaluation: the caller owns it, evaluation only writes it.
struct State {
  double position = 0.0;
  double velocity = 0.0;
  double acceleration = 0.0;
  double jerk = 0.0;
};

/// Initial and final constraints of a motion. The positions are mandatory; velocity, acceleration
/// and jerk default to zero (rest). Which of them a trajectory honours depends on its order (see
/// Polynomial). Every value must be finite: the constructors throw std::invalid_argument otherwise.
class Conditions {
 public:
  /// Rest to rest from `initial_position` to `final_position`.
  Conditions(double initial_position, double final_position);
  /// Full boundary states; throws std::invalid_argument naming the first non-finite value.
  Conditions(const State& initial, const State& final);

  const State& initial() const noexcept { return initial_; }
  const State& final() const noexcept { return final_; }

 private:
  State initial_;
  State final_;
};

}  // namespace cobra::trajectory
