// Closed triangle meshes as solids: whether a mesh encloses a volume (every edge used by an even
// number of triangles), and which points of a box lattice lie inside it, by rays along +x with
// exact orientation predicates and a symbolic tie rule. Used for blocked fluid cells
// (cfdem/fluid_blocked.h); built once, not inside the time step.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "core/vec3.h"

namespace quarry {

// Whether a mesh is the boundary of a solid. Vertices at the same position (bit for bit) count
// as one, so a mesh given with repeated corners is judged like its welded form.
struct MeshClosure {
  // Edges used by an odd number of triangles: the holes' rims (0 for a closed mesh).
  std::size_t open_edges = 0;
  Vec3 first_open_edge_midpoint;  // m: of the open edge with the smallest corner positions
  // Every edge used as often from a to b as from b to a: the triangles' normals all point out
  // of the solid or all into it (per closed shell).
  bool consistently_oriented = false;
  bool closed() const { return open_edges == 0; }
};

// Cost: O(t log t) in the triangles.
MeshClosure check_closure(std::span<const Vec3> vertices,
                          std::span<const std::array<std::uint32_t, 3>> triangles);

// The centres of a box of cells, x fastest: point (i, j, k) = origin + (i + ½, j + ½, k + ½)·spacing
// component by component (the same arithmetic as cfd::FluidGrid::cell_centre).
struct CellCentres {
  Vec3 origin;                    // m
  Vec3 spacing{1.0, 1.0, 1.0};    // m, > 0
  std::array<int, 3> count{1, 1, 1};
};

// 1 for each centre inside the closed mesh, 0 outside; index i + nx (j + ny k). Pre: closure is
// check_closure of this mesh and closure.closed().
//
// Method: ray casting (Jordan-Brouwer: a ray from a point crosses a closed surface an odd number
// of times iff the point is inside; O'Rourke 1998, Computational Geometry in C, §7.4). One ray
// along +x per row of centres (j, k); a triangle is crossed when the row's (y, z) lies in its
// projection, decided by the exact sign of 2-D orientation determinants (Shewchuk 1997, Discrete
// Comput. Geom. 18:305-363: floating-point filter, then exact expansion arithmetic). A row through
// a projected edge or vertex is resolved by Simulation of Simplicity (Edelsbrunner & Mücke 1990,
// ACM Trans. Graph. 9:66-104): the row is moved to (y + ε, z + ε²), so every crossing of a shared
// edge is counted once, in exactly one of its triangles, and triangles seen edge-on are never
// crossed. Consistently oriented meshes use the non-zero winding rule along the ray (each crossing
// adds ±1 by the sign of the triangle's normal along x), so overlapping closed parts are a union
// and inward-facing meshes (a box surface) count as solid too; other closed meshes the even-odd
// rule. A centre on the surface (to round-off) counts as the point a hair towards −x.
// Cost: O(t·r + n log n): t triangles, r rows per triangle's projection, n crossings.
std::vector<std::uint8_t> mark_centres_inside(const CellCentres& centres,
                                              std::span<const Vec3> vertices,
                                              std::span<const std::array<std::uint32_t, 3>> triangles,
                                              const MeshClosure& closure);

// The sign (−1, 0, +1) of the 2-D orientation determinant (b − a) × (p − a) = (b_u − a_u)(p_v − a_v)
// − (b_v − a_v)(p_u − a_u), exactly (no round-off in the sign). Exposed for its test.
int orientation_sign(double a_u, double a_v, double b_u, double b_v, double p_u, double p_v);

}  // namespace quarry
