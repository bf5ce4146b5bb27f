// Vertex welding: turns a triangle soup (three corner positions per triangle, as STL files and
// mesh generators produce) into an indexed mesh whose triangles share coincident vertices.
// Used once when a surface is loaded or generated, never inside the time step.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "core/vec3.h"
#include "geometry/surface.h"

namespace quarry {

struct WeldedMesh {
  std::vector<Vec3> vertices;                           // m, in order of first occurrence
  std::vector<std::array<std::uint32_t, 3>> triangles;  // one per input triangle, input order
};

// 1e-9 × the diagonal of the bounding box of `points` (m): coincident within round-off.
double default_weld_tolerance(std::span<const Vec3> points);

// Merges corners closer than `tolerance` (m, ≥ 0) into one vertex. corners.size() must be a
// multiple of 3; triangle t is corners[3t..3t+2]. Vertex indices follow first occurrence, so
// the result is deterministic. Cost: O(n) expected (hash of tolerance-sized cells).
WeldedMesh weld_triangle_soup(std::span<const Vec3> corners, double tolerance);

// A ready-to-use Surface from a soup: welded with default_weld_tolerance unless a tolerance
// ≥ 0 is given, reference_vertices = vertices, zero vertex velocities, normals, areas and
// zeroed loads.
Surface surface_from_triangle_soup(std::span<const Vec3> corners, std::string name,
                                   double weld_tolerance = -1.0);

}  // namespace quarry
