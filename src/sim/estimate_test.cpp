// The split of a calibration's particle stages into a part per step and a part per particle
// (sim/estimate.h, particle_stage_fit): least squares on synthetic timings.
#include "sim/estimate.h"

#include <gtest/gtest.h>

#include <vector>

namespace quarry::sim {
namespace {

// t = a + b n exactly, n growing from 0 to 99 (a pour beginning): the fit returns a.
TEST(EstimateFit, RecoversTheFixedPartOfAGrowingCount) {
  const double a = 4.8e-5, b = 2.5e-7;  // s per step, s per particle-step
  std::vector<double> counts, seconds;
  for (int k = 0; k < 400; ++k) {
    counts.push_back(k / 4);
    // ±1 us of alternating timer noise, which least squares averages out.
    seconds.push_back(a + b * (k / 4) + (k % 2 == 0 ? 1e-6 : -1e-6));
  }
  EXPECT_NEAR(particle_stage_fit(counts, seconds), a, 2e-7);
}

// Where the count hardly moves (a filled drum), a fixed part cannot be told from a per-particle
// one: no split. Too few steps, a negative slope or intercept (noise): none either.
TEST(EstimateFit, NoSplitWithoutASpreadOfCountsOrWithAnUnphysicalFit) {
  std::vector<double> counts(100, 2000.0), seconds(100, 1e-3);
  for (int k = 0; k < 100; ++k) counts[k] += k % 3;
  EXPECT_EQ(particle_stage_fit(counts, seconds), 0.0);
  EXPECT_EQ(particle_stage_fit({1, 50, 100}, {1e-5, 2e-5, 3e-5}), 0.0);  // 3 steps
  std::vector<double> n, falling, negative;
  for (int k = 0; k < 100; ++k) {
    n.push_back(k);
    falling.push_back(1e-3 - 1e-6 * k);  // slower with fewer particles: noise, not a cost
    negative.push_back(-1e-5 + 1e-6 * k);
  }
  EXPECT_EQ(particle_stage_fit(n, falling), 0.0);
  EXPECT_EQ(particle_stage_fit(n, negative), 0.0);
}

}  // namespace
}  // namespace quarry::sim
