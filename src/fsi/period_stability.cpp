// The per-period map of the particle–node exchange and its stability (period_stability.h).
#include "fsi/period_stability.h"

#include <array>
#include <cmath>
#include <limits>
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

}  // namespace quarry::fsi
