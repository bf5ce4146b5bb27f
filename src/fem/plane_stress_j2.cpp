// Plane-stress J2 return map with linear isotropic hardening (Simo & Taylor 1986; Simo & Hughes
// 1998, §3.4, "return mapping algorithm for plane stress").
#include "fem/plane_stress_j2.h"

#include <cmath>

namespace quarry::fem {

void plane_stress_return_map(const PlaneStressMaterial& material, Voigt3& stress,
                             double& plastic_strain) {
  const Voigt3 trial = stress;
  const double yield0 = material.yield_stress;
  const double hardening = material.hardening_modulus;

  // In the common eigenbasis of C and of the projection P (Simo & Hughes eq. 3.4.6):
  // a = (σxx + σyy)/√2 (C: E/(1 − ν), P: 1/3), b = (σyy − σxx)/√2 (C: 2G, P: 1),
  // c = σxy (C: G on γ_xy, P: 2). Then σ(Δγ) = [C⁻¹ + Δγ P]⁻¹ C⁻¹ σ_trial scales each
  // component: a/(1 + E Δγ/(3(1 − ν))), b/(1 + 2G Δγ), c/(1 + 2G Δγ).
  const double e = material.youngs_modulus, nu = material.poisson_ratio;
  const double shear_modulus = e / (2.0 * (1.0 + nu));
  const double a_rate = e / (3.0 * (1.0 - nu));
  const double b_rate = 2.0 * shear_modulus;
  const double a2 = 0.5 * (trial[0] + trial[1]) * (trial[0] + trial[1]);
  const double b2 = 0.5 * (trial[1] - trial[0]) * (trial[1] - trial[0]);
  const double c2 = trial[2] * trial[2];
  // f̄²(Δγ) = σᵀPσ = a²/3 + b² + 2c² = (2/3) σ_vm²; ε̄_p grows by Δγ √(2/3) f̄ (eq. 3.4.10).
  // Residual r(Δγ) = σ_vm(Δγ) − σ_y0 − H (ε̄_p,n + (2/3) Δγ σ_vm(Δγ)), decreasing in Δγ.
  auto residual = [&](double gamma, double* slope) {
    const double sa = 1.0 / (1.0 + a_rate * gamma), sb = 1.0 / (1.0 + b_rate * gamma);
    const double f2 = a2 * sa * sa / 3.0 + (b2 + 2.0 * c2) * sb * sb;
    const double vm = std::sqrt(1.5 * f2);
    const double df2 =
        -2.0 * a2 * a_rate * sa * sa * sa / 3.0 - 2.0 * (b2 + 2.0 * c2) * b_rate * sb * sb * sb;
    const double dvm = vm > 0.0 ? 0.75 * df2 / vm : 0.0;
    *slope = dvm - hardening * (2.0 / 3.0) * (vm + gamma * dvm);
    return vm - yield0 - hardening * (plastic_strain + (2.0 / 3.0) * gamma * vm);
  };
  // Bracket [0, high] with r(0) > 0 > r(high), then Newton kept inside the bracket.
  double low = 0.0, high = 1.0 / b_rate, slope = 0.0;
  while (residual(high, &slope) > 0.0) high *= 2.0;
  double gamma = 0.0;
  for (int iteration = 0; iteration < 60; ++iteration) {
    const double r = residual(gamma, &slope);
    if (r > 0.0) low = gamma; else high = gamma;
    double next = slope < 0.0 ? gamma - r / slope : 0.5 * (low + high);
    if (!(next > low && next < high)) next = 0.5 * (low + high);
    if (std::abs(next - gamma) <= 1e-15 * std::abs(next) + 1e-300) {
      gamma = next;
      break;
    }
    gamma = next;
  }
  const double sa = 1.0 / (1.0 + a_rate * gamma), sb = 1.0 / (1.0 + b_rate * gamma);
  const double a = (trial[0] + trial[1]) * sa, b = (trial[1] - trial[0]) * sb;  // both × √2
  stress = {0.5 * (a - b), 0.5 * (a + b), trial[2] * sb};
  plastic_strain += (2.0 / 3.0) * gamma * von_mises(stress);
}

}  // namespace quarry::fem
