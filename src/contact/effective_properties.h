// Pair ("effective") properties of one contact: E*, G*, R*, m* and the damping ratio β from
// the coefficient of restitution. E*, G*, β are computed once per material pair, R*, m* per
// contact evaluation. Formulas: EDEM theory reference guide (Hertz-Mindlin no-slip), Johnson 1985.
#pragma once

#include <cmath>
#include <numbers>

namespace quarry {

// Elastic properties of one material (particle or surface).
struct MaterialProperties {
  double density = 0.0;         // kg/m³
  double youngs_modulus = 0.0;  // Pa
  double poisson_ratio = 0.0;   // 1
  // Infinitely stiff (a surface material, `rigid: true`): its compliance terms below vanish, so a
  // particle on it has E* = Ep/(1−νp²) and G* = Gp/(2−νp) (Johnson 1985, eq. 4.22 with E → ∞), the
  // rigid plane of the classic benchmarks. Young's modulus and Poisson ratio are then unused.
  bool rigid = false;
};

namespace contact {

// 1/E* = (1−νi²)/Ei + (1−νj²)/Ej  (Johnson 1985, Contact Mechanics, eq. 4.22; EDEM guide).
// A rigid material adds no compliance (two rigid ones give +inf: surfaces, which never touch).
// Precondition: Young's moduli > 0 (of the non-rigid ones). Cost: a few flops.
inline double effective_youngs_modulus(const MaterialProperties& a, const MaterialProperties& b) {
  const auto compliance_of = [](const MaterialProperties& m) {
    return m.rigid ? 0.0 : (1.0 - m.poisson_ratio * m.poisson_ratio) / m.youngs_modulus;  // 1/Pa
  };
  return 1.0 / (compliance_of(a) + compliance_of(b));
}

// 1/G* = 2(2−νi)(1+νi)/Ei + 2(2−νj)(1+νj)/Ej, i.e. (2−νi)/Gi + (2−νj)/Gj with G = E/(2(1+ν))
// (Mindlin & Deresiewicz 1953; EDEM guide); a rigid material adds none. Precondition as above.
inline double effective_shear_modulus(const MaterialProperties& a, const MaterialProperties& b) {
  const auto compliance_of = [](const MaterialProperties& m) {
    return m.rigid ? 0.0 : 2.0 * (2.0 - m.poisson_ratio) * (1.0 + m.poisson_ratio) / m.youngs_modulus;  // 1/Pa
  };
  return 1.0 / (compliance_of(a) + compliance_of(b));
}

// 1/R* = 1/Ri + 1/Rj (m). radius_j = 0 marks a wall (flat: infinite radius), so R* = Ri.
inline double effective_radius(double radius_i, double radius_j) {
  return radius_j > 0.0 ? radius_i * radius_j / (radius_i + radius_j) : radius_i;
}

// 1/m* = 1/mi + 1/mj (kg). mass_j = 0 marks a wall (infinite mass), so m* = mi.
inline double effective_mass(double mass_i, double mass_j) {
  return mass_j > 0.0 ? mass_i * mass_j / (mass_i + mass_j) : mass_i;
}

// β = ln e / sqrt(ln² e + π²)  (EDEM guide; Tsuji, Tanaka & Ishida 1992). β ∈ [−1, 0]:
// e = 1 gives β = 0 exactly (no damping); e → 0 gives β → −1 (critical damping), which is also
// returned for e <= 0 instead of the NaN the formula would give. Precondition: e <= 1.
inline double damping_ratio_from_restitution(double restitution) {
  if (restitution >= 1.0) return 0.0;
  if (restitution <= 0.0) return -1.0;
  const double log_restitution = std::log(restitution);  // 1
  return log_restitution /
         std::sqrt(log_restitution * log_restitution + std::numbers::pi * std::numbers::pi);
}

}  // namespace contact
}  // namespace quarry
