// Surface bookkeeping: normals, areas, per-step loads.
#include "geometry/surface.h"

#include <algorithm>
#include <cmath>

namespace quarry {

void Surface::update_normals_and_areas() {
  triangle_normals.resize(triangles.size());
  triangle_areas.resize(triangles.size());
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    const Vec3& a = vertices[triangles[t][0]];
    const Vec3& b = vertices[triangles[t][1]];
    const Vec3& c = vertices[triangles[t][2]];
    const Vec3 n = cross(b - a, c - a);
    const double twice_area = norm(n);
    triangle_areas[t] = 0.5 * twice_area;
    triangle_normals[t] = twice_area > 0.0 ? n / twice_area : Vec3{};
  }
  update_triangle_bounds();
}

void Surface::update_triangle_bounds() {
  triangle_centroids.resize(triangles.size());
  triangle_reach.resize(triangles.size());
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    const Vec3& a = vertices[triangles[t][0]];
    const Vec3& b = vertices[triangles[t][1]];
    const Vec3& c = vertices[triangles[t][2]];
    const Vec3 centroid = (a + b + c) / 3.0;
    const double farthest2 = std::max({norm2(a - centroid), norm2(b - centroid), norm2(c - centroid)});  // m²
    triangle_centroids[t] = centroid;
    // Padded by a part in 10⁶ so that round-off in the test can only keep a triangle, never
    // drop one that touches.
    triangle_reach[t] = std::sqrt(farthest2) * (1.0 + 1e-6);
  }
}

void Surface::reset_loads() {
  triangle_force.assign(triangles.size(), {});
  vertex_force.assign(vertices.size(), {});
  total_force = {};
  total_torque = {};
  if (vertex_velocities.size() != vertices.size()) vertex_velocities.assign(vertices.size(), {});
}

void Surface::clear_step_loads() {
  for (auto& f : triangle_force) f = {};
  for (auto& f : vertex_force) f = {};
  total_force = {};
  total_torque = {};
}

Aabb Surface::bounds() const {
  Aabb box;
  for (const auto& v : vertices) box.expand(v);
  return box;
}

}  // namespace quarry
