#pragma once
/// @file
/// Seeded standard normal samples for the simulated sensors' noise, fast enough to draw a few per
/// sensor axis every control period: xoshiro256++ (Blackman and Vigna, 2018) for the bits and the
/// ziggurat method (Marsaglia and Tsang, 2000; 256 layers, one 64-bit draw per sample in ~99 % of
/// cases) for the shape. The standard library's normal_distribution costs a logarithm, a square
/// root and two 64-bit Mersenne twister draws per pair of samples, which made the F/T sensors'
/// noise a visible share of a whole simulated procedure.

#include <array>
#include <cstdint>

namespace cobra::sim {

/// A reproducible N(0, 1) generator: the same seed gives the same sequence on every platform
/// (integer arithmetic and IEEE double operations only; the tail uses std::log and std::exp).
/// `sample` is noexcept, allocation-free and lock-free (the layer tables are built once, at the
/// first construction).
class GaussianNoise {
 public:
  explicit GaussianNoise(std::uint64_t seed = 0) noexcept;

  /// Restarts the sequence from `seed` (any value, 0 included).
  void seed(std::uint64_t seed) noexcept;

  /// One standard normal sample (mean 0, standard deviation 1).
  double sample() noexcept;

  /// One uniform sample in [0, 1) with 53 random bits.
  double uniform() noexcept;

  /// The next 64 random bits of xoshiro256++.
  std::uint64_t bits() noexcept;

 private:
  std::array<std::uint64_t, 4> state_{};
  const double* layer_x_;  // the ziggurat's 257 layer edges and densities (shared, built once)
  const double* layer_f_;
};

}  // namespace cobra::sim
