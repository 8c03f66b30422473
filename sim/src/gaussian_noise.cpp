#include "cobra/sim/gaussian_noise.hpp"

#include <cmath>

namespace cobra::sim {
namespace {

// The ziggurat of the standard normal density f(x) = exp(-x²/2) (unnormalised) with 256 layers of
// equal area kArea: layer i spans |x| < kX[i] between heights kF[i] and kF[i + 1]. kR is where the
// tail starts; the base layer (i = 0) is the rectangle under f(kR) of width kArea / f(kR) plus the
// tail beyond kR. Constants of Marsaglia and Tsang's 256-layer table.
constexpr int kLayers = 256;
constexpr double kR = 3.6541528853610088;
constexpr double kArea = 0.00492867323399;

double density(double x) { return std::exp(-0.5 * x * x); }

struct Tables {
  std::array<double, kLayers + 1> x{};
  std::array<double, kLayers + 1> f{};
  Tables() {
    x[0] = kArea / density(kR);
    x[1] = kR;
    for (int i = 1; i < kLayers - 1; ++i) x[i + 1] = std::sqrt(-2.0 * std::log(kArea / x[i] + density(x[i])));
    x[kLayers] = 0.0;
    for (int i = 0; i <= kLayers; ++i) f[i] = density(x[i]);
  }
};

const Tables& tables() {
  static const Tables instance;  // built once; thread-safe initialisation
  return instance;
}

std::uint64_t rotl(std::uint64_t v, int k) { return (v << k) | (v >> (64 - k)); }

// splitmix64: spreads any seed (0 included) over xoshiro's 256-bit state, as its authors advise.
std::uint64_t splitmix(std::uint64_t& s) {
  std::uint64_t z = (s += 0x9e3779b97f4a7c15ULL);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

}  // namespace

GaussianNoise::GaussianNoise(std::uint64_t seed) noexcept
    : layer_x_(tables().x.data()), layer_f_(tables().f.data()) {
  this->seed(seed);
}

void GaussianNoise::seed(std::uint64_t seed) noexcept {
  for (auto& word : state_) word = splitmix(seed);
}

std::uint64_t GaussianNoise::bits() noexcept {
  const std::uint64_t result = rotl(state_[0] + state_[3], 23) + state_[0];
  const std::uint64_t t = state_[1] << 17;
  state_[2] ^= state_[0];
  state_[3] ^= state_[1];
  state_[1] ^= state_[2];
  state_[0] ^= state_[3];
  state_[2] ^= t;
  state_[3] = rotl(state_[3], 45);
  return result;
}

double GaussianNoise::uniform() noexcept { return static_cast<double>(bits() >> 11) * 0x1.0p-53; }

double GaussianNoise::sample() noexcept {
  const double* layer_x = layer_x_;
  const double* layer_f = layer_f_;
  for (;;) {
    const std::uint64_t r = bits();
    const int i = static_cast<int>(r & 0xff);
    // A symmetric uniform in (-1, 1) from the 53 high bits (independent of the layer's 8 low bits).
    const double u = 2.0 * ((static_cast<double>(r >> 11) + 0.5) * 0x1.0p-53) - 1.0;
    const double x = u * layer_x[i];
    if (std::abs(x) < layer_x[i + 1]) return x;  // inside the layer's core rectangle: accepted at once
    if (i == 0) {
      // The tail beyond kR (Marsaglia's method: exponential proposals, accepted by -2y >= x²).
      double tail = 0.0;
      double y = 0.0;
      do {
        tail = std::log(1.0 - uniform()) / kR;  // <= 0
        y = std::log(1.0 - uniform());
      } while (-2.0 * y < tail * tail);
      return u < 0.0 ? tail - kR : kR - tail;
    }
    // The wedge between the core rectangle and the density: accept under the curve.
    if (layer_f[i + 1] + (layer_f[i] - layer_f[i + 1]) * uniform() < density(x)) return x;
  }
}

}  // namespace cobra::sim
