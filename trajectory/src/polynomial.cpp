#include "cobra/trajectory/polynomial.hpp"

#include <Eigen/Dense>

#include "checks.hpp"

namespace cobra::trajectory {

namespace {

constexpr int kMaxConditionsPerSide = 4;  // position, velocity, acceleration, jerk

double derivative(const State& s, int k) {
  switch (k) {
    case 0: return s.position;
    case 1: return s.velocity;
    case 2: return s.acceleration;
    default: return s.jerk;
  }
}

/// i! / (i - d)!: the factor d-th differentiation puts on tau^i (evaluated at tau = 1).
double fallingFactorial(int i, int d) {
  double f = 1.0;
  for (int k = 0; k < d; ++k) f *= static_cast<double>(i - k);
  return f;
}

}  // namespace

Polynomial::Polynomial(int order, const Conditions& conditions, double duration) : order_(order), duration_(duration) {
  if (order < kMinOrder || order > kMaxOrder)
    detail::fail("Polynomial: order ", order, " is out of range, expected ", kMinOrder, " to ", kMaxOrder);
  detail::requirePositive(duration, "s", "Polynomial: duration");
  inverse_duration_ = 1.0 / duration;

  // In tau = t / T the k-th derivative scales by T^k. The initial side fixes the low coefficients in
  // closed form, c_k = T^k q^(k)(0) / k!; the final side leaves a small fixed-size linear system
  // M c_high = rhs whose rows are the derivatives d = 0.. at tau = 1 (a Hermite-type matrix, always
  // invertible). Even orders give their extra condition to the initial side (see the header).
  const int initial_count = (order + 2) / 2;
  const int final_count = (order + 1) / 2;
  double scale = 1.0;  // T^k / k!
  for (int k = 0; k < initial_count; ++k) {
    normalised_[k] = derivative(conditions.initial(), k) * scale;
    scale *= duration / static_cast<double>(k + 1);
  }
  using Matrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxConditionsPerSide, kMaxConditionsPerSide>;
  using Vector = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxConditionsPerSide, 1>;
  Matrix m(final_count, final_count);
  Vector rhs(final_count);
  double t_power = 1.0;  // T^d
  for (int d = 0; d < final_count; ++d) {
    rhs(d) = derivative(conditions.final(), d) * t_power;
    for (int i = d; i < initial_count; ++i) rhs(d) -= fallingFactorial(i, d) * normalised_[i];
    for (int j = 0; j < final_count; ++j) m(d, j) = fallingFactorial(initial_count + j, d);
    t_power *= duration;
  }
  const Vector high = m.partialPivLu().solve(rhs);
  for (int j = 0; j < final_count; ++j) normalised_[initial_count + j] = high(j);
}

Polynomial Polynomial::stop(const State& current, double stop_time) {
  detail::requirePositive(stop_time, "s", "Polynomial::stop: stop time");
  const State start{current.position, current.velocity, current.acceleration, 0.0};
  // Integral over [0, 1] of the cubic Hermite velocity with v(0) = v0, v'(0) = a0 T, v(1) = v'(1) = 0
  // is v0 / 2 + a0 T / 12; the quintic with these six conditions is that quartic exactly.
  const double rest = current.position + stop_time * (current.velocity / 2.0 + current.acceleration * stop_time / 12.0);
  return Polynomial(5, Conditions(start, State{rest}), stop_time);
}

std::array<double, Polynomial::kMaxOrder + 1> Polynomial::coefficients() const noexcept {
  std::array<double, kMaxOrder + 1> a{};
  double scale = 1.0;  // 1 / T^i
  for (int i = 0; i <= order_; ++i) {
    a[i] = normalised_[i] * scale;
    scale *= inverse_duration_;
  }
  return a;
}

void Polynomial::evaluate(double t, State& out) const noexcept {
  // Horner's scheme for the value and the first three derivatives at once: d1 = p', d2 = p'' / 2,
  // d3 = p''' / 6 in tau; the chain rule turns them into time derivatives.
  const double tau = t * inverse_duration_;
  double p = 0.0, d1 = 0.0, d2 = 0.0, d3 = 0.0;
  for (int i = order_; i >= 0; --i) {
    d3 = d3 * tau + d2;
    d2 = d2 * tau + d1;
    d1 = d1 * tau + p;
    p = p * tau + normalised_[i];
  }
  const double r = inverse_duration_;
  out.position = p;
  out.velocity = d1 * r;
  out.acceleration = 2.0 * d2 * r * r;
  out.jerk = 6.0 * d3 * r * r * r;
}

}  // namespace cobra::trajectory
