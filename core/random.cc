#include "core/random.h"

#include <algorithm>
#include <cmath>

namespace fitbase::core {
namespace {

constexpr double kTwoPowMinus52 = 0x1.0p-52;
constexpr double kTwoPowMinus53 = 0x1.0p-53;

}  // namespace

uint64_t SplitMix64(uint64_t x) {
  uint64_t z = x + 0x9e3779b97f4a7c15ULL;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

// Mixing the seed before adding the stream keeps neighbouring (seed, stream) pairs such as
// (1, 0) and (0, 1) from landing on the same engine seed.
Random::Random(uint64_t seed, uint64_t stream) : engine_(SplitMix64(SplitMix64(seed) + stream)) {}

double Random::Uniform01() { return static_cast<double>(engine_() >> 11) * kTwoPowMinus53; }

// Products that meet a sum go through an explicit std::fma: compilers otherwise fuse
// a * b + c on FMA hardware or not depending on target and flags (GCC does by default), which
// changes the last bit between builds. An explicit fma rounds once everywhere.
double Random::Uniform(double lo, double hi) { return std::fma(hi - lo, Uniform01(), lo); }

double Random::Normal(double mean, double sd) {
  double u;
  double v;
  double s;
  do {
    u = 2.0 * Uniform01() - 1.0;
    v = 2.0 * Uniform01() - 1.0;
    s = std::fma(u, u, v * v);
  } while (s >= 1.0 || s == 0.0);
  return std::fma(sd, u * std::sqrt(-2.0 * std::log(s) / s), mean);
}

double Random::TruncatedNormal(double mean, double sd, double lo, double hi) {
  double x = mean;
  for (int i = 0; i < kMaxTruncatedNormalTries; ++i) {
    x = Normal(mean, sd);
    if (x >= lo && x <= hi) return x;
  }
  return std::clamp(x, lo, hi);
}

double Random::Exponential() {
  // The midpoint of one of 2^52 equal cells lies strictly inside (0, 1) and is exact in a
  // double (with 2^53 cells the top midpoint would round to 1), so the result is finite and
  // never 0, which keeps Dirichlet normalization away from 0 / 0.
  const double u = (static_cast<double>(engine_() >> 12) + 0.5) * kTwoPowMinus52;
  return -std::log(u);
}

void Random::FlatDirichlet(std::span<double> shares) {
  double sum = 0.0;
  for (double& share : shares) {
    share = Exponential();
    sum += share;
  }
  for (double& share : shares) share /= sum;
}

}  // namespace fitbase::core
