// Mesh topology of a Surface: unique edges and the triangle/edge/vertex incidences that the
// particle–surface contact needs to tell one contact from duplicates on shared edges and
// vertices. Depends only on connectivity: build once per mesh, valid while vertices move.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "geometry/surface.h"

namespace quarry {

struct MeshTopology {
  static constexpr std::uint32_t no_edge = 0xFFFFFFFFu;

  // Unique edges as vertex pairs (first < second), sorted lexicographically.
  std::vector<std::array<std::uint32_t, 2>> edges;
  // triangle_edges[t][k]: the edge from triangle vertex k to vertex (k+1)%3, or no_edge when
  // those two vertex indices are equal (a collapsed triangle).
  std::vector<std::array<std::uint32_t, 3>> triangle_edges;
  // Compressed adjacency lists (each list ascending): entries offsets[i] .. offsets[i+1]−1.
  std::vector<std::uint32_t> edge_triangle_offsets, edge_triangle_list;      // 1–2 on a manifold
  std::vector<std::uint32_t> vertex_edge_offsets, vertex_edge_list;
  std::vector<std::uint32_t> vertex_triangle_offsets, vertex_triangle_list;

  std::size_t edge_count() const { return edges.size(); }
  std::span<const std::uint32_t> triangles_of_edge(std::uint32_t edge) const {
    return list(edge_triangle_offsets, edge_triangle_list, edge);
  }
  std::span<const std::uint32_t> edges_of_vertex(std::uint32_t vertex) const {
    return list(vertex_edge_offsets, vertex_edge_list, vertex);
  }
  std::span<const std::uint32_t> triangles_of_vertex(std::uint32_t vertex) const {
    return list(vertex_triangle_offsets, vertex_triangle_list, vertex);
  }

 private:
  static std::span<const std::uint32_t> list(const std::vector<std::uint32_t>& offsets,
                                             const std::vector<std::uint32_t>& entries, std::uint32_t i) {
    return std::span<const std::uint32_t>(entries).subspan(offsets[i], offsets[i + 1] - offsets[i]);
  }
};

// Builds the topology of `surface` (its triangles and vertex count). Cost: O(n log n) in the
// number of triangles.
MeshTopology build_topology(const Surface& surface);

}  // namespace quarry
