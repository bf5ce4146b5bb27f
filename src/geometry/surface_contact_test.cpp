// Tests of sphere–mesh contact detection. Closed forms: a sphere of radius R whose centre is at
// height h above a flat plate overlaps it by R − h along the plate normal, wherever it is over
// the plate (so a tessellated plate must give exactly one contact everywhere, DESIGN.md §5);
// distances to a box's edges/corners and to a regular polygon prism are elementary geometry.
#include "geometry/surface_contact.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <numeric>
#include <random>

#include "geometry/primitives.h"
#include "geometry/surface_grid.h"

namespace quarry {
namespace {

std::vector<std::uint32_t> all_triangles(const Surface& s) {
  std::vector<std::uint32_t> all(s.triangle_count());
  std::iota(all.begin(), all.end(), 0u);
  return all;
}

// Every contact's point is the weighted sum of its owning triangle's vertices, weights sum 1.
void expect_consistent_weights(const Surface& s, const SurfaceContact& c) {
  const auto& tri = s.triangles[c.triangle];
  EXPECT_NEAR(c.weights[0] + c.weights[1] + c.weights[2], 1.0, 1e-12);
  const Vec3 from_weights =
      s.vertices[tri[0]] * c.weights[0] + s.vertices[tri[1]] * c.weights[1] + s.vertices[tri[2]] * c.weights[2];
  EXPECT_NEAR(norm(from_weights - c.point), 0.0, 1e-12);
}

struct Plate {
  Vec3 point{0.3, -0.2, 0.7};  // m, deliberately off the origin
  Vec3 normal = normalized(Vec3{1, 2, 2});
  Surface surface = make_plane(point, normal, 1.0, 10);
  MeshTopology topology = build_topology(surface);
  std::vector<std::uint32_t> candidates = all_triangles(surface);
};

constexpr double sphere_radius = 0.05;  // m
constexpr double height = 0.04;         // m, centre above the plate: overlap 0.01 m

void expect_one_plate_contact(const Plate& plate, const Vec3& foot, double side, ContactFeature feature) {
  const Vec3 centre = foot + plate.normal * (side * height);
  std::vector<SurfaceContact> contacts;
  find_surface_contacts(plate.surface, plate.topology, centre, sphere_radius, plate.candidates, contacts);
  ASSERT_EQ(contacts.size(), 1u);
  const SurfaceContact& c = contacts[0];
  EXPECT_EQ(c.feature, feature);
  EXPECT_NEAR(norm(c.normal - plate.normal * side), 0.0, 1e-12);
  EXPECT_NEAR(c.overlap, sphere_radius - height, 1e-12);
  EXPECT_NEAR(norm(c.point - foot), 0.0, 1e-12);
  expect_consistent_weights(plate.surface, c);
}

TEST(SurfaceContact, FlatPlateFaceInteriorGivesOneFaceContact) {
  const Plate plate;
  const auto& tri = plate.surface.triangles[37];
  const Vec3 foot = (plate.surface.vertices[tri[0]] + plate.surface.vertices[tri[1]] + plate.surface.vertices[tri[2]]) / 3.0;
  expect_one_plate_contact(plate, foot, +1.0, ContactFeature::face);
}

TEST(SurfaceContact, FlatPlateExactlyOverASharedEdgeGivesOneEdgeContact) {
  const Plate plate;
  int interior_edges = 0;
  for (std::uint32_t e = 0; e < plate.topology.edge_count(); ++e) {
    if (plate.topology.triangles_of_edge(e).size() != 2) continue;
    ++interior_edges;
    const auto [a, b] = plate.topology.edges[e];
    const Vec3 foot = (plate.surface.vertices[a] + plate.surface.vertices[b]) * 0.5;
    expect_one_plate_contact(plate, foot, +1.0, ContactFeature::edge);
  }
  EXPECT_EQ(interior_edges, 2 * 10 * 9 + 100);  // grid lines inside + all diagonals
}

TEST(SurfaceContact, FlatPlateExactlyOverASixTriangleVertexGivesOneVertexContact) {
  const Plate plate;
  int six_triangle_vertices = 0;
  for (std::uint32_t v = 0; v < plate.surface.vertex_count(); ++v) {
    if (plate.topology.triangles_of_vertex(v).size() != 6) continue;
    ++six_triangle_vertices;
    const Vec3 foot = plate.surface.vertices[v];
    expect_one_plate_contact(plate, foot, +1.0, ContactFeature::vertex);
    std::vector<SurfaceContact> contacts;
    find_surface_contacts(plate.surface, plate.topology, foot + plate.normal * height, sphere_radius,
                          plate.candidates, contacts);
    const SurfaceContact& c = contacts.at(0);
    EXPECT_EQ(c.feature_index, v);
    double weight_on_vertex = 0.0;
    for (int k = 0; k < 3; ++k)
      if (plate.surface.triangles[c.triangle][k] == v) weight_on_vertex = c.weights[k];
    EXPECT_EQ(weight_on_vertex, 1.0);
    EXPECT_EQ(c.triangle, plate.topology.triangles_of_vertex(v)[0]);  // lowest incident triangle
  }
  EXPECT_EQ(six_triangle_vertices, 81);  // the 9 × 9 interior vertices
}

TEST(SurfaceContact, ThinPlateTouchedFromBelowGivesOneContactAlongMinusNormal) {
  const Plate plate;
  const auto& tri = plate.surface.triangles[12];
  const Vec3 face_foot = (plate.surface.vertices[tri[0]] + plate.surface.vertices[tri[1]] * 2.0 + plate.surface.vertices[tri[2]]) / 4.0;
  expect_one_plate_contact(plate, face_foot, -1.0, ContactFeature::face);
  expect_one_plate_contact(plate, plate.surface.vertices[tri[1]], -1.0, ContactFeature::vertex);
}

TEST(SurfaceContact, SphereRollingAcrossSeamsAlwaysFeelsExactlyOneContact) {
  const Plate plate;
  SurfaceGrid grid;
  grid.build(plate.surface, 2.0 * sphere_radius);
  // In-plane frame of the plate (any orthonormal pair ⟂ normal).
  const Vec3 u = normalized(cross(plate.normal, Vec3{0, 0, 1})), v = cross(plate.normal, u);
  std::vector<std::uint32_t> candidates;
  std::vector<SurfaceContact> contacts;
  auto check = [&](const Vec3& foot) {
    const Vec3 centre = foot + plate.normal * height;
    const Vec3 reach{sphere_radius, sphere_radius, sphere_radius};
    grid.query(Aabb{centre - reach, centre + reach}, candidates);
    find_surface_contacts(plate.surface, plate.topology, centre, sphere_radius, candidates, contacts);
    ASSERT_EQ(contacts.size(), 1u) << "foot " << foot.x << " " << foot.y << " " << foot.z;
    EXPECT_NEAR(norm(contacts[0].normal - plate.normal), 0.0, 1e-9);
    EXPECT_NEAR(contacts[0].overlap, sphere_radius - height, 1e-12);
  };
  // Straight paths in several directions, 4001 positions each (0.2 mm apart): they cross grid
  // lines and diagonals at arbitrary points.
  for (const double angle : {0.0, 0.3, std::numbers::pi / 4, 1.1, 2.0}) {
    const Vec3 direction = u * std::cos(angle) + v * std::sin(angle);
    for (int i = 0; i <= 4000; ++i) check(plate.point + direction * (-0.4 + 0.8 * i / 4000.0) + v * 0.013);
  }
  // Paths exactly along seams: every grid line and diagonal of the plate passes through its
  // vertices, so walk from each interior vertex to each of its neighbours.
  for (std::uint32_t e = 0; e < plate.topology.edge_count(); e += 3) {
    const auto [a, b] = plate.topology.edges[e];
    for (int i = 0; i <= 20; ++i)
      check(plate.surface.vertices[a] + (plate.surface.vertices[b] - plate.surface.vertices[a]) * (i / 20.0));
  }
  // Random positions.
  std::mt19937 random(11);
  std::uniform_real_distribution<double> coordinate(-0.3, 0.3);  // |offset| < 0.43 m: on the plate
  for (int i = 0; i < 5000; ++i) check(plate.point + u * coordinate(random) + v * coordinate(random));
}

TEST(SurfaceContact, NoContactWhenTheSphereIsClearOfThePlate) {
  const Plate plate;
  std::vector<SurfaceContact> contacts{SurfaceContact{}};
  find_surface_contacts(plate.surface, plate.topology, plate.point + plate.normal * 0.0501, sphere_radius,
                        plate.candidates, contacts);
  EXPECT_TRUE(contacts.empty());
}

struct UnitBox {
  Surface surface = make_box({0, 0, 0}, {1, 1, 1}, 4);
  MeshTopology topology = build_topology(surface);
  std::vector<std::uint32_t> candidates = all_triangles(surface);
  std::vector<SurfaceContact> contacts(const Vec3& centre, double radius) const {
    std::vector<SurfaceContact> out;
    find_surface_contacts(surface, topology, centre, radius, candidates, out);
    return out;
  }
};

TEST(SurfaceContact, ConcaveCornerOfABoxGivesOneFaceContactPerWall) {
  const UnitBox box;
  // Centre 0.03 m from the wall x = 0 and 0.04 m above the floor, away from every seam.
  auto two = box.contacts({0.03, 0.4, 0.04}, 0.05);
  ASSERT_EQ(two.size(), 2u);
  int seen = 0;
  for (const auto& c : two) {
    EXPECT_EQ(c.feature, ContactFeature::face);
    if (std::abs(c.normal.x - 1.0) < 1e-12) { EXPECT_NEAR(c.overlap, 0.02, 1e-12); seen |= 1; }
    if (std::abs(c.normal.z - 1.0) < 1e-12) { EXPECT_NEAR(c.overlap, 0.01, 1e-12); seen |= 2; }
  }
  EXPECT_EQ(seen, 3);
  // In the three-wall corner: three face contacts, overlaps R − distance to each wall.
  auto three = box.contacts({0.03, 0.04, 0.02}, 0.05);
  ASSERT_EQ(three.size(), 3u);
  double overlap_sum = 0.0;
  for (const auto& c : three) {
    EXPECT_EQ(c.feature, ContactFeature::face);
    overlap_sum += c.overlap;
  }
  EXPECT_NEAR(overlap_sum, 0.02 + 0.01 + 0.03, 1e-12);
}

TEST(SurfaceContact, ConvexEdgeOfABoxFromOutsideGivesOneEdgeContact) {
  const UnitBox box;
  const Vec3 centre{1.02, 0.4, 1.03};
  const auto contacts = box.contacts(centre, 0.05);
  ASSERT_EQ(contacts.size(), 1u);
  const SurfaceContact& c = contacts[0];
  EXPECT_EQ(c.feature, ContactFeature::edge);
  // Distance to the edge line x = z = 1: √(0.02² + 0.03²).
  const double distance = std::hypot(0.02, 0.03);
  EXPECT_NEAR(c.overlap, 0.05 - distance, 1e-12);
  EXPECT_NEAR(norm(c.point - Vec3{1, 0.4, 1}), 0.0, 1e-12);
  EXPECT_NEAR(norm(c.normal - Vec3{0.02, 0, 0.03} / distance), 0.0, 1e-12);
  expect_consistent_weights(box.surface, c);
}

TEST(SurfaceContact, ConvexCornerOfABoxFromOutsideGivesOneVertexContactWithUnitWeight) {
  const UnitBox box;
  const Vec3 centre{1.02, 1.03, 1.01};
  const auto contacts = box.contacts(centre, 0.05);
  ASSERT_EQ(contacts.size(), 1u);
  const SurfaceContact& c = contacts[0];
  EXPECT_EQ(c.feature, ContactFeature::vertex);
  EXPECT_EQ(box.surface.vertices[c.feature_index], (Vec3{1, 1, 1}));
  EXPECT_NEAR(c.overlap, 0.05 - norm(Vec3{0.02, 0.03, 0.01}), 1e-12);
  const auto& tri = box.surface.triangles[c.triangle];
  for (int k = 0; k < 3; ++k) EXPECT_EQ(c.weights[k], tri[k] == c.feature_index ? 1.0 : 0.0);
}

TEST(SurfaceContact, SphereAroundAFacetedPillarFeelsOneContactAtTheClosedFormDistance) {
  // Outward prism of n facets: in a facet's frame a point at polar (ρ, φ), |φ| ≤ π/n, is at
  // distance ρ cos φ − a from the facet (a = R cos(π/n), the apothem) while its tangential
  // offset ρ sin φ is within the half-chord R sin(π/n); beyond that the corner is nearest.
  const int n = 12;
  const double pillar_radius = 0.3, ball = 0.05;
  const Surface pillar = make_cylinder({0, 0, 0}, {0, 0, 1}, pillar_radius, 1.0, n, true, false);
  const MeshTopology topology = build_topology(pillar);
  const auto candidates = all_triangles(pillar);
  const double apothem = pillar_radius * std::cos(std::numbers::pi / n);
  const double half_chord = pillar_radius * std::sin(std::numbers::pi / n);
  std::vector<SurfaceContact> contacts;
  for (int i = 0; i < 2000; ++i) {
    const double angle = 2.0 * std::numbers::pi * i / 2000.0;
    const double rho = apothem + 0.035;  // m, centre distance from the axis
    const Vec3 centre{rho * std::cos(angle), rho * std::sin(angle), 0.55};
    find_surface_contacts(pillar, topology, centre, ball, candidates, contacts);
    // Facet k faces the direction of its centre; the frame u, v of make_cylinder starts at some
    // angle, so find the nearest facet direction from the vertices instead of assuming one.
    double best_distance = 1e300;
    for (int k = 0; k < n; ++k) {
      const Vec3& a = pillar.vertices[0];
      const double start = std::atan2(a.y, a.x);
      const double facet_angle = start + 2.0 * std::numbers::pi * (k + 0.5) / n;
      const double phi = std::remainder(angle - facet_angle, 2.0 * std::numbers::pi);
      if (std::abs(phi) > std::numbers::pi / n + 1e-12) continue;
      const double tangential = rho * std::sin(phi), normal = rho * std::cos(phi);
      best_distance = std::abs(tangential) <= half_chord
                          ? normal - apothem
                          : std::hypot(normal - apothem, std::abs(tangential) - half_chord);
    }
    ASSERT_EQ(contacts.size(), 1u) << "angle " << angle;
    EXPECT_NEAR(contacts[0].overlap, ball - best_distance, 1e-12) << "angle " << angle;
  }
}

// The triangles' bounds (a disc of the sphere in each triangle's plane against the triangle's
// reach from its centroid) only skip triangles that no point of within R: the contacts are those
// found without them (every candidate's closest point computed), for spheres of every size
// against a box and a faceted pillar with caps, wherever they stand, and for spheres that just
// reach a vertex, an edge's midpoint or a face's centre (overlap a part in 10⁹ of R).
TEST(SurfaceContact, TheTrianglesBoundsSkipOnlyTrianglesOutOfReach) {
  std::mt19937_64 random(20261204);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (const Surface& bounded : {make_box({0, 0, 0}, {1, 1, 1}, 4),
                                 make_cylinder({0.5, 0.5, 0}, {0, 0, 1}, 0.4, 1.0, 24, true, true)}) {
    ASSERT_EQ(bounded.triangle_reach.size(), bounded.triangle_count());
    Surface unbounded = bounded;
    unbounded.triangle_reach.clear();
    unbounded.triangle_centroids.clear();
    const MeshTopology topology = build_topology(bounded);
    const std::vector<std::uint32_t> candidates = all_triangles(bounded);
    std::vector<SurfaceContact> with, without;
    std::size_t touching = 0;
    const auto compare = [&](const Vec3& centre, double radius) {
      find_surface_contacts(bounded, topology, centre, radius, candidates, with);
      find_surface_contacts(unbounded, topology, centre, radius, candidates, without);
      ASSERT_EQ(with.size(), without.size()) << "centre " << centre.x << " " << centre.y << " " << centre.z;
      for (std::size_t k = 0; k < with.size(); ++k) {
        EXPECT_EQ(with[k].triangle, without[k].triangle);
        EXPECT_EQ(with[k].feature, without[k].feature);
        EXPECT_EQ(with[k].feature_index, without[k].feature_index);
        EXPECT_EQ(with[k].overlap, without[k].overlap);
      }
      touching += !with.empty();
    };
    for (int n = 0; n < 4000; ++n) {
      const Vec3 centre{1.4 * unit(random) - 0.2, 1.4 * unit(random) - 0.2, 1.4 * unit(random) - 0.2};  // m
      compare(centre, 0.3 * std::pow(10.0, -3.0 * unit(random)));  // 0.3 mm to 0.3 m
    }
    for (std::size_t t = 0; t < bounded.triangle_count(); ++t) {
      const auto& tri = bounded.triangles[t];
      const Vec3 a = bounded.vertices[tri[0]], b = bounded.vertices[tri[1]], c = bounded.vertices[tri[2]];
      for (const Vec3& target : {a, (a + b) / 2.0, (a + b + c) / 3.0}) {
        const double radius = 0.01 + 0.05 * unit(random);  // m
        const Vec3 away = normalized(Vec3{unit(random) - 0.5, unit(random) - 0.5, unit(random) - 0.5});
        compare(target + away * (radius * (1.0 - 1e-9)), radius);
      }
    }
    EXPECT_GT(touching, 1000u);  // the comparison saw contacts, not only misses
  }
}

}  // namespace
}  // namespace quarry
