// Surface: a triangle mesh that particles touch — walls, moving equipment, the skin of a
// structure. Vertices are moved by the surface's driver (sim: fixed, prescribed or coupled).
// Each step the contact stage fills its loads per triangle and per vertex; LoadWindow
// (geometry/load_window.h) averages them over time. Element ids = input order.
#pragma once

#include <array>
#include <bit>
#include <cstdint>
#include <string>
#include <vector>

#include "core/vec3.h"

namespace quarry {

struct Surface {
  std::string name;
  std::uint16_t material = 0;
  // ---- geometry (m, m/s); triangle t has vertices vertices[triangles[t][k]] ----
  std::vector<Vec3> reference_vertices;          // as read/generated, before motion
  std::vector<Vec3> vertices;                    // current positions
  std::vector<Vec3> vertex_velocities;           // current velocities (m/s)
  std::vector<std::array<std::uint32_t, 3>> triangles;
  std::vector<Vec3> triangle_normals;            // unit, right-hand rule of vertex order
  std::vector<double> triangle_areas;            // m²
  // Each triangle lies within triangle_reach (m) of its centroid (m): a bound that lets the
  // contact search skip a triangle without finding its closest point (surface_contact.cpp).
  std::vector<Vec3> triangle_centroids;
  std::vector<double> triangle_reach;
  Vec3 conveyor_velocity;                        // tangential surface velocity added at contacts
  bool export_loads = false;
  // Driven (prescribed motion or a coupling partner): the vertices leave reference_vertices
  // during the run, so the load export also writes their displacement.
  bool moving = false;

  // ---- per-step contact loads (reset each step, filled by the particle–surface stage) ----
  std::vector<Vec3> triangle_force;              // N, force the particles exert on the triangle
  std::vector<Vec3> vertex_force;                // N, barycentric share of each contact force
  Vec3 total_force;                              // N
  Vec3 total_torque;                             // N·m about the origin
  // The triangles and vertices whose load above may be non-zero this step, one bit each (bit
  // i % 64 of word i / 64): the load windows and the clearing visit them alone, in ascending
  // order (for_each_loaded), since a large mesh is mostly untouched each step
  // (docs/performance.md, "The load windows visit the marked triangles alone").
  std::vector<std::uint64_t> loaded_triangles, loaded_vertices;

  std::size_t triangle_count() const { return triangles.size(); }
  std::size_t vertex_count() const { return vertices.size(); }

  // Recomputes triangle_normals, triangle_areas, triangle_centroids and triangle_reach from
  // vertices (call whenever the vertices move).
  void update_normals_and_areas();
  // Recomputes triangle_centroids and triangle_reach alone (a restored checkpoint has the rest).
  void update_triangle_bounds();
  // Sizes the load arrays to the mesh and zeroes them (call after the mesh changes).
  void reset_loads();
  // Zeroes the per-step loads (triangle_force, vertex_force, totals) and their marks.
  // Cost: O(marked entries + mesh / 64).
  void clear_step_loads();
  // Adds a contact's reaction (N, the force on the surface) at `point` (m) on triangle t,
  // shared among its vertices by the barycentric weights, to the step's loads and totals, and
  // marks them. The contact stage's only way to load a surface.
  void add_contact_load(std::uint32_t t, const Vec3& reaction, const std::array<double, 3>& weights,
                        const Vec3& point);
  // Marks every triangle and vertex with a non-zero load, for whoever wrote triangle_force and
  // vertex_force directly (a restored checkpoint, a test). Cost: O(triangles + vertices).
  void mark_step_loads();
  Aabb bounds() const;
};

// Calls f(i) for each set bit i of `bits` (Surface::loaded_triangles, loaded_vertices), in
// ascending order. Cost: O(words + set bits).
template <class F>
void for_each_loaded(const std::vector<std::uint64_t>& bits, F f) {
  for (std::size_t w = 0; w < bits.size(); ++w)
    for (std::uint64_t word = bits[w]; word != 0; word &= word - 1)
      f(static_cast<std::uint32_t>(64 * w + static_cast<std::size_t>(std::countr_zero(word))));
}

}  // namespace quarry
