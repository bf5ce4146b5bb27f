// Gauss–Legendre and Gauss–Lobatto points by Newton's method on the Legendre polynomials
// (Abramowitz & Stegun 25.4.29 and 25.4.32 for the weights).
#include "fem/through_thickness.h"

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace quarry::fem {
namespace {

struct Legendre {
  double value;       // P_n(x)
  double derivative;  // P_n'(x)
  double previous;    // P_{n−1}(x)
};

// P_n, P_n' and P_{n−1} at x by the three-term recurrence (n ≥ 1, |x| < 1 for P_n').
Legendre legendre(int n, double x) {
  double p_previous = 1.0;
  double p = x;
  for (int k = 2; k <= n; ++k) {
    const double p_next = ((2.0 * k - 1.0) * x * p - (k - 1.0) * p_previous) / k;
    p_previous = p;
    p = p_next;
  }
  return {p, n * (x * p - p_previous) / (x * x - 1.0), p_previous};
}

}  // namespace

ThicknessPoints thickness_points(ThicknessRule rule, int count) {
  const int minimum = rule == ThicknessRule::gauss ? 1 : 2;
  if (count < minimum || count > 16) {
    throw std::invalid_argument("through-thickness integration: " + std::to_string(count) +
                                " points requested; " +
                                (rule == ThicknessRule::gauss ? "Gauss" : "Lobatto") +
                                " rules have " + std::to_string(minimum) + " to 16");
  }
  ThicknessPoints points;
  points.coordinate.resize(count);
  points.weight.resize(count);
  const double pi = std::numbers::pi;
  if (rule == ThicknessRule::gauss) {
    // Roots of P_n; w = 2 / ((1 − x²) P_n'(x)²) (A&S 25.4.29).
    for (int i = 0; i < count; ++i) {
      double x = -std::cos(pi * (i + 0.75) / (count + 0.5));
      for (int iteration = 0; iteration < 100; ++iteration) {
        const Legendre p = legendre(count, x);
        const double dx = p.value / p.derivative;
        x -= dx;
        if (std::abs(dx) < 1e-16) break;
      }
      const Legendre p = legendre(count, x);
      points.coordinate[i] = x;
      points.weight[i] = 2.0 / ((1.0 - x * x) * p.derivative * p.derivative);
    }
    return points;
  }
  // Lobatto: ±1 and the roots of P'_{n−1}; w = 2 / (n (n − 1) P_{n−1}(x)²) (A&S 25.4.32).
  const int m = count - 1;
  for (int i = 0; i < count; ++i) {
    double x = -std::cos(pi * i / m);
    if (i > 0 && i < m) {
      for (int iteration = 0; iteration < 100; ++iteration) {
        // Newton on P_m'(x): P_m'' = (2x P_m' − m(m+1) P_m) / (1 − x²).
        const Legendre p = legendre(m, x);
        const double second = (2.0 * x * p.derivative - m * (m + 1.0) * p.value) / (1.0 - x * x);
        const double dx = p.derivative / second;
        x -= dx;
        if (std::abs(dx) < 1e-16) break;
      }
    }
    const double p_m = i == 0 ? (m % 2 == 0 ? 1.0 : -1.0) : (i == m ? 1.0 : legendre(m, x).value);
    points.coordinate[i] = x;
    points.weight[i] = 2.0 / (count * (count - 1.0) * p_m * p_m);
  }
  return points;
}

}  // namespace quarry::fem
