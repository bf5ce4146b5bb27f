// The input of the shell solver: nodes, 3- and 4-node shell elements, sections, materials and
// boundary conditions on node sets, as plain data in SI units. Built by a reader or by code;
// `validate_shell_model` checks it and ShellSolver's constructor calls that.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "core/vec3.h"
#include "fem/through_thickness.h"

namespace quarry::fem {

struct ShellMaterial {
  double youngs_modulus = 0.0;  // E (Pa), > 0
  double poisson_ratio = 0.0;   // ν (1), in (−1, 0.5)
  double density = 0.0;         // ρ (kg/m³), > 0
  // J2 plasticity with linear isotropic hardening σ_y = σ_y0 + H ε̄_p; σ_y0 = 0: elastic.
  double yield_stress = 0.0;       // σ_y0 (Pa), ≥ 0
  double hardening_modulus = 0.0;  // H (Pa), ≥ 0: the slope of stress vs plastic strain
};

struct ShellSection {
  double thickness = 0.0;         // t (m), > 0
  int integration_points = 5;     // through the thickness
  ThicknessRule rule = ThicknessRule::lobatto;
  int material = 0;               // index into ShellModel::materials
};

// A quadrilateral (node_count 4, nodes counter-clockwise seen from the side the normal points
// to) or a triangle (node_count 3; nodes[3] ignored). Node indices are 0-based.
struct ShellElement {
  std::array<std::int32_t, 4> nodes{};
  int node_count = 4;
  int section = 0;  // index into ShellModel::sections
};

// Degrees of freedom of a node as bits: translations x, y, z then rotations about x, y, z.
namespace dof {
inline constexpr std::uint8_t ux = 1, uy = 2, uz = 4, rx = 8, ry = 16, rz = 32;
inline constexpr std::uint8_t translations = ux | uy | uz;
inline constexpr std::uint8_t rotations = rx | ry | rz;
inline constexpr std::uint8_t all = translations | rotations;
}  // namespace dof

// The DOFs in `dofs` of every node of `nodes` move with `velocity` (m/s for translations, rad/s
// for rotations, global axes; zero: fixed). Components outside the mask are ignored. A later
// condition on the same node and DOF replaces an earlier one.
struct BoundaryCondition {
  std::vector<std::int32_t> nodes;
  std::uint8_t dofs = 0;
  std::array<double, 6> velocity{};
};

struct ShellModel {
  std::vector<Vec3> nodes;  // initial positions (m)
  std::vector<ShellElement> elements;
  std::vector<ShellSection> sections;
  std::vector<ShellMaterial> materials;
  std::vector<BoundaryCondition> boundary_conditions;
};

// The shape of an element with corners x[0 .. node_count − 1] (m): degenerate (area ≤ 1e-12
// of the squared longest edge, coincident or collinear corners), a quad not convex at a corner
// (a bow-tie, or a re-entrant corner: that corner's triangle turns against the element's
// normal), or fine. The test of validate_shell_model, for the model readers to report at the
// element's card. Cost: O(1).
struct ElementShape {
  enum Kind { fine, degenerate, not_convex } kind = fine;
  double area = 0.0;          // m²
  double longest_edge = 0.0;  // m
  int corner = -1;            // not_convex: the first such corner (0-based)
};
ElementShape element_shape(const std::array<Vec3, 4>& x, int node_count);

// Throws std::invalid_argument naming the first offending item (element id = its index, node,
// section, material) and the value: bad indices, repeated nodes, degenerate elements (area ≤
// 1e-12 of the squared longest edge), thickness ≤ 0, integration points out of range, E ≤ 0,
// ν outside (−1, 0.5), ρ ≤ 0, σ_y0 < 0, H < 0, non-finite numbers. Cost: O(size of the model).
void validate_shell_model(const ShellModel& model);

// The model's supports: the nodes with a prescribed DOF, grouped where an element edge joins
// two of them (a rail, a clamped edge: each group one support whose reaction a monitor sums).
// Groups in the order of their smallest node, nodes ascending. Pre: a valid model. O(size).
std::vector<std::vector<std::int32_t>> support_groups(const ShellModel& model);

// The quads warped beyond kWarpageLimitDegrees (shell_element.h): how many, and the worst one's
// index and warpage (degrees). Cost: O(elements).
struct WarpedQuads {
  int count = 0;
  int worst_element = -1;
  double worst_degrees = 0.0;
};
WarpedQuads warped_quads(const ShellModel& model);

}  // namespace quarry::fem
