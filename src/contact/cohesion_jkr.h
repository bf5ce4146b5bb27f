// JKR adhesive normal contact (EDEM's "JKR cohesion"): the elastic normal force of two adhering
// spheres from the radius a of their contact circle, used instead of the Hertz spring by an
// interaction with cohesion_model: jkr. Sources: Johnson, Kendall & Roberts 1971 (Proc. R. Soc.
// A 324, 301); the DEM form with contact forming at δ = 0 and breaking at δ_c: Thornton & Yin
// 1991 (Powder Technol. 65, 153), Thornton & Ning 1998 (Powder Technol. 99, 154).
// γ here is JKR's: the energy per unit area of contact (work of adhesion), so the pull-off
// force is 3/2 π γ R*. EDEM writes the same law as 4 sqrt(π γ E*) a^{3/2} and sqrt(4π γ a/E*),
// i.e. with half this γ (docs/deck.md says how to convert).
#pragma once

#include <cmath>
#include <numbers>

namespace quarry::contact {

// The JKR curve of one contact, δ(a) = a²/R* − sqrt(2π γ a/E*) and
// F(a) = 4 E* a³/(3 R*) − sqrt(8π γ E* a³), measured in its own scales: the contact radius
// at break a_c = (π γ R*²/(8 E*))^{1/3} (m), where dδ/da = 0, and the overlap at break
// δ_c = −3 a_c²/R* = −(3/4) (π² γ² R*/E*²)^{1/3} (m). With u = sqrt(a/a_c) and Δ = δ/|δ_c|
// the curve is 3Δ = u⁴ − 4u and F = π γ R* (u⁶/6 − u³): F = −5/6 π γ R* at break (u = 1),
// the least force −3/2 π γ R* (pull-off, JKR 1971) at u³ = 3, F = 0 at u³ = 6, i.e.
// a0 = (9π γ R*²/(2 E*))^{1/3}.
struct JkrScales {
  double break_radius = 0.0;   // m, a_c
  double break_overlap = 0.0;  // m, δ_c (< 0)
};

// γ (J/m²) > 0, E* (Pa) > 0, R* (m) > 0. Cost: one cube root.
inline JkrScales jkr_scales(double surface_energy, double effective_youngs, double effective_radius) {
  const double break_radius = std::cbrt(std::numbers::pi * surface_energy * effective_radius *
                                        effective_radius / (8.0 * effective_youngs));  // m
  return {break_radius, -3.0 * break_radius * break_radius / effective_radius};
}

// The contact radius a (m) of the loaded (stable) branch at overlap δ >= δ_c: the largest root
// u >= 1 of u⁴ − 4u − 3Δ = 0, a = a_c u². Newton's method from u0 = max(2, (6Δ)^{1/4}),
// which lies above that root (there u⁴/2 >= 4u and u⁴/2 > 3Δ); the quartic is convex, so the
// iterates decrease monotonically onto the root: stopped when they no longer decrease (round-
// off), at most 64 times (quadratic convergence, linear only at the double root Δ = −1,
// where 64 halvings reach round-off). Finite for every δ: Δ < −1 (no root, the contact
// has broken) is taken as Δ = −1, a = a_c. About 5 iterations for δ ≫ |δ_c|.
inline double jkr_contact_radius(const JkrScales& scales, double overlap) {
  const double reduced = std::fmax(overlap / -scales.break_overlap, -1.0);  // Δ (1)
  double u = std::fmax(2.0, std::sqrt(std::sqrt(6.0 * std::fmax(reduced, 0.0))));
  for (int iteration = 0; iteration < 64; ++iteration) {
    const double u3 = u * u * u;
    const double slope = 4.0 * u3 - 4.0;  // > 0 above the root
    if (!(slope > 0.0)) break;
    const double next = u - (u3 * u - 4.0 * u - 3.0 * reduced) / slope;
    if (!(next < u)) break;
    u = next;
  }
  u = std::fmax(u, 1.0);
  return scales.break_radius * u * u;
}

// F(a) = 4 E* a³/(3 R*) − sqrt(8π γ E* a³) (N, > 0 repulsive): the Hertz load of the contact
// circle less the adhesive pull (JKR 1971 eq. 3 rearranged).
inline double jkr_normal_force(double surface_energy, double effective_youngs,
                               double effective_radius, double contact_radius) {
  const double a3 = contact_radius * contact_radius * contact_radius;  // m³
  return 4.0 * effective_youngs * a3 / (3.0 * effective_radius) -
         std::sqrt(8.0 * std::numbers::pi * surface_energy * effective_youngs * a3);
}

}  // namespace quarry::contact
