// Surface bookkeeping: normals, areas, per-step loads.
#include "geometry/surface.h"

#include <algorithm>
#include <cassert>
#include <cmath>

namespace quarry {

namespace {
// Words of the load marks of n entries (one bit each), and the mark of entry i set.
std::size_t mark_words(std::size_t n) { return (n + 63) / 64; }
void mark(std::vector<std::uint64_t>& bits, std::uint32_t i) {
  assert(i / 64 < bits.size());  // sized with the loads (reset_loads, mark_step_loads)
  bits[i / 64] |= std::uint64_t{1} << (i % 64);
}
}  // namespace

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
  loaded_triangles.assign(mark_words(triangles.size()), 0);
  loaded_vertices.assign(mark_words(vertices.size()), 0);
  if (vertex_velocities.size() != vertices.size()) vertex_velocities.assign(vertices.size(), {});
}

void Surface::clear_step_loads() {
  for_each_loaded(loaded_triangles, [this](std::uint32_t t) { triangle_force[t] = {}; });
  for_each_loaded(loaded_vertices, [this](std::uint32_t n) { vertex_force[n] = {}; });
  std::fill(loaded_triangles.begin(), loaded_triangles.end(), 0);
  std::fill(loaded_vertices.begin(), loaded_vertices.end(), 0);
  total_force = {};
  total_torque = {};
  // Every writer marks what it loads (add_contact_load, mark_step_loads): nothing is left.
  [[maybe_unused]] const auto zero = [](const Vec3& f) { return f == Vec3{}; };
  assert(std::all_of(triangle_force.begin(), triangle_force.end(), zero));
  assert(std::all_of(vertex_force.begin(), vertex_force.end(), zero));
}

void Surface::add_contact_load(std::uint32_t t, const Vec3& reaction,
                               const std::array<double, 3>& weights, const Vec3& point) {
  triangle_force[t] += reaction;
  mark(loaded_triangles, t);
  const auto& tri = triangles[t];
  for (int k = 0; k < 3; ++k) {
    vertex_force[tri[k]] += reaction * weights[k];
    mark(loaded_vertices, tri[k]);
  }
  total_force += reaction;
  total_torque += cross(point, reaction);
}

void Surface::mark_step_loads() {
  loaded_triangles.assign(mark_words(triangle_force.size()), 0);
  loaded_vertices.assign(mark_words(vertex_force.size()), 0);
  for (std::size_t t = 0; t < triangle_force.size(); ++t)
    if (!(triangle_force[t] == Vec3{})) mark(loaded_triangles, static_cast<std::uint32_t>(t));
  for (std::size_t n = 0; n < vertex_force.size(); ++n)
    if (!(vertex_force[n] == Vec3{})) mark(loaded_vertices, static_cast<std::uint32_t>(n));
}

Aabb Surface::bounds() const {
  Aabb box;
  for (const auto& v : vertices) box.expand(v);
  return box;
}

}  // namespace quarry
