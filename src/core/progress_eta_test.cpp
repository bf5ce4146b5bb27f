// Tests for the smoothed ETA: a steady pace gives the exact time left; a run whose pace jumps
// between intervals (the hopper's progress lines, issue 20) gets an ETA that stays within a
// narrow band, where the last-interval pace swings by the full ratio of the two paces.
#include "core/progress_eta.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace quarry {

TEST(ProgressEta, SteadyPaceGivesTheExactTimeLeft) {
  ProgressEta eta;
  EXPECT_TRUE(std::isnan(eta.seconds_left(1.0)));
  for (int k = 0; k < 10; ++k) eta.add(0.01, 2.0);  // 0.005 simulated s per wall s
  EXPECT_NEAR(eta.pace(), 0.005, 1e-15);
  EXPECT_NEAR(eta.seconds_left(1.0), 200.0, 1e-9);
  EXPECT_EQ(eta.seconds_left(0.0), 0.0);
}

TEST(ProgressEta, AlternatingPaceNoLongerJumps) {
  // Progress lines every 2 s of wall time; every other interval holds a frame write and
  // advances the simulation 18x less (the ratio of 1.5 h to 5 min). Remaining: 1 simulated s.
  ProgressEta eta;
  double lo = 1e300, hi = 0.0, raw_lo = 1e300, raw_hi = 0.0;
  for (int k = 0; k < 60; ++k) {
    const double simulated = (k % 2 == 0) ? 0.018 : 0.001;  // s in 2 s of wall time
    eta.add(simulated, 2.0);
    const double raw = 1.0 / (simulated / 2.0);  // the last-interval ETA, s
    raw_lo = std::min(raw_lo, raw), raw_hi = std::max(raw_hi, raw);
    if (k >= 20) {  // after the first tau: the smoothed ETA
      lo = std::min(lo, eta.seconds_left(1.0));
      hi = std::max(hi, eta.seconds_left(1.0));
    }
  }
  EXPECT_NEAR(raw_hi / raw_lo, 18.0, 1e-9);
  // The mean pace is (0.018 + 0.001) / 4 s per wall s: ETA 210.5 s; the smoothed ETA stays
  // within 10 % of it (one interval is 2/30 of the window).
  const double mean_eta = 1.0 / ((0.018 + 0.001) / 4.0);
  EXPECT_GT(lo, 0.9 * mean_eta);
  EXPECT_LT(hi, 1.1 * mean_eta);
}

TEST(ProgressEta, FollowsALastingChangeOfPace) {
  // The cost per step grows (particles added): the pace halves and stays there; after four
  // tau of wall time the ETA is that of the new pace within 5 %.
  ProgressEta eta(30.0);
  for (int k = 0; k < 50; ++k) eta.add(0.02, 2.0);
  for (int k = 0; k < 60; ++k) eta.add(0.01, 2.0);  // 120 s: four tau
  EXPECT_NEAR(eta.seconds_left(1.0), 200.0, 0.05 * 200.0);
}

TEST(ProgressEta, IgnoresABackwardClock) {
  ProgressEta eta;
  eta.add(0.01, 1.0);
  eta.add(0.01, -5.0);
  EXPECT_NEAR(eta.pace(), 0.01, 1e-15);
}

}  // namespace quarry
