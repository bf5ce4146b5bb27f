// The dashpot window's pieces (dashpot_window.h) against their definitions: the window mean of
// δ^{1/4} against a numerical quadrature of the straight path, its limit at the centre, and the
// implicit velocity against the equation it solves.
#include "contact/dashpot_window.h"

#include <gtest/gtest.h>

#include <cmath>

namespace quarry {
namespace {

// Mean of max(δ(t), 0)^{1/4} over the window, δ(t) from δ − s to δ + s, by the midpoint rule
// with many points (m^{1/4}).
double quadrature_mean(double overlap, double half_path) {
  constexpr int kPoints = 200000;
  double sum = 0.0;
  for (int k = 0; k < kPoints; ++k) {
    const double x = overlap - half_path + (k + 0.5) * (2.0 * half_path / kPoints);
    sum += x > 0.0 ? std::sqrt(std::sqrt(x)) : 0.0;
  }
  return sum / kPoints;
}

TEST(DashpotWindow, MeanOfTheQuarterPowerIsTheWindowsIntegral) {
  // Inside contact, across the first touch, and just short of it (δ ≤ 0 < δ + s); m.
  for (const auto& [overlap, half_path] :
       {std::pair{2e-6, 1e-6}, std::pair{0.5e-6, 1e-6}, std::pair{0.0, 1e-6},
        std::pair{-0.4e-6, 1e-6}, std::pair{1e-5, 3e-6}}) {
    const double mean = contact::hertz_window_quarter_power(overlap, half_path);
    EXPECT_NEAR(mean / quadrature_mean(overlap, half_path), 1.0, 1e-5)
        << "δ = " << overlap << ", s = " << half_path;
  }
}

// Far inside contact the mean tends to the centre value: δ^{1/4} (1 − (s/δ)²/32 + …).
TEST(DashpotWindow, ShortPathsGiveTheCentreValue) {
  const double overlap = 1e-5;  // m
  for (const double ratio : {0.1, 0.05}) {
    const double mean = contact::hertz_window_quarter_power(overlap, ratio * overlap);
    EXPECT_NEAR(mean / std::sqrt(std::sqrt(overlap)), 1.0 - ratio * ratio / 32.0, 1e-5);
  }
  EXPECT_FALSE(contact::window_matters(overlap, 0.1 * overlap));
  EXPECT_TRUE(contact::window_matters(overlap, 0.11 * overlap));
  EXPECT_TRUE(contact::window_matters(0.0, 1e-9));
  EXPECT_TRUE(contact::window_matters(-1e-9, 0.0));
}

// u = u_lead + w (F − F_prev) with F = spring − c u: the returned u satisfies it, and w = 0
// gives the lead's velocity.
TEST(DashpotWindow, ImplicitVelocitySolvesItsEquation) {
  const double lead = -0.8, spring = 3.0, previous = 1.2, damping = 40.0, w = 0.01;
  const double u = contact::implicit_normal_velocity(lead, spring, previous, damping, w);
  EXPECT_NEAR(u, lead + w * ((spring - damping * u) - previous), 1e-15);
  EXPECT_EQ(contact::implicit_normal_velocity(lead, spring, previous, damping, 0.0), lead);
}

}  // namespace
}  // namespace quarry
