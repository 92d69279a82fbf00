#include "core/random.h"

#include <array>
#include <cmath>
#include <vector>

#include "gtest/gtest.h"

namespace fitbase::core {
namespace {

constexpr int kDraws = 100000;

TEST(SplitMix64Test, MatchesReferenceImplementation) {
  // First output of Vigna's splitmix64.c with state 0.
  EXPECT_EQ(SplitMix64(0), 0xe220a8397b1dcdafULL);
}

TEST(RandomTest, GoldenFirstUniform) {
  // Pins the engine, the seeding and the 53-bit transform: a change here changes every
  // population ever sampled.
  Random random(42, 0);
  EXPECT_EQ(random.Uniform01(), 0x1.7185a0e03fbfbp-1);
}

TEST(RandomTest, SameSeedAndStreamGiveSameSequence) {
  Random a(7, 3);
  Random b(7, 3);
  for (int i = 0; i < 1000; ++i) {
    ASSERT_EQ(a.Uniform01(), b.Uniform01());
    ASSERT_EQ(a.Normal(0.0, 1.0), b.Normal(0.0, 1.0));
    ASSERT_EQ(a.Exponential(), b.Exponential());
  }
}

TEST(RandomTest, DifferentSeedsOrStreamsDiffer) {
  const double base = Random(7, 3).Uniform01();
  EXPECT_NE(Random(8, 3).Uniform01(), base);
  EXPECT_NE(Random(7, 4).Uniform01(), base);
  // Swapping seed and stream must not alias.
  EXPECT_NE(Random(1, 0).Uniform01(), Random(0, 1).Uniform01());
}

TEST(RandomTest, Uniform01IsInHalfOpenUnitIntervalWithMeanOneHalf) {
  Random random(1, 0);
  double sum = 0.0;
  for (int i = 0; i < kDraws; ++i) {
    const double u = random.Uniform01();
    ASSERT_GE(u, 0.0);
    ASSERT_LT(u, 1.0);
    sum += u;
  }
  // Standard error 0.29 / sqrt(1e5) ~ 0.0009.
  EXPECT_NEAR(sum / kDraws, 0.5, 0.005);
}

TEST(RandomTest, UniformStaysInRange) {
  Random random(2, 0);
  for (int i = 0; i < kDraws; ++i) {
    const double x = random.Uniform(25.0, 70.0);
    ASSERT_GE(x, 25.0);
    ASSERT_LE(x, 70.0);
  }
}

TEST(RandomTest, NormalHasRequestedMeanAndSd) {
  Random random(3, 0);
  double sum = 0.0;
  double sum_sq = 0.0;
  for (int i = 0; i < kDraws; ++i) {
    const double x = random.Normal(2.0, 0.5);
    ASSERT_TRUE(std::isfinite(x));
    sum += x;
    sum_sq += x * x;
  }
  const double mean = sum / kDraws;
  const double sd = std::sqrt(sum_sq / kDraws - mean * mean);
  // Standard errors: 0.5 / sqrt(1e5) ~ 0.0016 for the mean, ~0.0011 for the sd.
  EXPECT_NEAR(mean, 2.0, 0.01);
  EXPECT_NEAR(sd, 0.5, 0.01);
}

TEST(RandomTest, TruncatedNormalStaysInBounds) {
  Random random(4, 0);
  for (int i = 0; i < kDraws; ++i) {
    const double x = random.TruncatedNormal(0.05, 0.05, 0.0, 0.25);
    ASSERT_GE(x, 0.0);
    ASSERT_LE(x, 0.25);
  }
}

TEST(RandomTest, TruncatedNormalClampsWhenIntervalHoldsNoMass) {
  Random random(5, 0);
  EXPECT_EQ(random.TruncatedNormal(0.0, 1.0, 50.0, 51.0), 50.0);
  EXPECT_EQ(random.TruncatedNormal(0.0, 1.0, -51.0, -50.0), -50.0);
}

TEST(RandomTest, ExponentialIsPositiveWithMeanOne) {
  Random random(6, 0);
  double sum = 0.0;
  for (int i = 0; i < kDraws; ++i) {
    const double x = random.Exponential();
    ASSERT_GT(x, 0.0);
    ASSERT_TRUE(std::isfinite(x));
    sum += x;
  }
  // Standard error 1 / sqrt(1e5) ~ 0.003.
  EXPECT_NEAR(sum / kDraws, 1.0, 0.015);
}

TEST(RandomTest, FlatDirichletSumsToOneWithEqualMeans) {
  Random random(7, 0);
  std::array<double, 3> sums = {0.0, 0.0, 0.0};
  for (int i = 0; i < kDraws; ++i) {
    std::array<double, 3> shares;
    random.FlatDirichlet(shares);
    double total = 0.0;
    for (double share : shares) {
      ASSERT_GE(share, 0.0);
      total += share;
    }
    ASSERT_NEAR(total, 1.0, 1e-12);
    for (int k = 0; k < 3; ++k) sums[k] += shares[k];
  }
  // Each share is Beta(1, 2): mean 1/3, sd 0.236, standard error ~0.0007.
  for (double sum : sums) EXPECT_NEAR(sum / kDraws, 1.0 / 3.0, 0.005);
}

}  // namespace
}  // namespace fitbase::core
