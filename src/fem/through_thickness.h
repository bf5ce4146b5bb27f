// Through-thickness integration rules of the shell section: n points ξ_i and weights w_i on
// [−1, 1], so that ∫ f dz over the thickness t is (t/2) Σ w_i f(ξ_i t/2). Gauss–Legendre and
// Gauss–Lobatto, computed from the Legendre polynomials (Abramowitz & Stegun 25.4.29, 25.4.32).
#pragma once

#include <vector>

namespace quarry::fem {

enum class ThicknessRule {
  // Gauss–Lobatto: includes the two surfaces (ξ = ±1), so the top and bottom stresses and the
  // first yield at the surface are sampled directly; exact for polynomials of degree 2n − 3.
  lobatto,
  // Gauss–Legendre: interior points only; exact for polynomials of degree 2n − 1.
  gauss,
};

struct ThicknessPoints {
  std::vector<double> coordinate;  // ξ_i in [−1, 1], ascending (1)
  std::vector<double> weight;      // w_i, Σ w_i = 2 (1)
};

// The n-point rule. Pre: 1 ≤ n ≤ 16 for Gauss, 2 ≤ n ≤ 16 for Lobatto (throws
// std::invalid_argument otherwise). Cost: O(n²) with a few Newton iterations per point.
ThicknessPoints thickness_points(ThicknessRule rule, int count);

}  // namespace quarry::fem
