#pragma once
/// @file
/// One polynomial of order 1 to 7 over [0, T] meeting boundary conditions: the building block of
/// every TGL trajectory (thesis §3.2.3, eq. 3.6: q(t) = a0 + a1 t + ... + an t^n).

#include <array>

#include "cobra/trajectory/conditions.hpp"

namespace cobra::trajectory {

/// q(t) = a0 + a1 t + ... + an t^n for t in [0, duration], with n + 1 coefficients chosen so that
/// the boundary conditions below hold. A fixed-size value: copying or building one never allocates.
///
/// Which conditions an order meets (initial side first, the extra one of even orders is initial):
/// | order | initial (t = 0)       | final (t = T)       |
/// | 1     | position              | position            |
/// | 2     | position, velocity    | position            |
/// | 3     | position, velocity    | position, velocity  |
/// | 4     | pos, vel, acc         | position, velocity  |
/// | 5     | pos, vel, acc         | pos, vel, acc       |
/// | 6     | pos, vel, acc, jerk   | pos, vel, acc       |
/// | 7     | pos, vel, acc, jerk   | pos, vel, acc, jerk |
/// Conditions beyond the order are ignored. Internally the coefficients are held in normalised time
/// tau = t / T, where the boundary system is well conditioned for any T.
class Polynomial {
 public:
  static constexpr int kMinOrder = 1;
  static constexpr int kMaxOrder = 7;

  /// Solves the boundary conditions of `order` over `duration` (s). Throws std::invalid_argument
  /// when the order is outside 1..7 or the duration is not finite and > 0.
  Polynomial(int order, const Conditions& conditions, double duration);

  /// A motion from `current` (position, velocity, acceleration; jerk ignored) to rest (zero
  /// velocity and acceleration) in exactly `stop_time` s: the quintic whose velocity is the cubic
  /// Hermite curve from (v0, a0) to (0, 0), so the rest position is not chosen but follows,
  /// q_rest = q0 + T (v0 / 2 + a0 T / 12). Allocation-free, so a generator may build it inside its
  /// real-time update from the state it is sending. Throws std::invalid_argument for a non-finite
  /// state or a stop time that is not finite and > 0 (check the stop time at configuration).
  static Polynomial stop(const State& current, double stop_time);

  int order() const noexcept { return order_; }
  /// Duration T in s.
  double duration() const noexcept { return duration_; }

  /// The thesis' coefficients a_i of eq. 3.6 in physical time (a_i in axis unit / s^i); entries
  /// above order() are zero.
  std::array<double, kMaxOrder + 1> coefficients() const noexcept;

  /// Value and derivatives at `t` s from the start. Real-time safe; `t` is not clamped, so the
  /// polynomial extrapolates outside [0, T] (trajectories clamp before calling this).
  void evaluate(double t, State& out) const noexcept;
  State at(double t) const noexcept {
    State s;
    evaluate(t, s);
    return s;
  }

 private:
  int order_ = 1;
  double duration_ = 1.0;
  double inverse_duration_ = 1.0;
  std::array<double, kMaxOrder + 1> normalised_{};  // coefficients c_i of tau^i, tau = t / T
};

}  // namespace cobra::trajectory
