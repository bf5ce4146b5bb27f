// Sphere–mesh contacts with duplicate suppression on shared edges and vertices. The closest
// point is Ericson's Voronoi-region walk (Real-Time Collision Detection §5.1.5); the feature is
// then read from its barycentric weights with a relative tolerance, so that a point exactly on
// a seam is the seam's edge (or vertex) for every triangle that shares it, never two faces.
#include "geometry/surface_contact.h"

#include <algorithm>
#include <tuple>

namespace quarry {

namespace {

struct ClosestPoint {
  Vec3 point;                     // m
  std::array<double, 3> weights;  // barycentric on (a, b, c)
};

// Ericson (2005) §5.1.5 ClosestPtPointTriangle, returning barycentric weights as well.
ClosestPoint closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= 0.0 && d2 <= 0.0) return {a, {1.0, 0.0, 0.0}};
  const Vec3 bp = p - b;
  const double d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0.0 && d4 <= d3) return {b, {0.0, 1.0, 0.0}};
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
    const double v = d1 / (d1 - d3);
    return {a + ab * v, {1.0 - v, v, 0.0}};
  }
  const Vec3 cp = p - c;
  const double d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0.0 && d5 <= d6) return {c, {0.0, 0.0, 1.0}};
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
    const double w = d2 / (d2 - d6);
    return {a + ac * w, {1.0 - w, 0.0, w}};
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return {b + (c - b) * w, {0.0, 1.0 - w, w}};
  }
  const double denominator = 1.0 / (va + vb + vc);
  const double v = vb * denominator, w = vc * denominator;
  return {a + ab * v + ac * w, {1.0 - v - w, v, w}};
}

// Lowest-index triangle of non-zero area in an ascending incidence list (the first one if all
// are degenerate, which cannot happen for a feature reported by a non-degenerate triangle).
std::uint32_t owning_triangle(const Surface& surface, std::span<const std::uint32_t> incident) {
  for (const std::uint32_t t : incident)
    if (surface.triangle_areas[t] > 0.0) return t;
  return incident.front();
}

// Weights on `triangle`'s vertices that put weight_first on vertex `first` and the rest on `second`.
std::array<double, 3> weights_on(const Surface& surface, std::uint32_t triangle, std::uint32_t first,
                                 double weight_first, std::uint32_t second) {
  std::array<double, 3> weights{0.0, 0.0, 0.0};
  for (int k = 0; k < 3; ++k) {
    if (surface.triangles[triangle][k] == first) weights[k] = weight_first;
    else if (surface.triangles[triangle][k] == second) weights[k] = 1.0 - weight_first;
  }
  return weights;
}

// An edge contact stands unless some incident triangle has the centre's projection strictly
// inside it across this edge (that triangle's face, or a neighbour's, is the real contact).
bool edge_contact_is_valid(const Surface& surface, const MeshTopology& topology, std::uint32_t edge,
                           const Vec3& centre) {
  const auto [v0, v1] = topology.edges[edge];
  const Vec3& x0 = surface.vertices[v0];
  const Vec3 along = surface.vertices[v1] - x0;
  for (const std::uint32_t t : topology.triangles_of_edge(edge)) {
    if (!(surface.triangle_areas[t] > 0.0)) continue;
    const auto& tri = surface.triangles[t];
    const std::uint32_t opposite = tri[0] != v0 && tri[0] != v1 ? tri[0] : (tri[1] != v0 && tri[1] != v1 ? tri[1] : tri[2]);
    const Vec3 inward = cross(surface.triangle_normals[t], along);  // in-plane, ⟂ edge
    const double height = dot(surface.vertices[opposite] - x0, inward);
    if (height == 0.0) continue;
    // Barycentric weight of the projected centre on the opposite vertex.
    const double weight_opposite = dot(centre - x0, inward) / height;
    if (weight_opposite > contact_feature_tolerance) return false;
  }
  return true;
}

// A vertex contact stands only if the vertex is the closest point of every incident edge.
bool vertex_contact_is_valid(const Surface& surface, const MeshTopology& topology, std::uint32_t vertex,
                             const Vec3& centre) {
  const Vec3& xv = surface.vertices[vertex];
  for (const std::uint32_t edge : topology.edges_of_vertex(vertex)) {
    const auto [a, b] = topology.edges[edge];
    const Vec3 along = surface.vertices[a == vertex ? b : a] - xv;
    if (dot(centre - xv, along) > contact_feature_tolerance * norm2(along)) return false;
  }
  return true;
}

bool already_found(const std::vector<SurfaceContact>& found, ContactFeature feature, std::uint32_t index) {
  return std::any_of(found.begin(), found.end(), [&](const SurfaceContact& contact) {
    return contact.feature == feature && contact.feature_index == index;
  });
}

}  // namespace

void find_surface_contacts(const Surface& surface, const MeshTopology& topology, const Vec3& centre,
                           double radius, std::span<const std::uint32_t> candidate_triangles,
                           std::vector<SurfaceContact>& out) {
  out.clear();
  const double radius2 = radius * radius;
  const bool bounded = surface.triangle_reach.size() == surface.triangles.size();
  for (const std::uint32_t t : candidate_triangles) {
    if (!(surface.triangle_areas[t] > 0.0)) continue;
    const auto& tri = surface.triangles[t];
    // The distance to the triangle's plane bounds the distance to the triangle from below: a
    // cheap rejection of the many candidates that are within the skin but not touching.
    const double height = dot(centre - surface.vertices[tri[0]], surface.triangle_normals[t]);  // m
    if (height * height >= radius2) continue;
    // The plane cuts the sphere in a disc of radius √(R² − h²) about the centre's foot, and the
    // triangle lies within its reach of its centroid: unless the foot is within the sum of the
    // two of the centroid, no point of t is within R. On a floor of many triangles this skips
    // most of them (the flagship: 14.6 candidates a particle pass the plane test, 1.2 touch).
    if (bounded) {
      const double foot_to_centroid2 = norm2(centre - surface.triangle_centroids[t]) - height * height;  // m²
      const double sum = std::sqrt(radius2 - height * height) + surface.triangle_reach[t];              // m
      if (foot_to_centroid2 > sum * sum) continue;
    }
    const ClosestPoint closest =
        closest_point_on_triangle(centre, surface.vertices[tri[0]], surface.vertices[tri[1]], surface.vertices[tri[2]]);
    if (norm2(centre - closest.point) >= radius2) continue;  // beyond reach of every feature of t

    int small_count = 0, large_slot = 0, small_slot = 0;
    for (int k = 0; k < 3; ++k) {
      if (closest.weights[k] <= contact_feature_tolerance) {
        ++small_count;
        small_slot = k;
      }
      if (closest.weights[k] > closest.weights[large_slot]) large_slot = k;
    }

    SurfaceContact contact{};
    if (small_count == 0) {
      if (already_found(out, ContactFeature::face, t)) continue;
      contact = {t, ContactFeature::face, t, closest.point, {}, 0.0, closest.weights};
    } else if (small_count == 1) {
      // Edge slot j runs from vertex j to j+1, so the edge opposite vertex k is slot (k+1)%3.
      const std::uint32_t edge = topology.triangle_edges[t][(small_slot + 1) % 3];
      if (edge == MeshTopology::no_edge || already_found(out, ContactFeature::edge, edge)) continue;
      if (!edge_contact_is_valid(surface, topology, edge, centre)) continue;
      // The point is recomputed from the edge alone so it does not depend on which triangle saw it.
      const auto [v0, v1] = topology.edges[edge];
      const Vec3& x0 = surface.vertices[v0];
      const Vec3 along = surface.vertices[v1] - x0;
      const double s = std::clamp(dot(centre - x0, along) / norm2(along), 0.0, 1.0);
      const std::uint32_t owner = owning_triangle(surface, topology.triangles_of_edge(edge));
      contact = {owner, ContactFeature::edge, edge, x0 + along * s, {}, 0.0, weights_on(surface, owner, v0, 1.0 - s, v1)};
    } else {
      const std::uint32_t vertex = tri[large_slot];
      if (already_found(out, ContactFeature::vertex, vertex)) continue;
      if (!vertex_contact_is_valid(surface, topology, vertex, centre)) continue;
      const std::uint32_t owner = owning_triangle(surface, topology.triangles_of_vertex(vertex));
      contact = {owner, ContactFeature::vertex, vertex, surface.vertices[vertex], {}, 0.0,
                 weights_on(surface, owner, vertex, 1.0, vertex)};
    }
    const Vec3 separation = centre - contact.point;
    const double distance = norm(separation);
    if (distance >= radius) continue;
    // A centre exactly on the surface has no direction to it: use the owner's normal.
    contact.normal = distance > 0.0 ? separation / distance : surface.triangle_normals[contact.triangle];
    contact.overlap = radius - distance;
    out.push_back(contact);
  }
  std::sort(out.begin(), out.end(), [](const SurfaceContact& p, const SurfaceContact& q) {
    return std::tie(p.triangle, p.feature, p.feature_index) < std::tie(q.triangle, q.feature, q.feature_index);
  });
}

}  // namespace quarry
