// Tests of the primitive meshes against closed forms: counts (Euler's formula for closed
// meshes), areas, orientation, and enclosed volume by the divergence theorem.
#include "geometry/primitives.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "core/diagnostics.h"
#include "geometry/mesh_topology.h"

namespace quarry {
namespace {

double total_area(const Surface& s) {
  double area = 0.0;
  for (double a : s.triangle_areas) area += a;
  return area;
}

Vec3 centroid(const Surface& s, std::size_t t) {
  return (s.vertices[s.triangles[t][0]] + s.vertices[s.triangles[t][1]] +
          s.vertices[s.triangles[t][2]]) /
         3.0;
}

// Divergence theorem: V = (1/3) Σ (x_centroid · n) A over a closed surface with OUTWARD normals
// (exact for flat triangles since x · n is constant on each). Inward normals give −V.
double signed_volume(const Surface& s) {
  double volume = 0.0;
  for (std::size_t t = 0; t < s.triangle_count(); ++t)
    volume += dot(centroid(s, t), s.triangle_normals[t]) * s.triangle_areas[t] / 3.0;
  return volume;
}

// Closed 2-manifold: every edge has exactly two triangles, and V − E + F = 2 (sphere topology).
void expect_closed(const Surface& s) {
  const MeshTopology topology = build_topology(s);
  for (std::uint32_t e = 0; e < topology.edge_count(); ++e)
    ASSERT_EQ(topology.triangles_of_edge(e).size(), 2u);
  EXPECT_EQ(static_cast<long>(s.vertex_count()) - static_cast<long>(topology.edge_count()) +
                static_cast<long>(s.triangle_count()),
            2);
}

TEST(Primitives, PlaneIsAFlatSquareFacingItsNormal) {
  const Vec3 point{1, -2, 0.5};
  const Vec3 normal{1, 2, 2};  // length 3
  const Surface plane = make_plane(point, normal, 0.6, 5);
  EXPECT_EQ(plane.triangle_count(), 50u);
  EXPECT_EQ(plane.vertex_count(), 36u);
  EXPECT_NEAR(total_area(plane), 0.36, 1e-14);
  Vec3 mean;
  for (const Vec3& x : plane.vertices) {
    EXPECT_NEAR(dot(x - point, normal / 3.0), 0.0, 1e-14);
    mean += x / 36.0;
  }
  EXPECT_NEAR(norm(mean - point), 0.0, 1e-14);
  for (std::size_t t = 0; t < plane.triangle_count(); ++t) {
    EXPECT_NEAR(norm(plane.triangle_normals[t] - normal / 3.0), 0.0, 1e-15);
    // The right-hand rule of the stored vertex order agrees with the reported normal.
    const auto& tri = plane.triangles[t];
    EXPECT_GT(dot(cross(plane.vertices[tri[1]] - plane.vertices[tri[0]],
                        plane.vertices[tri[2]] - plane.vertices[tri[0]]),
                  normal),
              0.0);
  }
}

TEST(Primitives, BoxIsClosedWithInwardNormals) {
  const Vec3 lo{-1, 0, 2}, hi{1, 0.5, 2.25};
  const Surface box = make_box(lo, hi, 3);
  EXPECT_EQ(box.triangle_count(), 12u * 9u);
  EXPECT_EQ(box.vertex_count(), 6u * 9u + 2u);  // Euler: V = 6d² + 2
  expect_closed(box);
  EXPECT_NEAR(total_area(box), 2.0 * (2 * 0.5 + 0.5 * 0.25 + 2 * 0.25), 1e-13);
  EXPECT_NEAR(signed_volume(box), -(2 * 0.5 * 0.25), 1e-13);  // inward: −V
  const Vec3 middle = (lo + hi) / 2.0;
  for (std::size_t t = 0; t < box.triangle_count(); ++t)
    EXPECT_GT(dot(box.triangle_normals[t], middle - centroid(box, t)), 0.0);
}

TEST(Primitives, OpenCylinderHasThePolygonPrismSideArea) {
  const int segments = 24;
  const double radius = 0.3, length = 1.1;
  const Surface side = make_cylinder({0, 0, 0}, {0, 0, 5}, radius, length, segments, false);
  // Side of the inscribed prism: segments · chord · length, chord = 2R sin(π/segments).
  EXPECT_NEAR(total_area(side),
              segments * 2 * radius * std::sin(std::numbers::pi / segments) * length, 1e-12);
  for (std::size_t t = 0; t < side.triangle_count(); ++t) {
    const Vec3 c = centroid(side, t);
    EXPECT_LT(dot(side.triangle_normals[t], Vec3{c.x, c.y, 0}), 0.0);  // towards the axis
  }
  for (const Vec3& x : side.vertices) EXPECT_NEAR(std::hypot(x.x, x.y), radius, 1e-15);
}

TEST(Primitives, CappedCylinderEnclosesThePrismVolumeInBothOrientations) {
  const int segments = 20;
  const double radius = 0.25, length = 0.8;
  const Vec3 base{0.5, -0.2, 1.0}, axis{1, 1, 0};
  // Inscribed regular polygon area (segments/2) R² sin(2π/segments) times the length.
  const double volume =
      0.5 * segments * radius * radius * std::sin(2 * std::numbers::pi / segments) * length;
  const Surface inward = make_cylinder(base, axis, radius, length, segments, true, true);
  const Surface outward = make_cylinder(base, axis, radius, length, segments, true, false);
  expect_closed(inward);
  expect_closed(outward);
  // Volume is translation invariant for a closed surface, so the offset base does not matter.
  EXPECT_NEAR(signed_volume(inward), -volume, 1e-12);
  EXPECT_NEAR(signed_volume(outward), volume, 1e-12);
  const Vec3 middle = base + normalized(axis) * (length / 2);
  for (std::size_t t = 0; t < inward.triangle_count(); ++t)
    EXPECT_GT(dot(inward.triangle_normals[t], middle - centroid(inward, t)), 0.0);
}

TEST(Primitives, InvalidArgumentsAreUserErrors) {
  EXPECT_THROW(make_plane({}, {0, 0, 0}, 1.0), UserError);
  EXPECT_THROW(make_plane({}, {0, 0, 1}, -1.0), UserError);
  EXPECT_THROW(make_box({0, 0, 0}, {1, 0, 1}), UserError);
  EXPECT_THROW(make_cylinder({}, {0, 0, 1}, 1.0, 1.0, 2, false), UserError);
  EXPECT_THROW(make_cylinder({}, {0, 0, 0}, 1.0, 1.0, 8, false), UserError);
}

}  // namespace
}  // namespace quarry

namespace quarry {
namespace {

// The count the memory estimate uses is the count make_cylinder makes, for short, long, thin and
// fat cylinders, open and capped.
TEST(Primitives, CylinderTriangleCountIsTheCountMade) {
  struct Case {
    double radius, length;
    int segments;
  };
  for (const Case c :
       {Case{0.3, 0.6, 48}, Case{0.01, 2.0, 3}, Case{1.0, 0.01, 200}, Case{0.5, 0.5, 7}})
    for (const bool capped : {false, true})
      EXPECT_EQ(cylinder_triangle_count(c.radius, c.length, c.segments, capped),
                static_cast<std::int64_t>(
                    make_cylinder({0, 0, 0}, {0, 0, 1}, c.radius, c.length, c.segments, capped)
                        .triangle_count()))
          << c.radius << " " << c.length << " " << c.segments << " " << capped;
}

}  // namespace
}  // namespace quarry
