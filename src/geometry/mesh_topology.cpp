// Edges are found by sorting the 3 (low vertex, high vertex, triangle, slot) records of every
// triangle; incidence lists are filled by counting sort, so every list is ascending.
#include "geometry/mesh_topology.h"

#include <algorithm>
#include <tuple>

namespace quarry {

namespace {

// Turns (key, value) pairs into offsets + values grouped by key, values in ascending order.
void fill_adjacency(std::size_t key_count, std::vector<std::pair<std::uint32_t, std::uint32_t>>& pairs,
                    std::vector<std::uint32_t>& offsets, std::vector<std::uint32_t>& entries) {
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  offsets.assign(key_count + 1, 0);
  for (const auto& [key, value] : pairs) ++offsets[key + 1];
  for (std::size_t i = 0; i < key_count; ++i) offsets[i + 1] += offsets[i];
  entries.resize(pairs.size());
  for (std::size_t i = 0; i < pairs.size(); ++i) entries[i] = pairs[i].second;  // already grouped
}

}  // namespace

MeshTopology build_topology(const Surface& surface) {
  MeshTopology topology;
  const std::size_t triangle_count = surface.triangles.size();
  const std::size_t vertex_count = surface.vertices.size();

  struct EdgeRecord {
    std::uint32_t low, high, triangle, slot;
  };
  std::vector<EdgeRecord> records;
  records.reserve(3 * triangle_count);
  topology.triangle_edges.assign(triangle_count, {MeshTopology::no_edge, MeshTopology::no_edge, MeshTopology::no_edge});
  for (std::uint32_t t = 0; t < triangle_count; ++t)
    for (std::uint32_t k = 0; k < 3; ++k) {
      const std::uint32_t a = surface.triangles[t][k], b = surface.triangles[t][(k + 1) % 3];
      if (a != b) records.push_back({std::min(a, b), std::max(a, b), t, k});
    }
  std::sort(records.begin(), records.end(), [](const EdgeRecord& p, const EdgeRecord& q) {
    return std::tie(p.low, p.high, p.triangle, p.slot) < std::tie(q.low, q.high, q.triangle, q.slot);
  });

  std::vector<std::pair<std::uint32_t, std::uint32_t>> edge_triangle, vertex_edge, vertex_triangle;
  edge_triangle.reserve(records.size());
  for (std::size_t r = 0; r < records.size(); ++r) {
    const EdgeRecord& record = records[r];
    if (r == 0 || record.low != records[r - 1].low || record.high != records[r - 1].high) {
      const auto edge = static_cast<std::uint32_t>(topology.edges.size());
      topology.edges.push_back({record.low, record.high});
      vertex_edge.emplace_back(record.low, edge);
      vertex_edge.emplace_back(record.high, edge);
    }
    const auto edge = static_cast<std::uint32_t>(topology.edges.size() - 1);
    topology.triangle_edges[record.triangle][record.slot] = edge;
    edge_triangle.emplace_back(edge, record.triangle);
  }
  vertex_triangle.reserve(3 * triangle_count);
  for (std::uint32_t t = 0; t < triangle_count; ++t)
    for (int k = 0; k < 3; ++k) vertex_triangle.emplace_back(surface.triangles[t][k], t);

  fill_adjacency(topology.edges.size(), edge_triangle, topology.edge_triangle_offsets, topology.edge_triangle_list);
  fill_adjacency(vertex_count, vertex_edge, topology.vertex_edge_offsets, topology.vertex_edge_list);
  fill_adjacency(vertex_count, vertex_triangle, topology.vertex_triangle_offsets, topology.vertex_triangle_list);
  return topology;
}

}  // namespace quarry
