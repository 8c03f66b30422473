// GaussianNoise: the ziggurat's samples follow N(0, 1) (moments, tail shares, a Kolmogorov-Smirnov
// distance against the normal CDF), the uniform is uniform, a seed reproduces its sequence and
// different seeds differ, and sampling allocates nothing.

#include "cobra/sim/gaussian_noise.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "cobra/test_support/counting_new.hpp"

namespace {

using cobra::sim::GaussianNoise;

double normalCdf(double x) { return 0.5 * std::erfc(-x / std::sqrt(2.0)); }

// 400,000 samples from each of 3 seeds: moments within ~5 standard errors, the shares beyond 1, 2,
// 3 and 4 sigma within 5 standard errors of the binomial, and the KS distance below the 1e-3
// critical value (1.95 / sqrt(n)).
TEST(GaussianNoise, SamplesFollowTheStandardNormal) {
  constexpr int kSamples = 400000;
  for (const std::uint64_t seed : {0ULL, 1ULL, 0x5eedULL}) {
    GaussianNoise noise(seed);
    std::vector<double> x(kSamples);
    for (double& v : x) v = noise.sample();
    double mean = 0.0;
    for (const double v : x) mean += v;
    mean /= kSamples;
    double m2 = 0.0, m3 = 0.0, m4 = 0.0;
    for (const double v : x) {
      const double d = v - mean;
      m2 += d * d;
      m3 += d * d * d;
      m4 += d * d * d * d;
    }
    m2 /= kSamples;
    m3 /= kSamples;
    m4 /= kSamples;
    const double n = kSamples;
    EXPECT_NEAR(mean, 0.0, 5.0 / std::sqrt(n)) << "seed " << seed;
    EXPECT_NEAR(m2, 1.0, 5.0 * std::sqrt(2.0 / n)) << "seed " << seed;
    EXPECT_NEAR(m3, 0.0, 5.0 * std::sqrt(15.0 / n)) << "seed " << seed;
    EXPECT_NEAR(m4, 3.0, 5.0 * std::sqrt(96.0 / n)) << "seed " << seed;
    for (const double k : {1.0, 2.0, 3.0, 4.0}) {
      const double p = 2.0 * (1.0 - normalCdf(k));
      const double share = static_cast<double>(std::count_if(x.begin(), x.end(), [k](double v) {
                             return std::abs(v) > k;
                           })) / n;
      EXPECT_NEAR(share, p, 5.0 * std::sqrt(p * (1.0 - p) / n) + 1.0 / n) << "beyond " << k << " sigma, seed " << seed;
    }
    std::sort(x.begin(), x.end());
    double ks = 0.0;
    for (int i = 0; i < kSamples; ++i) {
      const double c = normalCdf(x[static_cast<std::size_t>(i)]);
      ks = std::max({ks, std::abs(c - i / n), std::abs((i + 1) / n - c)});
    }
    EXPECT_LT(ks, 1.95 / std::sqrt(n)) << "seed " << seed;
    EXPECT_GT(x.back(), 3.6) << "the tail beyond the ziggurat's base (3.654) is reached, seed " << seed;
  }
}

TEST(GaussianNoise, UniformIsUniformOnTheUnitInterval) {
  GaussianNoise noise(7);
  constexpr int kBins = 20, kSamples = 200000;
  std::vector<int> bins(kBins, 0);
  for (int i = 0; i < kSamples; ++i) {
    const double u = noise.uniform();
    ASSERT_GE(u, 0.0);
    ASSERT_LT(u, 1.0);
    ++bins[static_cast<std::size_t>(u * kBins)];
  }
  double chi2 = 0.0;
  const double expected = static_cast<double>(kSamples) / kBins;
  for (const int b : bins) chi2 += (b - expected) * (b - expected) / expected;
  EXPECT_LT(chi2, 43.8) << "chi-square with 19 degrees of freedom above its 0.1 % critical value";
}

TEST(GaussianNoise, ASeedReproducesItsSequence) {
  GaussianNoise a(42), b(42), c(43);
  bool differs = false;
  for (int i = 0; i < 1000; ++i) {
    const double va = a.sample();
    EXPECT_EQ(va, b.sample());
    differs = differs || va != c.sample();
  }
  EXPECT_TRUE(differs);
  a.seed(42);
  GaussianNoise fresh(42);
  for (int i = 0; i < 100; ++i) EXPECT_EQ(a.sample(), fresh.sample());
}

TEST(GaussianNoise, SamplingAllocatesNothing) {
  GaussianNoise noise(3);
  double sum = 0.0;
  EXPECT_EQ(cobra::test_support::allocationsDuring([&] {
              for (int i = 0; i < 10000; ++i) sum += noise.sample();
            }),
            0);
  EXPECT_TRUE(std::isfinite(sum));
}

}  // namespace
