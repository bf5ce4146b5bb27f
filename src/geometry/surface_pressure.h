// Smoothed surface pressure for the output frames (issue #20). The per-triangle window mean is
// speckle where triangles are smaller than particles (a triangle either holds a contact or
// not); these two vertex fields are the remedies: the nodal pressure (the vertex force over
// the vertex's tributary area; conserves the total load exactly) and the coarse-grained
// pressure (a Gaussian average over the surface of width ~ a particle; converges to the mean).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "core/vec3.h"
#include "geometry/surface.h"

namespace quarry {

// Unit vertex normals: the area-weighted mean of the adjacent triangles' normals (zero for a
// vertex of no triangle). Pre: triangle_normals/areas are current. Cost: O(triangles).
std::vector<Vec3> vertex_normals(const Surface& surface);

// Tributary area of each vertex (m²): a third of the area of every triangle that uses it, so
// the tributary areas sum to the surface's area.
std::vector<double> tributary_areas(const Surface& surface);

// Nodal pressure (Pa) per vertex: p_v = −F_v·n_v / A_v with F_v the (window mean) nodal force,
// n_v the vertex normal and A_v the tributary area; compressive positive, as the per-triangle
// pressure. On a flat surface Σ p_v A_v = −(Σ F_v)·n: the total normal load, exactly.
// Pre: nodal_force.size() == vertex_count() (else std::invalid_argument). Cost: O(triangles).
std::vector<double> nodal_pressure(const Surface& surface, std::span<const Vec3> nodal_force);

// Coarse-grained pressure (Pa) per vertex: the Gaussian-weighted mean of the nodal pressure
// over the surface,  p̄_u = Σ_v W(|x_u − x_v|) p_v A_v / Σ_v W(|x_u − x_v|) A_v,
// W(r) = exp(−r² / (2 w²)) cut at r = 3w, A_v the tributary area. Built on the nodal forces
// (barycentric, so they keep each contact's position to first order; a triangle's centroid
// would shift it by up to 2/3 of a triangle and bias a mean by several %). The normalisation
// (a Shepard average) reproduces a uniform pressure exactly, also at the surface's edges. Only
// vertices whose normals lie within 60° of x_u's count, so a floor next to a wall is not
// averaged with it. `width` w (m, > 0) is the Gaussian's standard deviation; the output stage
// uses the largest particle radius, so the lattice of contacts under a packing (spacing p ~2R)
// is averaged out up to a ripple of relative amplitude 2·exp(−2π²w²/p²) per direction.
// Pre: nodal_pressure.size() == vertex_count() (else std::invalid_argument).
// Cost: O(vertices × vertices within 3w), through a uniform grid of cell 3w.
std::vector<double> coarse_grained_pressure(const Surface& surface,
                                            std::span<const double> nodal_pressure, double width);

// coarse_grained_pressure for a series of frames of one surface: the neighbours within 3w and
// their weights depend on the vertices alone, so they are found once and kept while the
// surface's vertices and the width stay as they were (a fixed wall: the whole run; a moving
// one: made anew each frame). The same values, to the bit, as coarse_grained_pressure. Cost of
// a frame once made: O(vertices × vertices within 3w) multiply-adds, no search and no exp.
class PressureSmoother {
 public:
  std::vector<double> smooth(const Surface& surface, std::span<const double> nodal_pressure,
                             double width);

 private:
  bool made_for(const Surface& surface, double width) const;
  void make(const Surface& surface, double width);

  std::vector<Vec3> vertices_;  // m: those the tables were made for
  std::size_t triangles_ = 0;
  double width_ = 0.0;                      // m
  std::vector<double> areas_;               // m², tributary, per vertex
  std::vector<std::size_t> offsets_;        // vertex u's neighbours: [offsets_[u], offsets_[u + 1])
  std::vector<std::uint32_t> neighbours_;   // within 3w, normals within 60°, in search order
  std::vector<double> weights_;             // exp(−r² / (2 w²)) per neighbour
  std::vector<double> weighted_areas_;      // m²: Σ W A_v per vertex
};

}  // namespace quarry
