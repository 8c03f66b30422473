#pragma once
/// @file
/// One-axis trajectories of the thesis' TGL (§3.2.3): the `Trajectory` base, a piecewise
/// polynomial in time, and `PolynomialTrajectory`, one polynomial of order 1 to 7 meeting the given
/// `Conditions` over a duration. Model/Data split: a trajectory is immutable after construction;
/// evaluation writes into a caller-owned `State`, never allocates, never throws and costs
/// O(log segments).

#include <cstddef>
#include <span>
#include <vector>

#include "cobra/trajectory/conditions.hpp"
#include "cobra/trajectory/polynomial.hpp"

namespace cobra::trajectory {

/// A polynomial piece of a trajectory: `polynomial` runs from `start_time` s for its duration.
struct Segment {
  double start_time = 0.0;
  Polynomial polynomial;
};

/// Base of every one-axis trajectory: contiguous polynomial segments covering [0, duration()].
///
/// Evaluation outside [0, duration()] clamps: before 0 it holds the initial position, after
/// duration() the final position, both with zero velocity, acceleration and jerk (the axis is at
/// rest before it starts and after it ends, even when the conditions asked for a final velocity).
/// A NaN time evaluates as a time before the start.
class Trajectory {
 public:
  virtual ~Trajectory() = default;
  Trajectory(const Trajectory&) = default;
  Trajectory(Trajectory&&) noexcept = default;
  Trajectory& operator=(const Trajectory&) = default;
  Trajectory& operator=(Trajectory&&) noexcept = default;

  /// Total duration in s.
  double duration() const noexcept { return duration_; }
  /// The segments in time order, for inspection and tests.
  std::span<const Segment> segments() const noexcept { return segments_; }

  /// Position and derivatives at `t` s from the start, clamped as the class comment says.
  /// Real-time safe: noexcept, allocation-free, binary search over the segments.
  void evaluate(double t, State& out) const noexcept;
  State at(double t) const noexcept {
    State s;
    evaluate(t, s);
    return s;
  }

 protected:
  /// `segments` must be non-empty and contiguous (each starts where the previous ends, the first
  /// at 0); derived classes guarantee it, so this is not re-checked.
  explicit Trajectory(std::vector<Segment> segments);

 private:
  std::vector<Segment> segments_;
  std::vector<double> start_times_;  // segments_[i].start_time, contiguous for a cache-friendly search
  double duration_ = 0.0;
};

/// One polynomial of `order` 1..7 meeting `conditions` over `duration` s (thesis default: 1 s).
/// See Polynomial for which conditions each order meets. Throws std::invalid_argument for an order
/// out of range or a duration that is not finite and > 0.
class PolynomialTrajectory : public Trajectory {
 public:
  PolynomialTrajectory(int order, const Conditions& conditions, double duration = 1.0);
  /// Wraps an already solved polynomial (e.g. Polynomial::stop).
  explicit PolynomialTrajectory(const Polynomial& polynomial);

  const Polynomial& polynomial() const noexcept { return segments().front().polynomial; }
};

/// The stop motion of the thesis' trajectory generator (askStopMove, §4.5.2): from `current`
/// (position, velocity, acceleration) to rest in exactly `stop_time` s; see Polynomial::stop.
PolynomialTrajectory stopTrajectory(const State& current, double stop_time);

}  // namespace cobra::trajectory
