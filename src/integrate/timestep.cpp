// Time-step estimates (Rayleigh, Hertz contact time); see timestep.h for formulas and sources.
#include "integrate/timestep.h"

#include <cmath>
#include <numbers>

namespace quarry {

double shear_modulus(double youngs, double poisson) {
  return youngs / (2.0 * (1.0 + poisson));
}

double rayleigh_time_step(double radius, double density, double shear_modulus, double poisson) {
  // T_R = π R sqrt(ρ/G) / (0.1631 ν + 0.8766)  (EDEM guide)
  return std::numbers::pi * radius * std::sqrt(density / shear_modulus) /
         (0.1631 * poisson + 0.8766);
}

double hertz_contact_time(double effective_mass, double effective_radius, double effective_youngs,
                          double impact_speed) {
  // T_h = 2.87 (m*² / (R* E*² V))^{1/5}  (EDEM guide; Johnson 1985 eq. 11.24)
  return 2.87 *
         std::pow(effective_mass * effective_mass /
                      (effective_radius * effective_youngs * effective_youngs * impact_speed),
                  0.2);
}

double hertz_peak_overlap(double effective_mass, double effective_radius, double effective_youngs,
                          double impact_speed) {
  // δmax = (15 m* V² / (16 E* sqrt(R*)))^{2/5}  (Johnson 1985 eq. 11.23)
  return std::pow(15.0 * effective_mass * impact_speed * impact_speed /
                      (16.0 * effective_youngs * std::sqrt(effective_radius)),
                  0.4);
}

double hertz_peak_force(double effective_mass, double effective_radius, double effective_youngs,
                        double impact_speed) {
  const double peak_overlap =
      hertz_peak_overlap(effective_mass, effective_radius, effective_youngs, impact_speed);  // m
  // Fmax = 4/3 E* sqrt(R*) δmax^{3/2}  (Hertz; Johnson 1985 eq. 4.23)
  return 4.0 / 3.0 * effective_youngs * std::sqrt(effective_radius) * peak_overlap *
         std::sqrt(peak_overlap);
}

}  // namespace quarry
