// Time-step estimates, used once at setup to choose dt and check it: the Rayleigh time step
// of the smallest particle and the Hertz contact time at the expected impact speed.
// Sources: EDEM guide (Rayleigh, after Li et al. 2005); Johnson 1985 §11.1 (Hertz impact).
#pragma once

namespace quarry {

// G = E / (2 (1 + ν)) (Pa), isotropic elasticity. Precondition: ν > −1.
double shear_modulus(double youngs, double poisson);

// Rayleigh time step (s): the time a Rayleigh surface wave needs to cross one particle,
// T_R = π R sqrt(ρ/G) / (0.1631 ν + 0.8766)  (EDEM guide; the denominator fits the Rayleigh
// wave speed ratio). R (m), ρ (kg/m³), G (Pa). Preconditions: all > 0, ν in (−1, 0.5].
double rayleigh_time_step(double radius, double density, double shear_modulus, double poisson);

// Duration of an elastic Hertz impact (s) at closing speed V (m/s):
// T_h = 2.87 (m*² / (R* E*² V))^{1/5}  (EDEM guide; Johnson 1985 eq. 11.24 gives 2.868).
double hertz_contact_time(double effective_mass, double effective_radius, double effective_youngs,
                          double impact_speed);

// Largest overlap of that impact (m): δmax = (15 m* V² / (16 E* sqrt(R*)))^{2/5}
// (Johnson 1985 eq. 11.23; from ½ m* V² = ∫ Fn dδ = 8/15 E* sqrt(R*) δmax^{5/2}).
double hertz_peak_overlap(double effective_mass, double effective_radius, double effective_youngs,
                          double impact_speed);

// Largest normal force of that impact (N): Fmax = 4/3 E* sqrt(R*) δmax^{3/2}.
double hertz_peak_force(double effective_mass, double effective_radius, double effective_youngs,
                        double impact_speed);

}  // namespace quarry
