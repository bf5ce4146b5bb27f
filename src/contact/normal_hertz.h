// Hertz-Mindlin no-slip stiffnesses and dashpots (EDEM's default contact model), evaluated in
// the force stage for every touching pair. Sources: EDEM theory reference guide; Johnson 1985
// §4.2 (Hertz); Mindlin & Deresiewicz 1953 (no-slip tangential stiffness); Tsuji et al. 1992.
#pragma once

#include <cmath>

namespace quarry::contact {

// Elastic normal force and its tangent stiffness dF/dδ at one overlap.
struct NormalSpring {
  double elastic_force = 0.0;  // N, > 0 repulsive
  double stiffness = 0.0;      // N/m
};

// Fn = 4/3 E* sqrt(R*) δ^{3/2},  Sn = dFn/dδ = 2 E* sqrt(R* δ)  (Johnson 1985 eq. 4.23; EDEM).
// Precondition: overlap >= 0. Cost: one sqrt.
inline NormalSpring hertz_normal_spring(double effective_youngs, double effective_radius,
                                        double overlap) {
  const double contact_radius = std::sqrt(effective_radius * overlap);  // m, a = sqrt(R* δ)
  return {4.0 / 3.0 * effective_youngs * contact_radius * overlap,
          2.0 * effective_youngs * contact_radius};
}

// St = 8 G* sqrt(R* δ)  (Mindlin & Deresiewicz 1953, no-slip; EDEM guide). N/m.
inline double mindlin_tangential_stiffness(double effective_shear, double effective_radius,
                                           double overlap) {
  return 8.0 * effective_shear * std::sqrt(effective_radius * overlap);
}

// Dashpot coefficient (N·s/m) used for both directions of Hertz-Mindlin:
// c = −2 sqrt(5/6) β sqrt(S m*) with S = Sn or St (EDEM guide; Tsuji et al. 1992). EDEM writes
// the force as −2 sqrt(5/6) β sqrt(S m*) v with v the approach speed; here β <= 0 makes c >= 0
// and the force on i is −c · (relative velocity of i), which opposes the motion either way.
inline double hertz_mindlin_damping_coefficient(double damping_ratio_beta, double stiffness,
                                                double effective_mass) {
  return -2.0 * std::sqrt(5.0 / 6.0) * damping_ratio_beta * std::sqrt(stiffness * effective_mass);
}

}  // namespace quarry::contact
