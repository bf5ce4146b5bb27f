// Through-thickness rules: exactness degree (Gauss 2n − 1, Lobatto 2n − 3; Abramowitz & Stegun
// 25.4.29/25.4.32), the known 5-point nodes, and the plastic-moment integral ∫|ξ| dξ = 1 that
// sets how well a fully plastic section is captured.
#include "fem/through_thickness.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

namespace quarry::fem {
namespace {

double integrate_power(const ThicknessPoints& points, int power) {
  double sum = 0.0;
  for (std::size_t i = 0; i < points.coordinate.size(); ++i) {
    sum += points.weight[i] * std::pow(points.coordinate[i], power);
  }
  return sum;
}

TEST(ThroughThickness, GaussIsExactToDegreeTwoNMinusOne) {
  for (int n = 1; n <= 10; ++n) {
    const ThicknessPoints points = thickness_points(ThicknessRule::gauss, n);
    for (int power = 0; power <= 2 * n - 1; ++power) {
      const double exact = power % 2 == 1 ? 0.0 : 2.0 / (power + 1);
      EXPECT_NEAR(integrate_power(points, power), exact, 1e-13) << n << " points, x^" << power;
    }
  }
}

TEST(ThroughThickness, LobattoIsExactToDegreeTwoNMinusThreeAndHoldsTheSurfaces) {
  for (int n = 2; n <= 10; ++n) {
    const ThicknessPoints points = thickness_points(ThicknessRule::lobatto, n);
    EXPECT_DOUBLE_EQ(points.coordinate.front(), -1.0);
    EXPECT_DOUBLE_EQ(points.coordinate.back(), 1.0);
    for (int power = 0; power <= 2 * n - 3; ++power) {
      const double exact = power % 2 == 1 ? 0.0 : 2.0 / (power + 1);
      EXPECT_NEAR(integrate_power(points, power), exact, 1e-13) << n << " points, x^" << power;
    }
  }
}

TEST(ThroughThickness, FivePointNodesMatchTheTables) {
  // A&S Table 25.4: Gauss ±0.906179845938664, ±0.538469310105683; Lobatto ±√(3/7), weights
  // 1/10, 49/90, 32/45.
  const ThicknessPoints gauss = thickness_points(ThicknessRule::gauss, 5);
  EXPECT_NEAR(gauss.coordinate[0], -0.906179845938664, 1e-14);
  EXPECT_NEAR(gauss.coordinate[1], -0.538469310105683, 1e-14);
  EXPECT_NEAR(gauss.coordinate[2], 0.0, 1e-15);
  const ThicknessPoints lobatto = thickness_points(ThicknessRule::lobatto, 5);
  EXPECT_NEAR(lobatto.coordinate[1], -std::sqrt(3.0 / 7.0), 1e-14);
  EXPECT_NEAR(lobatto.weight[0], 0.1, 1e-14);
  EXPECT_NEAR(lobatto.weight[1], 49.0 / 90.0, 1e-14);
  EXPECT_NEAR(lobatto.weight[2], 32.0 / 45.0, 1e-14);
}

TEST(ThroughThickness, PlasticMomentIntegralIsUnderestimatedByFewPoints) {
  // ∫|ξ| dξ = 1 (the fully plastic moment σ_y b t²/4 in units of itself): 5 Lobatto points give
  // 0.913, 5 Gauss 0.945 (hand sums of A&S's tables), 9 Gauss points within 2.5 %.
  auto plastic = [](ThicknessRule rule, int n) {
    const ThicknessPoints p = thickness_points(rule, n);
    double sum = 0.0;
    for (std::size_t i = 0; i < p.coordinate.size(); ++i) sum += p.weight[i] * std::abs(p.coordinate[i]);
    return sum;
  };
  EXPECT_NEAR(plastic(ThicknessRule::lobatto, 5), 0.913, 1e-3);
  EXPECT_NEAR(plastic(ThicknessRule::gauss, 5), 0.945, 1e-3);
  EXPECT_NEAR(plastic(ThicknessRule::gauss, 9), 1.0, 0.025);
}

TEST(ThroughThickness, RejectsCountsOutOfRange) {
  EXPECT_THROW(thickness_points(ThicknessRule::lobatto, 1), std::invalid_argument);
  EXPECT_THROW(thickness_points(ThicknessRule::gauss, 0), std::invalid_argument);
  EXPECT_THROW(thickness_points(ThicknessRule::gauss, 17), std::invalid_argument);
}

}  // namespace
}  // namespace quarry::fem
