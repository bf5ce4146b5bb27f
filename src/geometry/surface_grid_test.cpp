// Tests of the surface cell grid against brute force: no triangle that intersects a query box
// is missed, nothing outside the box's reach is returned, output sorted and unique.
#include "geometry/surface_grid.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>

#include "geometry/primitives.h"

namespace quarry {
namespace {

bool boxes_overlap(const Aabb& a, const Aabb& b) {
  return a.lo.x <= b.hi.x && a.hi.x >= b.lo.x && a.lo.y <= b.hi.y && a.hi.y >= b.lo.y &&
         a.lo.z <= b.hi.z && a.hi.z >= b.lo.z;
}

Aabb triangle_box(const Surface& s, std::size_t t) {
  Aabb box;
  for (int k = 0; k < 3; ++k) box.expand(s.vertices[s.triangles[t][k]]);
  return box;
}

// Checks one query: sorted, unique, ⊆ bounding-box overlaps, ⊇ triangles with a sample point
// (vertex or centroid) inside the box (those certainly intersect it).
void check_query(const Surface& surface, const SurfaceGrid& grid, const Aabb& box) {
  std::vector<std::uint32_t> found;
  grid.query(box, found);
  ASSERT_TRUE(std::is_sorted(found.begin(), found.end()));
  ASSERT_EQ(std::adjacent_find(found.begin(), found.end()), found.end());
  for (const std::uint32_t t : found) ASSERT_TRUE(boxes_overlap(triangle_box(surface, t), box));
  for (std::uint32_t t = 0; t < surface.triangle_count(); ++t) {
    const auto& tri = surface.triangles[t];
    const Vec3 centroid =
        (surface.vertices[tri[0]] + surface.vertices[tri[1]] + surface.vertices[tri[2]]) / 3.0;
    bool must = box.contains(centroid);
    for (int k = 0; k < 3; ++k) must = must || box.contains(surface.vertices[tri[k]]);
    if (must) {
      ASSERT_TRUE(std::binary_search(found.begin(), found.end(), t)) << "missed triangle " << t;
    }
  }
}

// A small grid reads a row's triangles from a per-cell table, a large one searches its sparse
// keys: both must answer as brute force does. The tilted drum at 5 cm cells has some 20,000
// cells (dense), at 8 mm about 2 million (sparse); the queries are sphere-sized and larger.
TEST(SurfaceGrid, QueriesMatchBruteForceOnATiltedDrumInDenseAndSparseRows) {
  const Surface drum = make_cylinder({0.1, 0.2, 0.3}, {1, 2, 3}, 0.4, 0.9, 40, true);
  for (const double cell : {0.05, 0.008}) {
    SCOPED_TRACE("cell " + std::to_string(cell));
    SurfaceGrid grid;
    grid.build(drum, cell);
    EXPECT_DOUBLE_EQ(grid.cell_size(), cell);
    EXPECT_EQ(grid.dense(), cell == 0.05);
    std::mt19937 random(11);
    std::uniform_real_distribution<double> coordinate(-0.6, 1.4), half(0.002, 0.15);
    for (int q = 0; q < 400; ++q) {
      const Vec3 centre{coordinate(random), coordinate(random), coordinate(random)};
      const double h = half(random);
      check_query(drum, grid, Aabb{centre - Vec3{h, h, h}, centre + Vec3{h, h, h}});
    }
    // On the wall itself (a rim vertex), where every query must find triangles.
    const Vec3 on_wall = drum.vertices[0], reach{0.004, 0.004, 0.004};  // m
    const Aabb at_wall{on_wall - reach, on_wall + reach};
    std::vector<std::uint32_t> found;
    grid.query(at_wall, found);
    EXPECT_FALSE(found.empty());
    check_query(drum, grid, at_wall);
  }
}

// A moving surface is re-gridded in the same object at every list rebuild, which keeps its
// buffers: a grid rebuilt after other meshes must answer exactly as a fresh one, dense (5 cm
// cells) and sparse (8 mm). The drum is turned by 0.3 rad between the builds.
TEST(SurfaceGrid, RebuiltGridAnswersAsAFreshOneInDenseAndSparseRows) {
  const Surface drum = make_cylinder({0.1, 0.2, 0.3}, {1, 2, 3}, 0.4, 0.9, 40, true);
  Surface turned = drum;
  const double c = std::cos(0.3), s = std::sin(0.3);
  for (Vec3& v : turned.vertices) v = Vec3{c * v.x - s * v.z, v.y, s * v.x + c * v.z};
  const Surface small = make_box({0, 0, 0}, {0.2, 0.2, 0.2}, 2);
  for (const double cell : {0.05, 0.008}) {
    SCOPED_TRACE("cell " + std::to_string(cell));
    SurfaceGrid reused, fresh;
    reused.build(drum, cell);
    reused.build(small, cell);
    reused.build(turned, cell);
    fresh.build(turned, cell);
    EXPECT_EQ(reused.dense(), fresh.dense());
    EXPECT_EQ(reused.occupied_cell_count(), fresh.occupied_cell_count());
    std::mt19937 random(5);
    std::uniform_real_distribution<double> coordinate(-0.6, 1.4), half(0.002, 0.15);
    std::vector<std::uint32_t> a, b;
    std::size_t nonempty = 0;
    for (int q = 0; q < 2000; ++q) {
      const Vec3 centre{coordinate(random), coordinate(random), coordinate(random)};
      const double h = half(random);
      const Aabb box{centre - Vec3{h, h, h}, centre + Vec3{h, h, h}};
      reused.query(box, a);
      fresh.query(box, b);
      ASSERT_EQ(a, b) << "query " << q;
      nonempty += !a.empty();
    }
    EXPECT_GT(nonempty, 100u);  // the queries do meet the drum
    check_query(turned, reused, Aabb{turned.vertices[7] - Vec3{0.01, 0.01, 0.01},
                                     turned.vertices[7] + Vec3{0.01, 0.01, 0.01}});
  }
}

TEST(SurfaceGrid, LargeSlantedTrianglesFoundInEveryCellTheyCross) {
  // Two triangles spanning 1 m with 1 cm cells: stored only along their plane.
  const Surface plane = make_plane({0, 0, 0}, {1, 1, 1}, 1.0, 1);
  SurfaceGrid grid;
  grid.build(plane, 0.01);
  EXPECT_LT(grid.occupied_cell_count(),
            60000u);  // a sheet (~1.7e4 cells), not its ~1e6-cell bounding-box volume
  std::vector<std::uint32_t> found;
  for (double s = -0.35; s <= 0.35; s += 0.01) {  // |p| ≤ 0.39 m: inside the square
    // Points on the plane: p = s·u + s·v/2 with u ⟂ v ⟂ (1,1,1).
    const Vec3 u = normalized(Vec3{1, -1, 0}), v = normalized(Vec3{1, 1, -2});
    const Vec3 p = u * s + v * (0.5 * s);
    grid.query(Aabb{p - Vec3{1e-3, 1e-3, 1e-3}, p + Vec3{1e-3, 1e-3, 1e-3}}, found);
    EXPECT_FALSE(found.empty()) << "s = " << s;
  }
}

TEST(SurfaceGrid, HugeCellCountIsCappedByCoarsening) {
  const Surface box = make_box({0, 0, 0}, {100, 100, 100}, 2);
  SurfaceGrid grid;
  grid.build(box, 1e-3);  // would be 1e15 cells
  EXPECT_GT(grid.cell_size(), 1e-3);
  const double cells_per_axis = std::floor(100.0 / grid.cell_size()) + 1;
  EXPECT_LE(cells_per_axis * cells_per_axis * cells_per_axis,
            static_cast<double>(SurfaceGrid::max_cells));
  check_query(box, grid, Aabb{{-1, -1, -1}, {3, 3, 3}});
  check_query(box, grid, Aabb{{40, 40, 99}, {41, 41, 101}});
}

TEST(SurfaceGrid, HundredThousandTrianglesBuildAndQueryCorrectly) {
  const Surface plane = make_plane({0, 0, 0}, {0, 0, 1}, 1.0, 224);  // 100,352 triangles
  SurfaceGrid grid;
  grid.build(plane, 0.01);
  std::vector<std::uint32_t> found;
  // A sphere-sized box (radius 5 mm) around a point in the plate touches a handful of triangles.
  grid.query(Aabb{{0.1 - 0.005, 0.2 - 0.005, -0.005}, {0.1 + 0.005, 0.2 + 0.005, 0.005}}, found);
  EXPECT_GT(found.size(), 4u);
  EXPECT_LT(found.size(), 40u);
  check_query(plane, grid, Aabb{{-0.3, 0.1, -0.01}, {-0.28, 0.13, 0.01}});
  grid.query(Aabb{{0, 0, 0.5}, {0.1, 0.1, 0.6}}, found);  // above the plate: outside the grid
  EXPECT_TRUE(found.empty());
}

// Answers stay ascending and unique whatever their length: query() keeps a short answer sorted
// as it goes (most answers: none or a few triangles) and past 32 collects and sorts. Boxes from
// within one cell to hundreds of triangles, each checked as check_query does.
TEST(SurfaceGrid, AnswersOfAnyLengthAreAscendingAndUnique) {
  const Surface plane = make_plane({0, 0, 0}, {0.3, 0.2, 1}, 1.0, 40);  // tilted: over many cells
  SurfaceGrid grid;
  grid.build(plane, 0.02);
  std::vector<std::uint32_t> found;
  std::size_t shortest = 1000, longest = 0;
  for (const double half : {0.001, 0.01, 0.03, 0.1, 0.3}) {
    for (int n = 0; n < 20; ++n) {
      const Vec3 centre{-0.4 + 0.04 * n, 0.3 - 0.03 * n, 0.001 * n};
      const Aabb box{centre - Vec3{half, half, half}, centre + Vec3{half, half, half}};
      check_query(plane, grid, box);
      grid.query(box, found);
      shortest = std::min(shortest, found.size());
      longest = std::max(longest, found.size());
    }
  }
  EXPECT_LE(shortest, 2u);
  EXPECT_GT(longest, 100u);  // the collecting path was taken
}

}  // namespace
}  // namespace quarry

namespace quarry {
namespace {

// The triangle of a flat surface that holds point p (on its plane), by barycentric coordinates.
std::uint32_t triangle_holding(const Surface& s, const Vec3& p) {
  for (std::uint32_t t = 0; t < s.triangle_count(); ++t) {
    const Vec3 &a = s.vertices[s.triangles[t][0]], &b = s.vertices[s.triangles[t][1]],
               &c = s.vertices[s.triangles[t][2]];
    const Vec3 n = cross(b - a, c - a);
    const double area2 = dot(n, n);
    const double u = dot(cross(c - b, p - b), n) / area2, v = dot(cross(a - c, p - c), n) / area2;
    if (u >= -1e-12 && v >= -1e-12 && u + v <= 1.0 + 1e-12) return t;
  }
  return ~0u;
}

// A grid clipped to a box bins only what lies inside it: a plane of side 100 m met by a 0.2 m box
// occupies a sheet of the box's cells, not 2²⁴ cells of the whole plane (issue 19: 17.7 s and
// 724 MB in `check`), and every query inside the box finds the triangle under its centre.
TEST(SurfaceGrid, ClippedGridBinsOnlyWhatIsInsideAndFindsTheTriangles) {
  const Vec3 normal = normalized(Vec3{0.2, 0.1, 1.0});
  const Surface plane = make_plane({0, 0, 0}, normal, 100.0, 40);  // 3200 triangles
  const Aabb clip{{-0.1, -0.1, -0.1}, {0.1, 0.1, 0.2}};
  SurfaceGrid grid;
  grid.build(plane, 0.01, clip);
  EXPECT_DOUBLE_EQ(grid.cell_size(), 0.01);  // not coarsened to fit
  EXPECT_GT(grid.occupied_cell_count(), 0u);
  EXPECT_LE(grid.occupied_cell_count(), 4u * 21u * 21u);  // a sheet a few cells thick
  std::mt19937 random(3);
  std::uniform_real_distribution<double> at(-0.09, 0.09);
  std::vector<std::uint32_t> found;
  for (int q = 0; q < 200; ++q) {
    Vec3 c{at(random), at(random), 0.0};
    c.z = -(normal.x * c.x + normal.y * c.y) / normal.z;  // on the plane
    const Aabb box{c - Vec3{0.005, 0.005, 0.005}, c + Vec3{0.005, 0.005, 0.005}};
    grid.query(box, found);
    const std::uint32_t under = triangle_holding(plane, c);
    ASSERT_NE(under, ~0u);
    EXPECT_TRUE(std::binary_search(found.begin(), found.end(), under)) << "query " << q;
    check_query(plane, grid, box);
  }
}

// A triangle wholly outside the clip box is never returned; a surface wholly outside has no cells.
TEST(SurfaceGrid, SurfaceOutsideTheClipBoxHasNoCells) {
  const Surface plane = make_plane({0, 0, -10}, {0, 0, 1}, 1.0, 2);
  SurfaceGrid grid;
  grid.build(plane, 0.01, Aabb{{-0.1, -0.1, 0.0}, {0.1, 0.1, 0.3}});
  EXPECT_EQ(grid.occupied_cell_count(), 0u);
  std::vector<std::uint32_t> found;
  grid.query(Aabb{{-1, -1, -11}, {1, 1, 1}}, found);
  EXPECT_TRUE(found.empty());
}

}  // namespace
}  // namespace quarry
