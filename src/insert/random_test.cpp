// Tests for Random: published SplitMix64 outputs, xoshiro256** outputs derived by hand from its
// definition, moments of uniform and normal variates, exact continuation from a saved state.
#include "insert/random.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace quarry {

TEST(Random, SplitMix64MatchesReferenceOutputs) {
  // Reference outputs of Vigna's splitmix64.c for seed 1234567 (as listed on Rosetta Code,
  // "Pseudo-random numbers/Splitmix64").
  std::uint64_t state = 1234567;
  EXPECT_EQ(splitmix64_next(state), 6457827717110365317ull);
  EXPECT_EQ(splitmix64_next(state), 3203168211198807973ull);
  EXPECT_EQ(splitmix64_next(state), 9817491932198370423ull);
  EXPECT_EQ(splitmix64_next(state), 4593380528125082431ull);
  EXPECT_EQ(splitmix64_next(state), 16408922859458223821ull);
}

TEST(Random, Xoshiro256StarStarFollowsItsDefinition) {
  // From state {1, 2, 3, 4}, by hand from Blackman & Vigna (2021), output = rotl(s1·5, 7)·9:
  // 1st: rotl(10, 7)·9 = 1280·9 = 11520; the update makes s1 = 0, so the 2nd output is 0;
  // next s1 = 262149, so the 3rd is rotl(1310745, 7)·9 = 167775360·9 = 1509978240.
  Random random(0);
  random.set_state({1, 2, 3, 4});
  EXPECT_EQ(random.next_u64(), 11520ull);
  EXPECT_EQ(random.next_u64(), 0ull);
  EXPECT_EQ(random.next_u64(), 1509978240ull);
}

TEST(Random, UniformHasTheMomentsOfU01) {
  // U(0,1): mean 1/2, variance 1/12, fourth central moment 1/80. Tolerance 4 standard errors:
  // σ/√n for the mean, √((μ₄ − σ⁴)/n) for the variance.
  Random random(42);
  const int n = 400000;
  double sum = 0.0, sum_sq = 0.0;
  for (int i = 0; i < n; ++i) {
    const double u = random.uniform();
    ASSERT_GE(u, 0.0);
    ASSERT_LT(u, 1.0);
    sum += u;
    sum_sq += u * u;
  }
  const double mean = sum / n;
  const double variance = sum_sq / n - mean * mean;
  EXPECT_NEAR(mean, 0.5, 4.0 * std::sqrt(1.0 / 12.0 / n));
  EXPECT_NEAR(variance, 1.0 / 12.0, 4.0 * std::sqrt((1.0 / 80.0 - 1.0 / 144.0) / n));
}

TEST(Random, NormalHasTheMomentsAndTailsOfTheStandardNormal) {
  // N(0,1): mean 0, variance 1 (μ₄ = 3, so SE √(2/n)), P(|z| > 2) = erfc(2/√2) = 0.0455.
  Random random(7);
  const int n = 400000;
  double sum = 0.0, sum_sq = 0.0;
  int beyond_two = 0;
  for (int i = 0; i < n; ++i) {
    const double z = random.normal();
    sum += z;
    sum_sq += z * z;
    if (std::abs(z) > 2.0) ++beyond_two;
  }
  const double mean = sum / n;
  EXPECT_NEAR(mean, 0.0, 4.0 / std::sqrt(n));
  EXPECT_NEAR(sum_sq / n - mean * mean, 1.0, 4.0 * std::sqrt(2.0 / n));
  const double tail = std::erfc(2.0 / std::sqrt(2.0));
  EXPECT_NEAR(static_cast<double>(beyond_two) / n, tail, 4.0 * std::sqrt(tail * (1.0 - tail) / n));
}

TEST(Random, SavedStateContinuesBitExactly) {
  Random random(99);
  for (int i = 0; i < 17; ++i) random.normal();
  const Random::State saved = random.state();
  std::vector<double> first;
  for (int i = 0; i < 50; ++i) first.push_back(i % 2 ? random.uniform() : random.normal());
  Random restored(12345);
  restored.set_state(saved);
  for (int i = 0; i < 50; ++i) EXPECT_EQ(i % 2 ? restored.uniform() : restored.normal(), first[i]);
}

TEST(Random, SeedsDetermineTheSequence) {
  Random a(5), b(5), c(6);
  bool any_difference = false;
  for (int i = 0; i < 100; ++i) {
    const std::uint64_t x = a.next_u64();
    EXPECT_EQ(x, b.next_u64());
    any_difference |= x != c.next_u64();
  }
  EXPECT_TRUE(any_difference);
  EXPECT_THROW(a.set_state({0, 0, 0, 0}), std::invalid_argument);
}

}  // namespace quarry
