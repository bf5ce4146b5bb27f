// Closed meshes as solids: the exact orientation sign against 128-bit integer arithmetic, the
// closure check (holes, orientation, repeated corners), and the inside test of a lattice — a
// cube on the cells (exact counts, also with rows through its edges and diagonals and centres on
// its faces), a sphere against its analytic inside, both orientations, and the union of two
// overlapping parts.
#include "geometry/closed_mesh.h"
#include "geometry/icosphere.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <map>
#include <numbers>
#include <random>

#include "geometry/primitives.h"

namespace quarry {
namespace {

using Triangles = std::vector<std::array<std::uint32_t, 3>>;
__extension__ typedef __int128 Int128;  // GCC's exact integer for the reference determinant

struct Mesh {
  std::vector<Vec3> vertices;
  Triangles triangles;
};

// The box [lo, hi], each face two triangles, normals outward. Vertex v has x = hi.x when bit 0 of
// v is set, y by bit 1, z by bit 2.
Mesh cube(const Vec3& lo, const Vec3& hi, std::uint32_t first_vertex = 0) {
  Mesh mesh;
  for (int v = 0; v < 8; ++v)
    mesh.vertices.push_back({(v & 1) ? hi.x : lo.x, (v & 2) ? hi.y : lo.y, (v & 4) ? hi.z : lo.z});
  const Triangles faces = {{0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}, {0, 1, 5}, {0, 5, 4},
                           {2, 6, 7}, {2, 7, 3}, {0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}};
  for (auto t : faces) mesh.triangles.push_back({t[0] + first_vertex, t[1] + first_vertex, t[2] + first_vertex});
  return mesh;
}

void flip(std::array<std::uint32_t, 3>& triangle) { std::swap(triangle[1], triangle[2]); }

// The sphere mesh of geometry/icosphere.h as this test's Mesh.
Mesh sphere_mesh(const Vec3& centre, double radius, int levels) {
  TriangleMesh sphere = quarry::icosphere(centre, radius, levels);
  Mesh mesh;
  mesh.vertices = std::move(sphere.vertices);
  mesh.triangles = std::move(sphere.triangles);
  return mesh;
}

std::size_t count_inside(const CellCentres& centres, const Mesh& mesh) {
  const MeshClosure closure = check_closure(mesh.vertices, mesh.triangles);
  EXPECT_TRUE(closure.closed());
  const std::vector<std::uint8_t> inside = mark_centres_inside(centres, mesh.vertices, mesh.triangles, closure);
  std::size_t n = 0;
  for (std::uint8_t b : inside) n += b;
  return n;
}

// The sign against exact 128-bit integer determinants: nearly collinear integer points (many of
// them exactly collinear: the sign must be 0), and the 256 x 256 points near (0.5, 0.5) of Kettner,
// Mehlhorn, Pion, Schirra & Yap (2008, Comput. Geom. 40:61-78, "Classroom examples of robustness
// problems") against q = (12, 12), r = (24, 24), where the rounded determinant has the wrong sign.
TEST(ClosedMesh, OrientationSignIsExact) {
  const auto sign_of = [](Int128 x) { return x > 0 ? 1 : (x < 0 ? -1 : 0); };
  const auto d = [](std::int64_t x) { return static_cast<double>(x); };
  std::mt19937_64 random(7);
  std::uniform_int_distribution<std::int64_t> coordinate(-(std::int64_t{1} << 40), std::int64_t{1} << 40);
  std::uniform_int_distribution<int> offset(-1, 1), step(-3, 3);
  int zeros = 0;
  for (int n = 0; n < 20000; ++n) {
    const std::int64_t au = coordinate(random) / 8, av = coordinate(random) / 8;
    const std::int64_t du = coordinate(random) / 64, dv = coordinate(random) / 64;
    const std::int64_t bu = au + du, bv = av + dv;
    const int k = step(random);
    const std::int64_t pu = au + k * du + offset(random), pv = av + k * dv + offset(random);
    const int expected =
        sign_of(static_cast<Int128>(bu - au) * (pv - av) - static_cast<Int128>(bv - av) * (pu - au));
    ASSERT_EQ(orientation_sign(d(au), d(av), d(bu), d(bv), d(pu), d(pv)), expected) << n;
    // Cyclic order keeps the sign, swapping two points flips it.
    ASSERT_EQ(orientation_sign(d(bu), d(bv), d(pu), d(pv), d(au), d(av)), expected) << n;
    ASSERT_EQ(orientation_sign(d(bu), d(bv), d(au), d(av), d(pu), d(pv)), -expected) << n;
    zeros += expected == 0;
  }
  EXPECT_GT(zeros, 1000);
  // Kettner et al.'s grid: coordinates 0.5 + i·2⁻⁵³ are exact; scaled by 2⁵³ they are integers.
  const double unit = 0x1p-53;
  const std::int64_t scale = std::int64_t{1} << 53;
  int naive_wrong = 0, collinear = 0;
  for (int i = 0; i < 256; ++i)
    for (int j = 0; j < 256; ++j) {
      const double au = 0.5 + i * unit, av = 0.5 + j * unit;
      const Int128 a_u = (scale >> 1) + i, a_v = (scale >> 1) + j, b = 12 * Int128{scale}, p = 24 * Int128{scale};
      const int expected = sign_of((b - a_u) * (p - a_v) - (b - a_v) * (p - a_u));
      ASSERT_EQ(orientation_sign(au, av, 12.0, 12.0, 24.0, 24.0), expected) << i << " " << j;
      const double naive = (12.0 - au) * (24.0 - av) - (12.0 - av) * (24.0 - au);
      naive_wrong += sign_of(naive > 0 ? 1 : (naive < 0 ? -1 : 0)) != expected;
      collinear += expected == 0;
    }
  std::printf("[ measured ] %d of 20000 integer triples exactly collinear; Kettner's grid: %d of 65536 "
              "collinear, the rounded determinant's sign wrong for %d\n",
              zeros, collinear, naive_wrong);
  EXPECT_GT(naive_wrong, 1000);  // the test tests: rounding alone would fail
}

TEST(ClosedMesh, ClosureFindsHolesOrientationAndRepeatedCorners) {
  Mesh box = cube({0, 0, 0}, {1, 2, 3});
  MeshClosure closure = check_closure(box.vertices, box.triangles);
  EXPECT_TRUE(closure.closed());
  EXPECT_TRUE(closure.consistently_oriented);

  Mesh open = box;
  open.triangles.resize(10);  // without the +z face: its four rim edges are used once
  closure = check_closure(open.vertices, open.triangles);
  EXPECT_EQ(closure.open_edges, 4u);
  EXPECT_FALSE(closure.closed());
  // The first open edge by position: from (0, 0, 3) to (0, 2, 3).
  EXPECT_EQ(closure.first_open_edge_midpoint, (Vec3{0, 1, 3}));

  Mesh turned = box;
  flip(turned.triangles[2]);
  flip(turned.triangles[3]);  // the +x face inward, the rest outward
  closure = check_closure(turned.vertices, turned.triangles);
  EXPECT_TRUE(closure.closed());
  EXPECT_FALSE(closure.consistently_oriented);

  // Every triangle with corners of its own (an unwelded STL): closed all the same.
  Mesh soup;
  for (const auto& t : box.triangles) {
    const auto first = static_cast<std::uint32_t>(soup.vertices.size());
    for (std::uint32_t corner : t) soup.vertices.push_back(box.vertices[corner]);
    soup.triangles.push_back({first, first + 1, first + 2});
  }
  closure = check_closure(soup.vertices, soup.triangles);
  EXPECT_TRUE(closure.closed());
  EXPECT_TRUE(closure.consistently_oriented);

  // The primitives: a box surface and a capped cylinder are closed (inward), a plane and an open
  // cylinder are not.
  const Surface walls = make_box({0, 0, 0}, {1, 1, 1}, 2);
  EXPECT_TRUE(check_closure(walls.vertices, walls.triangles).closed());
  const Surface drum = make_cylinder({0, 0, 0}, {0, 0, 1}, 0.3, 0.7, 24, true);
  EXPECT_TRUE(check_closure(drum.vertices, drum.triangles).closed());
  EXPECT_TRUE(check_closure(drum.vertices, drum.triangles).consistently_oriented);
  const Surface pipe = make_cylinder({0, 0, 0}, {0, 0, 1}, 0.3, 0.7, 24, false);
  EXPECT_EQ(check_closure(pipe.vertices, pipe.triangles).open_edges, 48u);
  const Surface plane = make_plane({0, 0, 0}, {0, 0, 1}, 1.0, 1);
  EXPECT_EQ(check_closure(plane.vertices, plane.triangles).open_edges, 4u);
}

// A cube whose faces lie on cell faces: exactly the 4 x 4 x 4 cells inside. Rows with y = z run
// through the diagonals of its x faces (the tie that Simulation of Simplicity breaks), so a
// rounded test would miss or double some crossings.
TEST(ClosedMesh, CubeOnTheCellsHoldsExactlyItsCells) {
  const CellCentres centres{{0, 0, 0}, {0.1, 0.1, 0.1}, {10, 10, 10}};
  const Mesh box = cube({0.2, 0.2, 0.2}, {0.6, 0.6, 0.6});
  const MeshClosure closure = check_closure(box.vertices, box.triangles);
  const std::vector<std::uint8_t> inside = mark_centres_inside(centres, box.vertices, box.triangles, closure);
  std::size_t count = 0;
  for (int k = 0; k < 10; ++k)
    for (int j = 0; j < 10; ++j)
      for (int i = 0; i < 10; ++i) {
        const bool expected = i >= 2 && i <= 5 && j >= 2 && j <= 5 && k >= 2 && k <= 5;
        EXPECT_EQ(inside[static_cast<std::size_t>(i + 10 * (j + 10 * k))], expected ? 1 : 0) << i << " " << j << " " << k;
        count += inside[static_cast<std::size_t>(i + 10 * (j + 10 * k))];
      }
  EXPECT_EQ(count, 64u);
  // Inward normals (the non-zero rule counts winding −1 as solid), and a mesh with one face
  // turned (even-odd): the same cells.
  Mesh inward = box;
  for (auto& t : inward.triangles) flip(t);
  EXPECT_EQ(count_inside(centres, inward), 64u);
  Mesh mixed = box;
  flip(mixed.triangles[4]);
  flip(mixed.triangles[5]);
  EXPECT_EQ(count_inside(centres, mixed), 64u);
  // Shifted by a whole number of cells and seen on a grid whose origin is not 0.
  const CellCentres shifted{{-0.3, 0.1, -1.0}, {0.1, 0.1, 0.1}, {12, 9, 20}};
  EXPECT_EQ(count_inside(shifted, box), 64u);
}

// Centres exactly on the cube's faces and rows exactly along its edges (binary-exact
// coordinates): the documented rule, the point moved to (x − δ, y + ε, z + ε²), takes the centres
// on the high x face and on the low y and z faces, so 2 of the 3 centres per axis count.
TEST(ClosedMesh, CentresOnTheSurfaceFollowTheTieRule) {
  const CellCentres centres{{0, 0, 0}, {0.25, 0.25, 0.25}, {4, 4, 4}};  // centres 0.125 + 0.25 i
  const Mesh box = cube({0.125, 0.125, 0.125}, {0.625, 0.625, 0.625});
  const MeshClosure closure = check_closure(box.vertices, box.triangles);
  const std::vector<std::uint8_t> inside = mark_centres_inside(centres, box.vertices, box.triangles, closure);
  for (int k = 0; k < 4; ++k)
    for (int j = 0; j < 4; ++j)
      for (int i = 0; i < 4; ++i) {
        const bool expected = (i == 1 || i == 2) && (j == 0 || j == 1) && (k == 0 || k == 1);
        EXPECT_EQ(inside[static_cast<std::size_t>(i + 4 * (j + 4 * k))], expected ? 1 : 0) << i << " " << j << " " << k;
      }
}

// A sphere of radius 0.3 m as an icosphere of 1280 triangles (its faces up to 0.6 % inside the
// sphere) on 40³ cells of 2 cm: every centre clearly inside or outside is classified as the
// sphere says, and the cells' volume is the polyhedron's to within the cells cut by its surface.
TEST(ClosedMesh, SphereMatchesItsAnalyticInside) {
  const double radius = 0.3, cell = 0.02;
  const Vec3 centre{0.401, 0.397, 0.403};  // off the lattice: no symmetric ties
  const Mesh sphere = sphere_mesh(centre, radius, 3);
  const CellCentres centres{{0, 0, 0}, {cell, cell, cell}, {40, 40, 40}};
  const MeshClosure closure = check_closure(sphere.vertices, sphere.triangles);
  ASSERT_TRUE(closure.closed());
  ASSERT_TRUE(closure.consistently_oriented);
  const std::vector<std::uint8_t> inside = mark_centres_inside(centres, sphere.vertices, sphere.triangles, closure);
  // The polyhedron lies between the sphere and the sphere of its smallest face-centre distance.
  double inner = radius;
  double volume = 0.0;  // m³, divergence theorem over the faces
  for (const auto& t : sphere.triangles) {
    const Vec3 a = sphere.vertices[t[0]] - centre, b = sphere.vertices[t[1]] - centre, c = sphere.vertices[t[2]] - centre;
    const Vec3 normal = cross(b - a, c - a);
    inner = std::min(inner, dot(a, normal) / std::sqrt(dot(normal, normal)));
    volume += dot(a, cross(b, c)) / 6.0;
  }
  std::size_t count = 0, ambiguous = 0;
  for (int k = 0; k < 40; ++k)
    for (int j = 0; j < 40; ++j)
      for (int i = 0; i < 40; ++i) {
        const Vec3 x{(i + 0.5) * cell, (j + 0.5) * cell, (k + 0.5) * cell};
        const double r = std::sqrt(dot(x - centre, x - centre));
        const std::uint8_t flag = inside[static_cast<std::size_t>(i + 40 * (j + 40 * k))];
        count += flag;
        if (r < inner) EXPECT_EQ(flag, 1) << i << " " << j << " " << k;
        else if (r > radius) EXPECT_EQ(flag, 0) << i << " " << j << " " << k;
        else ++ambiguous;
      }
  const double cells_volume = static_cast<double>(count) * cell * cell * cell;
  std::printf("[ measured ] %zu cells inside (%.6g m³), polyhedron %.6g m³, sphere %.6g m³; %zu centres between "
              "the polyhedron's inner and outer spheres (r %.5g to %.5g m)\n",
              count, cells_volume, volume, 4.0 / 3.0 * std::numbers::pi * std::pow(radius, 3), ambiguous, inner, radius);
  EXPECT_GT(inner, 0.99 * radius);
  EXPECT_NEAR(cells_volume / volume, 1.0, 0.01);
  // Inward normals: the same cells.
  Mesh inward = sphere;
  for (auto& t : inward.triangles) flip(t);
  const MeshClosure inward_closure = check_closure(inward.vertices, inward.triangles);
  EXPECT_EQ(mark_centres_inside(centres, inward.vertices, inward.triangles, inward_closure), inside);
}

// Two overlapping closed parts in one mesh: consistently oriented, the non-zero rule gives their
// union (4·4·4 + 4·4·4 − 2·4·4 shared = 96 cells); with one part's face turned the mesh is read
// even-odd and the overlap, inside both, counts as outside (64).
TEST(ClosedMesh, OverlappingPartsAreAUnionWhenConsistentlyOriented) {
  const CellCentres centres{{0, 0, 0}, {0.1, 0.1, 0.1}, {10, 10, 10}};
  Mesh parts = cube({0.2, 0.2, 0.2}, {0.6, 0.6, 0.6});
  const Mesh second = cube({0.4, 0.2, 0.2}, {0.8, 0.6, 0.6}, 8);
  parts.vertices.insert(parts.vertices.end(), second.vertices.begin(), second.vertices.end());
  parts.triangles.insert(parts.triangles.end(), second.triangles.begin(), second.triangles.end());
  EXPECT_EQ(count_inside(centres, parts), 96u);
  flip(parts.triangles[12]);
  flip(parts.triangles[13]);
  EXPECT_EQ(count_inside(centres, parts), 64u);
}

}  // namespace
}  // namespace quarry
