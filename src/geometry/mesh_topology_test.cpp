// Tests of mesh topology: edge counts against closed forms for structured grids and closed
// meshes, and consistency of the incidence lists.
#include "geometry/mesh_topology.h"

#include <gtest/gtest.h>

#include <algorithm>

#include "geometry/primitives.h"

namespace quarry {
namespace {

TEST(MeshTopology, PlaneGridHasTheStructuredCounts) {
  const int d = 6;
  const Surface plane = make_plane({0, 0, 0}, {0, 0, 1}, 1.0, d);
  const MeshTopology topology = build_topology(plane);
  // d(d+1) edges along each grid direction plus one diagonal per cell.
  EXPECT_EQ(topology.edge_count(), static_cast<std::size_t>(2 * d * (d + 1) + d * d));
  std::size_t boundary = 0;
  for (std::uint32_t e = 0; e < topology.edge_count(); ++e) {
    const auto triangles = topology.triangles_of_edge(e);
    ASSERT_TRUE(triangles.size() == 1 || triangles.size() == 2);
    boundary += triangles.size() == 1;
  }
  EXPECT_EQ(boundary, static_cast<std::size_t>(4 * d));
  // Interior vertices of a grid with one diagonal direction have 6 edges and 6 triangles.
  for (std::uint32_t v = 0; v < plane.vertex_count(); ++v) {
    const Vec3& x = plane.vertices[v];
    const bool interior = std::abs(x.x) < 0.49 && std::abs(x.y) < 0.49;
    if (!interior) continue;
    EXPECT_EQ(topology.edges_of_vertex(v).size(), 6u);
    EXPECT_EQ(topology.triangles_of_vertex(v).size(), 6u);
  }
}

TEST(MeshTopology, IncidenceListsAgreeWithTheTriangles) {
  const Surface box = make_box({0, 0, 0}, {1, 2, 3}, 2);
  const MeshTopology topology = build_topology(box);
  EXPECT_EQ(box.vertex_count() + box.triangle_count(), topology.edge_count() + 2);  // Euler
  for (std::uint32_t t = 0; t < box.triangle_count(); ++t)
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = box.triangles[t][k], b = box.triangles[t][(k + 1) % 3];
      const std::uint32_t edge = topology.triangle_edges[t][k];
      EXPECT_EQ(topology.edges[edge][0], std::min(a, b));
      EXPECT_EQ(topology.edges[edge][1], std::max(a, b));
      const auto around = topology.triangles_of_edge(edge);
      EXPECT_NE(std::find(around.begin(), around.end(), t), around.end());
      const auto of_vertex = topology.triangles_of_vertex(a);
      EXPECT_NE(std::find(of_vertex.begin(), of_vertex.end(), t), of_vertex.end());
      const auto edges_of_a = topology.edges_of_vertex(a);
      EXPECT_NE(std::find(edges_of_a.begin(), edges_of_a.end(), edge), edges_of_a.end());
    }
  for (std::uint32_t v = 0; v < box.vertex_count(); ++v) {
    const auto list = topology.triangles_of_vertex(v);
    EXPECT_TRUE(std::is_sorted(list.begin(), list.end()));
  }
}

TEST(MeshTopology, CollapsedTriangleHasNoSelfEdge) {
  Surface surface;
  surface.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  surface.triangles = {{0, 1, 2}, {0, 0, 1}};
  const MeshTopology topology = build_topology(surface);
  EXPECT_EQ(topology.edge_count(), 3u);
  EXPECT_EQ(topology.triangle_edges[1][0], MeshTopology::no_edge);
  EXPECT_EQ(topology.triangles_of_edge(topology.triangle_edges[1][1]).size(), 2u);
}

}  // namespace
}  // namespace quarry
