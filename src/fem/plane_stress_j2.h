// Plane-stress material update of one shell integration point: linear elastic, or J2 (von
// Mises) plasticity with linear isotropic hardening by the plane-stress return map of Simo &
// Taylor (1986), as in Simo & Hughes, "Computational Inelasticity" (1998) §3.4: the consistency
// condition is solved for the plastic multiplier Δγ directly in plane stress (no σ_zz iteration).
#pragma once

#include <array>
#include <cmath>

namespace quarry::fem {

// In-plane stress or strain in Voigt order (xx, yy, xy); strains carry the engineering shear
// γ_xy = 2 ε_xy. Stress in Pa, strain in 1.
using Voigt3 = std::array<double, 3>;

struct PlaneStressMaterial {
  double youngs_modulus = 0.0;     // E (Pa)
  double poisson_ratio = 0.0;      // ν (1)
  double yield_stress = 0.0;       // σ_y0 (Pa); ≤ 0 or infinite: elastic
  double hardening_modulus = 0.0;  // H = dσ_y/dε̄_p (Pa), the plastic modulus
};

// σ_vm = √(σxx² − σxx σyy + σyy² + 3 σxy²) (Pa), the plane-stress von Mises stress.
inline double von_mises(const Voigt3& stress) {
  const double xx = stress[0], yy = stress[1], xy = stress[2];
  return std::sqrt(xx * xx - xx * yy + yy * yy + 3.0 * xy * xy);
}

// σ = C ε with the plane-stress elastic matrix C = E/(1 − ν²) [[1, ν, 0], [ν, 1, 0],
// [0, 0, (1 − ν)/2]] (Pa). Inline (as update_plane_stress's elastic path): the shell kernel
// calls it at every through-thickness point of every element each step.
inline Voigt3 plane_stress_elastic(const PlaneStressMaterial& material, const Voigt3& strain) {
  const double e = material.youngs_modulus, nu = material.poisson_ratio;
  const double factor = e / (1.0 - nu * nu);
  return {factor * (strain[0] + nu * strain[1]), factor * (nu * strain[0] + strain[1]),
          factor * 0.5 * (1.0 - nu) * strain[2]};
}

// The return map of update_plane_stress: `stress` holds the elastic trial σ_n + C Δε, outside
// the yield surface; both arguments are overwritten with the returned state.
void plane_stress_return_map(const PlaneStressMaterial& material, Voigt3& stress,
                             double& plastic_strain);

// Advances one point by the strain increment: the elastic trial σ_n + C Δε, then, if it lies
// outside the yield surface σ_vm = σ_y0 + H ε̄_p, the return map. `stress` (Pa) and
// `plastic_strain` ε̄_p (1) are read and overwritten. Cost: a scalar Newton solve (≤ ~10
// iterations) when plastic. Post: σ_vm(σ) ≤ σ_y0 + H ε̄_p (1 + 1e-10).
inline void update_plane_stress(const PlaneStressMaterial& material,
                                const Voigt3& strain_increment, Voigt3& stress,
                                double& plastic_strain) {
  const Voigt3 increment = plane_stress_elastic(material, strain_increment);
  stress = {stress[0] + increment[0], stress[1] + increment[1], stress[2] + increment[2]};
  const double yield0 = material.yield_stress;
  if (!(yield0 > 0.0) || !std::isfinite(yield0)) return;
  if (von_mises(stress) <= yield0 + material.hardening_modulus * plastic_strain) return;
  plane_stress_return_map(material, stress, plastic_strain);
}

}  // namespace quarry::fem
