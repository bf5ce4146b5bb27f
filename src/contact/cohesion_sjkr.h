// Simplified JKR cohesion (SJKR): an attractive normal force k·A proportional to the contact
// area, added in the force stage to touching pairs. Source: LIGGGHTS documentation,
// "cohesion_model sjkr"; the lens geometry of two intersecting spheres.
#pragma once

#include <numbers>

namespace quarry::contact {

// Area (m²) of the circle where two spheres of radii Ri, Rj (m) with overlap δ (m) intersect:
//   a² = (4 d² Ri² − (d² − Rj² + Ri²)²) / (4 d²),  d = Ri + Rj − δ   (LIGGGHTS sjkr docs),
// evaluated in the factored form a² = δ (2Ri − δ)(2Rj − δ)(2Ri + 2Rj − δ) / (4 d²) — the
// numerator is a difference of squares that factors exactly — which avoids the cancellation of
// two nearly equal terms when δ ≪ R. A = π a². Precondition: 0 <= δ < 2 min(Ri, Rj).
inline double sphere_sphere_contact_area(double radius_i, double radius_j, double overlap) {
  const double centre_distance = radius_i + radius_j - overlap;  // m, d
  const double contact_radius2 = overlap * (2.0 * radius_i - overlap) * (2.0 * radius_j - overlap) *
                                 (2.0 * (radius_i + radius_j) - overlap) /
                                 (4.0 * centre_distance * centre_distance);  // m², a²
  return std::numbers::pi * contact_radius2;
}

// Sphere of radius Ri (m) cut by a plane at depth δ (m): A = π (2 Ri δ − δ²) (m²).
inline double sphere_wall_contact_area(double radius_i, double overlap) {
  return std::numbers::pi * (2.0 * radius_i * overlap - overlap * overlap);
}

// SJKR: F = k A (N, attractive) with k the cohesion energy density (J/m³) and A (m²).
inline double sjkr_cohesion_force(double cohesion_energy_density, double contact_area) {
  return cohesion_energy_density * contact_area;
}

}  // namespace quarry::contact
