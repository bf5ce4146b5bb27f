// The per-period map of the particle–node exchange and its stability (period_stability.h).
#include "fsi/period_stability.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

namespace quarry::fsi {
namespace {

using Matrix3 = std::array<std::array<double, 3>, 3>;

// The map over one period in units m_p = 1, P = 1, state (r = x_p − x_n, ṙ, J) with J the
// impulse the node receives next period, after the rigid motion is taken out (a uniform x, v
// with J = 0 maps to itself). The surface of the period is x_n + v_n t with the node's sync
// state, so the particle's motion relative to it, w = x_p − x_n − v_n t, is the free damped
// oscillator m_p ẅ + c ẇ + k w = 0 from w(0) = r, ẇ(0) = ṙ; with the node at rest at the sync
// (the rigid part removed) the node moves as x_n = J t²/(2 m_n P), v_n = J t/(m_n P); the
// particle's impulse is m_p (ẇ(P) − ẇ(0)) and the node's next J is minus that.
Matrix3 period_map(double omega_period, double damping_ratio, double mass_ratio) {
  const double effective_mass = mass_ratio / (1.0 + mass_ratio);                // m*/m_p
  const double stiffness = omega_period * omega_period * effective_mass;       // k P²/m_p
  const double natural = std::sqrt(stiffness);                                 // √(k/m_p) P
  const double decay = damping_ratio * natural;                                // c P/(2 m_p)
  const double damped = natural * std::sqrt(1.0 - damping_ratio * damping_ratio);  // ω_d P
  // Transition of the damped oscillator over one period (exact, underdamped).
  const double e = std::exp(-decay), cs = std::cos(damped), sn = std::sin(damped);
  const double w_w = e * (cs + decay / damped * sn), w_v = e * sn / damped;
  const double v_w = -e * natural * natural / damped * sn, v_v = e * (cs - decay / damped * sn);
  const double node_mass = mass_ratio;  // m_n/m_p
  return {{{w_w, w_v, -0.5 / node_mass},
           {v_w, v_v, -1.0 / node_mass},
           {-v_w, 1.0 - v_v, 0.0}}};
}

// The exchange with the node's own dynamics (NodeDynamics) over one period, units m_p = 1,
// P = 1. Within the period, z = (x_p, v_p, x_n, v_n, x_s, v_s, F, A) evolves linearly:
//   ẍ_p = −k (x_p − x_s) − c (v_p − v_s)             the particle against the surface,
//   m_n ẍ_n = −K x_n − α m_n v_n + F                  the node under the held force,
//   ẋ_s = v_s, v̇_s = 0, Ḟ = 0                         the surface of the last sync, the held force,
//   Ȧ = k (x_p − x_s) + c (v_p − v_s)                 the impulse the node will receive;
// the sync sets x_s = x_n, v_s = v_n, F = A (impulse / P), A = 0. So a sync state
// s = (x_p, v_p, x_n, v_n, F) maps to s' = select(exp(L)·embed(s)): a 5×5 map.
using Matrix5 = std::array<std::array<double, 5>, 5>;
using Matrix8 = std::array<std::array<double, 8>, 8>;

Matrix8 multiply(const Matrix8& a, const Matrix8& b) {
  Matrix8 c{};
  for (std::size_t i = 0; i < 8; ++i)
    for (std::size_t k = 0; k < 8; ++k)
      for (std::size_t j = 0; j < 8; ++j) c[i][j] += a[i][k] * b[k][j];
  return c;
}

// exp(L) by scaling and squaring with a Taylor series (Moler & Van Loan, "Nineteen dubious ways
// to compute the exponential of a matrix", 2003, method 3): ‖L/2^s‖ ≤ 1/2, 24 terms.
Matrix8 exponential(Matrix8 l) {
  double norm = 0.0;
  for (const auto& row : l) {
    double sum = 0.0;
    for (double x : row) sum += std::abs(x);
    norm = std::max(norm, sum);
  }
  int squarings = 0;
  while (norm > 0.5) {
    norm *= 0.5;
    ++squarings;
  }
  const double scale = std::ldexp(1.0, -squarings);
  for (auto& row : l)
    for (double& x : row) x *= scale;
  Matrix8 result{}, term{};
  for (std::size_t i = 0; i < 8; ++i) result[i][i] = term[i][i] = 1.0;
  for (int n = 1; n <= 24; ++n) {
    term = multiply(term, l);
    for (std::size_t i = 0; i < 8; ++i)
      for (std::size_t j = 0; j < 8; ++j) {
        term[i][j] /= n;
        result[i][j] += term[i][j];
      }
  }
  for (int i = 0; i < squarings; ++i) result = multiply(result, result);
  return result;
}

Matrix5 node_period_map(double omega_period, double damping_ratio, double mass_ratio, NodeDynamics node) {
  const double stiffness = omega_period * omega_period * mass_ratio / (1.0 + mass_ratio);  // k P²/m_p
  const double dashpot = 2.0 * damping_ratio * std::sqrt(stiffness);                        // c P/m_p
  enum { xp, vp, xn, vn, xs, vs, f, a };
  Matrix8 l{};
  l[xp][vp] = 1.0;
  l[vp][xp] = -stiffness, l[vp][xs] = stiffness, l[vp][vp] = -dashpot, l[vp][vs] = dashpot;
  l[xn][vn] = 1.0;
  l[vn][xn] = -node.omega_period * node.omega_period, l[vn][vn] = -node.damping_period, l[vn][f] = 1.0 / mass_ratio;
  l[xs][vs] = 1.0;
  l[a][xp] = stiffness, l[a][xs] = -stiffness, l[a][vp] = dashpot, l[a][vs] = -dashpot;
  const Matrix8 e = exponential(l);
  // Column j of the map: the sync state e_j embedded (x_s = x_n, v_s = v_n, A = 0), carried
  // over the period, read back with F' = A.
  constexpr std::array<std::array<int, 2>, 5> embedded{{{xp, -1}, {vp, -1}, {xn, xs}, {vn, vs}, {f, -1}}};
  constexpr std::array<int, 5> read{xp, vp, xn, vn, a};
  Matrix5 m{};
  for (std::size_t j = 0; j < 5; ++j)
    for (std::size_t i = 0; i < 5; ++i) {
      const auto row = static_cast<std::size_t>(read[i]);
      double sum = 0.0;
      for (int column : embedded[j])
        if (column >= 0) sum += e[row][static_cast<std::size_t>(column)];
      m[i][j] = sum;
    }
  return m;
}

// ln ρ(M) of the leading n×n block by Gelfand's formula, ρ = lim ‖M^k‖^(1/k), over k = 2^40
// periods by repeated squaring, each square scaled to a largest entry of 1 and the scales'
// logarithms summed. Constant factors (an eigenvector basis far from orthogonal) add ln(C)/k:
// below 1e-10 here.
double log_spectral_radius(Matrix5 m, std::size_t n) {
  double log_scale = 0.0;
  for (int squaring = 0; squaring < 40; ++squaring) {
    Matrix5 square{};
    double largest = 0.0;
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t j = 0; j < n; ++j) {
        for (std::size_t k = 0; k < n; ++k) square[i][j] += m[i][k] * m[k][j];
        largest = std::max(largest, std::abs(square[i][j]));
      }
    if (largest == 0.0) return -std::numeric_limits<double>::infinity();  // nilpotent
    for (auto& row : square)
      for (double& x : row) x /= largest;
    log_scale = 2.0 * log_scale + std::log(largest);
    m = square;
  }
  return std::ldexp(log_scale, -40);
}

// A free node (Ω = 0): nothing depends on where the pair is, so the map is taken in
// (r = x_p − x_n, v_p, v_n, F) with x_n dropped. Otherwise the rigid translation's double
// eigenvalue 1 (a Jordan block when α = 0) would split by the square root of the rounding,
// ~1e-8, into a false growth.
Matrix5 without_translation(const Matrix5& m) {
  constexpr std::size_t xp = 0, xn = 2;
  constexpr std::array<std::size_t, 4> kept{xp, 1, 3, 4};
  Matrix5 reduced{};
  for (std::size_t i = 0; i < 4; ++i)
    for (std::size_t j = 0; j < 4; ++j) {
      const std::size_t row = kept[i], column = kept[j];
      reduced[i][j] = m[row][column] - (row == xp ? m[xn][column] : 0.0);
    }
  return reduced;
}

constexpr double kGrowthTolerance = 1e-9;  // per period: above the formula's error, far below any growth that matters

}  // namespace

bool exchange_is_stable(double omega_period, double damping_ratio, double mass_ratio) {
  if (!(omega_period > 0.0) || !(damping_ratio >= 0.0 && damping_ratio < 1.0) || !(mass_ratio > 0.0))
    throw std::invalid_argument("exchange_is_stable: need ω·P > 0, 0 ≤ ζ < 1, m_n/m_p > 0");
  const Matrix3 m = period_map(omega_period, damping_ratio, mass_ratio);
  // Characteristic polynomial λ³ + a2 λ² + a1 λ + a0: a2 = −trace, a1 = sum of the principal
  // 2×2 minors, a0 = −det.
  const double a2 = -(m[0][0] + m[1][1] + m[2][2]);
  const double a1 = (m[0][0] * m[1][1] - m[0][1] * m[1][0]) + (m[0][0] * m[2][2] - m[0][2] * m[2][0]) +
                    (m[1][1] * m[2][2] - m[1][2] * m[2][1]);
  const double a0 = -(m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
                      m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                      m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]));
  // Jury's test for a real cubic (Jury, "Theory and Application of the z-Transform Method",
  // 1964): all roots in |λ| < 1 iff p(1) > 0, −p(−1) > 0, |a0| < 1, |a0² − 1| > |a0 a2 − a1|.
  return 1.0 + a2 + a1 + a0 > 0.0 && 1.0 - a2 + a1 - a0 > 0.0 && std::abs(a0) < 1.0 &&
         std::abs(a0 * a0 - 1.0) > std::abs(a0 * a2 - a1);
}

double critical_omega_period(double damping_ratio, double mass_ratio) {
  if (!(damping_ratio >= 0.0 && damping_ratio < 1.0) || !(mass_ratio > 0.0))
    throw std::invalid_argument("critical_omega_period: need 0 ≤ ζ < 1, m_n/m_p > 0");
  if (damping_ratio == 0.0) return 0.0;  // the lag's negative damping is unopposed
  constexpr double step = 0.005, largest = 10.0;
  double stable = 0.0;
  for (double x = step; x <= largest + 0.5 * step; x += step) {
    if (exchange_is_stable(x, damping_ratio, mass_ratio)) {
      stable = x;
      continue;
    }
    double unstable = x;
    while (unstable - stable > 1e-9) {
      const double mid = 0.5 * (stable + unstable);
      (exchange_is_stable(mid, damping_ratio, mass_ratio) ? stable : unstable) = mid;
    }
    return 0.5 * (stable + unstable);
  }
  return std::numeric_limits<double>::infinity();
}

double exchange_growth_per_period(double omega_period, double damping_ratio, double mass_ratio, NodeDynamics node) {
  if (!(omega_period > 0.0) || !(damping_ratio >= 0.0 && damping_ratio < 1.0) || !(mass_ratio > 0.0) ||
      !(node.omega_period >= 0.0) || !(node.damping_period >= 0.0) || !std::isfinite(omega_period) ||
      !std::isfinite(mass_ratio) || !std::isfinite(node.omega_period) || !std::isfinite(node.damping_period))
    throw std::invalid_argument("exchange_growth_per_period: need ω·P > 0, 0 ≤ ζ < 1, m_n/m_p > 0, Ω·P ≥ 0, α·P ≥ 0");
  const Matrix5 map = node_period_map(omega_period, damping_ratio, mass_ratio, node);
  return node.omega_period == 0.0 ? log_spectral_radius(without_translation(map), 4) : log_spectral_radius(map, 5);
}

double required_damping_period(double omega_period, double damping_ratio, double mass_ratio,
                               double node_omega_period) {
  const auto grows = [&](double damping) {
    return exchange_growth_per_period(omega_period, damping_ratio, mass_ratio, {node_omega_period, damping}) >
           kGrowthTolerance;
  };
  if (!grows(0.0)) return 0.0;
  double stable = 0.01, unstable = 0.0;
  while (grows(stable)) {
    unstable = stable;
    stable *= 2.0;
    if (stable > 100.0) return std::numeric_limits<double>::infinity();
  }
  while (stable - unstable > 1e-3 * stable) {
    const double mid = 0.5 * (stable + unstable);
    (grows(mid) ? unstable : stable) = mid;
  }
  return stable;
}

DampingNeed required_damping_over_modes(double omega_period, double damping_ratio, double mass_ratio,
                                        double highest_node_omega_period) {
  const double highest = std::min(highest_node_omega_period, 2.0 * std::numbers::pi);
  DampingNeed worst{required_damping_period(omega_period, damping_ratio, mass_ratio, 0.0), 0.0};
  const auto consider = [&](double node_omega_period) {
    const double need = required_damping_period(omega_period, damping_ratio, mass_ratio, node_omega_period);
    if (need > worst.damping_period) worst = {need, node_omega_period};
  };
  constexpr double step = 0.05;
  for (int i = 1; i * step <= highest; ++i) consider(i * step);
  if (worst.node_omega_period > 0.0 && std::isfinite(worst.damping_period)) {
    const double centre = worst.node_omega_period;
    for (int i = -9; i <= 9; ++i)
      if (centre + i * 0.1 * step <= highest) consider(centre + i * 0.1 * step);
  }
  return worst;
}

}  // namespace quarry::fsi
