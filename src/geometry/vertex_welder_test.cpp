// Tests of vertex welding: shared corners merge, distinct ones stay apart, order is first
// occurrence, and a 1e5-triangle soup welds to the exact grid vertex count.
#include "geometry/vertex_welder.h"

#include <gtest/gtest.h>

#include <vector>

namespace quarry {
namespace {

TEST(VertexWelder, TwoTrianglesSharingAnEdgeShareTwoVertices) {
  const std::vector<Vec3> corners{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  const WeldedMesh mesh = weld_triangle_soup(corners, 1e-9);
  ASSERT_EQ(mesh.vertices.size(), 4u);
  EXPECT_EQ(mesh.triangles[0], (std::array<std::uint32_t, 3>{0, 1, 2}));
  EXPECT_EQ(mesh.triangles[1], (std::array<std::uint32_t, 3>{0, 2, 3}));
  EXPECT_EQ(mesh.vertices[3], (Vec3{0, 1, 0}));
}

TEST(VertexWelder, MergesWithinToleranceAndKeepsPointsBeyondIt) {
  const double tolerance = 1e-6;  // m
  const std::vector<Vec3> corners{{0, 0, 0}, {1, 0, 0}, {0, 1, 0},
                                  {0.4e-6, 0.4e-6, 0}, {1 + 3e-6, 0, 0}, {0, 1, 0.9e-6}};
  const WeldedMesh mesh = weld_triangle_soup(corners, tolerance);
  EXPECT_EQ(mesh.vertices.size(), 4u);  // only the point 3e-6 away stays separate
  EXPECT_EQ(mesh.triangles[1][0], 0u);
  EXPECT_EQ(mesh.triangles[1][1], 3u);
  EXPECT_EQ(mesh.triangles[1][2], 2u);
}

TEST(VertexWelder, DefaultToleranceIsOneBillionthOfTheDiagonal) {
  const std::vector<Vec3> points{{0, 0, 0}, {3, 4, 0}};
  EXPECT_DOUBLE_EQ(default_weld_tolerance(points), 5e-9);
}

TEST(VertexWelder, LargeGridSoupWeldsToGridVertexCount) {
  // 250 × 200 cells × 2 = 100,000 triangles; the welded grid has 251 × 201 vertices.
  const int nx = 250, ny = 200;
  std::vector<Vec3> corners;
  corners.reserve(6 * nx * ny);
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const Vec3 a{i * 0.01, j * 0.01, 0}, b{(i + 1) * 0.01, j * 0.01, 0}, c{(i + 1) * 0.01, (j + 1) * 0.01, 0},
          d{i * 0.01, (j + 1) * 0.01, 0};
      corners.insert(corners.end(), {a, b, c, a, c, d});
    }
  const Surface surface = surface_from_triangle_soup(corners, "grid");
  EXPECT_EQ(surface.triangle_count(), 100000u);
  EXPECT_EQ(surface.vertex_count(), static_cast<std::size_t>((nx + 1) * (ny + 1)));
  EXPECT_EQ(surface.reference_vertices, surface.vertices);
  EXPECT_EQ(surface.vertex_velocities.size(), surface.vertex_count());
  EXPECT_NEAR(surface.triangle_areas[0], 0.5e-4, 1e-18);
}

}  // namespace
}  // namespace quarry
