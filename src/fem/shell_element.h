// One-point co-rotational shell elements: the Belytschko–Tsay quadrilateral (Belytschko, Lin &
// Tsay 1984, CMAME 42:225; hourglass control of Belytschko & Tsay 1983, IJNME 19:405) and the
// C0 triangle (Belytschko, Stolarski & Carpenter 1984, IJNME 20:787). Stage "internal forces"
// of the solver's step: strain rates at the element centre → stresses at the through-thickness
// points → resultants → nodal forces and moments.
#pragma once

#include <array>

#include "core/vec3.h"
#include "fem/plane_stress_j2.h"

namespace quarry::fem {

// The co-rotational frame: e3 the normal (quad: along the cross product of the diagonals,
// triangle: of two edges), e1 along edge 1→2 projected on the plane, e2 = e3 × e1.
struct ElementFrame {
  Vec3 origin;  // centroid of the nodes (m)
  Vec3 e1, e2, e3;
};
ElementFrame element_frame(const std::array<Vec3, 4>& x, int node_count);

// Area of the element's projection on its frame (m²).
double element_area(const std::array<Vec3, 4>& x, int node_count);
// L_c for the stable step (LS-DYNA's shell rule): quad A / max(edge), triangle 2A / max(edge),
// i.e. the smallest altitude (m).
double characteristic_length(const std::array<Vec3, 4>& x, int node_count);
// A quad's warpage (degrees): the larger over its two diagonals of the angle between the normals
// of the two triangles the diagonal cuts it into (0 for a flat quad).
double quad_warpage_degrees(const std::array<Vec3, 4>& x);
// LS-DYNA's default limit of shell warpage (*CONTROL_SHELL WRPANG, 20°): beyond it a one-point
// quad on its projection, even with the warping correction, is a poor model of the surface.
inline constexpr double kWarpageLimitDegrees = 20.0;

// Transverse shear of the quad: the Belytschko–Tsay centre value (fails the bending patch test
// on distorted meshes), or edge-tied assumed strains evaluated at the centre (default).
enum class QuadShear { centre, edge_tied };

struct SectionProperties {
  double thickness = 0.0;           // t (m)
  int points = 0;                   // through-thickness points
  const double* coordinate = nullptr;  // ξ_i in [−1, 1]
  const double* weight = nullptr;      // w_i, Σ = 2
  PlaneStressMaterial material;
  double shear_modulus = 0.0;        // G (Pa)
  double shear_factor = 5.0 / 6.0;   // κ, transverse shear correction (1)
  // Stiffness hourglass coefficients (1), fractions of the element's physical stiffness:
  // in-plane, out-of-plane w, and rotational modes (Belytschko & Tsay 1983 r_m, r_w, r_θ).
  double hourglass_membrane = 0.05, hourglass_transverse = 0.05, hourglass_bending = 0.05;
  QuadShear quad_shear = QuadShear::edge_tied;
  // Drilling stiffness α of G t A (N·m/rad) against the spin about the normal that the
  // translations do not carry (shell_element.cpp); 0: none. 0.1: the twisted beam within
  // 0.3 % of its value at α = 1, the drilling mode at ~0.3 of the membrane modes' frequency.
  double drilling = 0.1;
};

// History of one element, pointers into the solver's arrays.
struct ElementState {
  double* stress = nullptr;          // 3 per point: σxx, σyy, σxy in the element frame (Pa)
  double* plastic_strain = nullptr;  // ε̄_p per point (1)
  // 3 transverse shear resultants: quad Q_x, Q_y (N/m) at the centre and an unused slot;
  // triangle κGt (a_x, a_y, c) of its assumed shear field (N/m, N/m, N/m²).
  double* shear = nullptr;
  double* hourglass = nullptr;       // 5 hourglass resultants: m_x, m_y (N), w (N), θx, θy (N·m)
};

struct ElementForces {
  // Internal (resisting) force (N) and moment (N·m) per node, global axes: 0-2 force, 3-5 moment.
  std::array<std::array<double, 6>, 4> nodal{};
  double internal_energy_increment = 0.0;   // J, stress work of this step
  double hourglass_energy_increment = 0.0;  // J, hourglass work of this step
};

// Advances the element's stresses by the strain increments d·dt from the nodal velocities
// (v, ω at the step's midpoint) on the configuration x, and returns its nodal internal forces
// on x. Pre: non-degenerate element, dt ≥ 0. Cost: O(points).
ElementForces shell_internal_forces(const std::array<Vec3, 4>& x, const std::array<Vec3, 4>& v,
                                    const std::array<Vec3, 4>& omega, int node_count, double dt,
                                    const SectionProperties& section, ElementState state);

}  // namespace quarry::fem
