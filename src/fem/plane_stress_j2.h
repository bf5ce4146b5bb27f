// Plane-stress material update of one shell integration point: linear elastic, or J2 (von
// Mises) plasticity with linear isotropic hardening by the plane-stress return map of Simo &
// Taylor (1986), as in Simo & Hughes, "Computational Inelasticity" (1998) §3.4: the consistency
// condition is solved for the plastic multiplier Δγ directly in plane stress (no σ_zz iteration).
#pragma once

#include <array>

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
double von_mises(const Voigt3& stress);

// σ = C ε with the plane-stress elastic matrix C = E/(1 − ν²) [[1, ν, 0], [ν, 1, 0],
// [0, 0, (1 − ν)/2]] (Pa).
Voigt3 plane_stress_elastic(const PlaneStressMaterial& material, const Voigt3& strain);

// Advances one point by the strain increment: the elastic trial σ_n + C Δε, then, if it lies
// outside the yield surface σ_vm = σ_y0 + H ε̄_p, the return map. `stress` (Pa) and
// `plastic_strain` ε̄_p (1) are read and overwritten. Cost: a scalar Newton solve (≤ ~10
// iterations) when plastic. Post: σ_vm(σ) ≤ σ_y0 + H ε̄_p (1 + 1e-10).
void update_plane_stress(const PlaneStressMaterial& material, const Voigt3& strain_increment,
                         Voigt3& stress, double& plastic_strain);

}  // namespace quarry::fem
