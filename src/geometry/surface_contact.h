// Sphere–triangle-mesh contact detection for the particle–surface force stage: closest points
// on the candidate triangles (Ericson, Real-Time Collision Detection, 2005, §5.1.5), classified
// as face, edge or vertex, with duplicates on shared edges and vertices removed so that a sphere
// on a flat tessellated surface feels exactly one contact (face beats edge beats vertex).
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "core/vec3.h"
#include "geometry/mesh_topology.h"
#include "geometry/surface.h"

namespace quarry {

enum class ContactFeature : std::uint8_t { face, edge, vertex };

struct SurfaceContact {
  std::uint32_t triangle;         // owning triangle (element id); for edge/vertex contacts the
                                  // lowest-index incident triangle of non-zero area
  ContactFeature feature;
  std::uint32_t feature_index;    // triangle, edge or vertex index (per MeshTopology)
  Vec3 point;                     // closest point on the surface (m)
  Vec3 normal;                    // unit, from the surface point towards the sphere centre
  double overlap;                 // m, radius − distance (> 0)
  std::array<double, 3> weights;  // barycentric weights of `point` on `triangle`'s 3 vertices (sum 1)
};

// Relative tolerance of the feature classification: a closest point whose barycentric weight
// for a vertex is ≤ this is taken to lie on the opposite edge (or on a vertex if two are).
inline constexpr double contact_feature_tolerance = 1e-9;

// Finds the contacts of the sphere (centre in m, radius in m) with the candidate triangles
// (typically from SurfaceGrid::query of the sphere's box; it must contain every triangle the
// sphere touches, or a duplicate-suppressing neighbour may be missed). Clears `out` first.
// Validity: a face contact always counts; an edge contact only if no incident triangle has the
// centre's projection strictly inside it across that edge; a vertex contact only if the vertex
// is the closest point of every incident edge, i.e. dot(centre − v, w − v) ≤ tol·|w − v|².
// Edge and vertex contacts are reported once per edge / vertex. Both sides of a triangle count
// (normal from the surface point to the centre whatever the triangle's orientation); triangles
// of zero area are ignored. Output sorted by (triangle, feature, feature_index): deterministic.
// Preconditions: topology built from this surface; normals and areas current. Thread-safe.
void find_surface_contacts(const Surface& surface, const MeshTopology& topology, const Vec3& centre,
                           double radius, std::span<const std::uint32_t> candidate_triangles,
                           std::vector<SurfaceContact>& out);

}  // namespace quarry
