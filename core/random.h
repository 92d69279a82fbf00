#ifndef FITBASE_CORE_RANDOM_H_
#define FITBASE_CORE_RANDOM_H_

#include <cstdint>
#include <random>
#include <span>

namespace fitbase::core {

// One step of Vigna's SplitMix64: a bijective 64-bit mix whose outputs look independent even
// for consecutive inputs, which is what seeding many streams from small integers needs.
uint64_t SplitMix64(uint64_t x);

// A seeded generator whose draws are reproducible across compilers and standard libraries.
// The engine is std::mt19937_64, whose output sequence the C++ standard fixes bit for bit;
// the std::*_distribution classes are implementation-defined, so every transform is ours.
// Uniform draws are therefore bit-exact everywhere; draws that go through std::log / std::sqrt
// are as reproducible as the platform's libm (bit-exact across glibc builds).
class Random {
 public:
  // Streams with different (seed, stream) pairs are statistically independent, so callers can
  // give every item its own stream and draw items in any order or in parallel.
  Random(uint64_t seed, uint64_t stream);

  // Uniform in [0, 1) with the full 53-bit resolution of a double.
  double Uniform01();

  // Uniform in [lo, hi]: hi itself comes only from rounding the top few values of Uniform01().
  double Uniform(double lo, double hi);

  // Normal by Marsaglia's polar method. Each call consumes whole pairs and drops the spare
  // value, so a draw never depends on what an earlier call left behind.
  double Normal(double mean, double sd);

  // Normal(mean, sd) conditioned on [lo, hi], by rejection. After kMaxTruncatedNormalTries
  // rejections the last draw is clamped into [lo, hi]; that only happens when the interval
  // holds a negligible share of the mass, where it puts that share on the bounds instead of
  // looping without limit. Requires sd > 0 and lo <= hi.
  double TruncatedNormal(double mean, double sd, double lo, double hi);

  // Exponential with rate 1, strictly positive and finite.
  double Exponential();

  // Fills `shares` with a draw from the flat Dirichlet(1, ..., 1), i.e. uniform on the simplex:
  // non-negative values summing to 1 up to rounding. `shares` must not be empty.
  void FlatDirichlet(std::span<double> shares);

  static constexpr int kMaxTruncatedNormalTries = 100;

 private:
  std::mt19937_64 engine_;
};

}  // namespace fitbase::core

#endif  // FITBASE_CORE_RANDOM_H_
