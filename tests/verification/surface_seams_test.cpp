// Verification 03/04 — surfaces done right (DESIGN §5): a sphere touching a flat tessellated
// surface feels exactly one contact wherever it is (face, shared edge, shared vertex), so
//  03: a sphere rolling across a plate of many triangles carries a constant normal force
//      (its weight, by vertical equilibrium at rest in z) across every seam;
//  04: a sphere resting on a vertex shared by six coplanar triangles carries exactly its weight,
//      all of it assigned to that vertex (barycentric weight 1).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <numbers>

#include "geometry/primitives.h"
#include "geometry/stl_reader.h"
#include "sim/exchange.h"
#include "verification/test_support.h"

namespace quarry {
namespace {

using testing_support::start_world;

// A deck-free spec: one steel sphere type, one STL surface, no factories (particles are
// placed by the test). Softish material so that the equilibrium overlap is resolved.
SimulationSpec sphere_on_surface_spec(const std::string& stl_path, double end_time) {
  SimulationSpec spec;
  spec.simulation.end_time = end_time;
  spec.simulation.fixed_time_step = Located<double>(2e-6);
  spec.simulation.impact_speed = Located<double>(0.5);
  Aabb domain;
  domain.lo = {-1, -1, -1};
  domain.hi = {1, 1, 1};
  spec.simulation.domain = domain;
  MaterialSpec steel;
  steel.name = std::string("steel");
  steel.density = 7800.0;
  steel.youngs_modulus = 1e8;
  steel.poisson_ratio = 0.3;
  spec.materials = {steel};
  InteractionSpec inter;
  inter.material_a = std::string("steel");
  inter.material_b = std::string("steel");
  inter.restitution = 0.2;
  inter.static_friction = 0.5;
  spec.interactions = {inter};
  ParticleTypeSpec type;
  type.name = std::string("ball");
  type.material = std::string("steel");
  type.size.kind = SizeDistributionKind::fixed;
  type.size.radius = 0.005;
  spec.particle_types = {type};
  SurfaceSpec surface;
  surface.name = std::string("plate");
  surface.kind = SurfaceKind::stl;
  surface.file = stl_path;
  surface.material = std::string("steel");
  spec.surfaces = {surface};
  return spec;
}

// Equilibrium overlap of a sphere of mass m resting on a flat wall: m g = 4/3 E* √R δ^{3/2}
// (Hertz, Johnson 1985 eq. 4.22) → δ = (3 m g / (4 E* √R))^{2/3}. E* = E / (2 (1 − ν²)) for two
// equal materials, the wall with infinite radius.
double resting_overlap(double mass, double radius, double youngs, double poisson) {
  const double effective_youngs = youngs / (2.0 * (1.0 - poisson * poisson));
  return std::pow(3.0 * mass * 9.81 / (4.0 * effective_youngs * std::sqrt(radius)), 2.0 / 3.0);
}

TEST(Verification, RollingAcrossSeamsKeepsNormalForceConstant) {
  const std::string stl = ::testing::TempDir() + "quarry_seam_plate.stl";
  // 0.1 m plate in 10 × 10 squares of 2 triangles: the ball crosses 10 square seams and the
  // diagonals of the squares while rolling 60 mm.
  write_stl_binary(stl, make_plane({0.05, 0.0, 0.0}, {0, 0, 1}, 0.1, 10));
  const SimulationSpec spec = sphere_on_surface_spec(stl, 0.06);
  World world = build_world(spec);
  const double radius = 0.005;
  const double mass = 7800.0 * 4.0 / 3.0 * std::numbers::pi * std::pow(radius, 3);  // kg
  const double overlap = resting_overlap(mass, radius, 1e8, 0.3);
  const double speed = 1.0;  // m/s along x; ω = v/R about −y... rolling without slip: ω_y = v/R
  sim::NewParticle ball;
  ball.position = {0.02, 0.00317, radius - overlap};
  ball.velocity = {speed, 0, 0};
  ball.angular_velocity = {0, speed / radius, 0};
  ball.radius = radius;
  sim::add_particles(world, std::span(&ball, 1));
  sim::initialize(world);
  const double weight = mass * 9.81;  // N
  double worst = 0.0;
  int steps = 0;
  while (world.time < 0.06) {
    sim::step(world);
    ++steps;
    ASSERT_EQ(world.wall_contact_count(), 1u) << "at x = " << world.particles.position[0].x;
    worst = std::max(worst, std::abs(-world.surfaces[0].mesh.total_force.z / weight - 1.0));
  }
  EXPECT_GT(world.particles.position[0].x, 0.075);  // it crossed many seams
  // Started at the Hertz equilibrium with no vertical speed: the normal force stays the weight.
  // The only disturbance is the integration error of the resting spring, O((ω dt)²) ~ 1e-4.
  EXPECT_LT(worst, 1e-3) << "largest relative deviation of the normal force from the weight";
  EXPECT_GT(steps, 10000);
}

TEST(Verification, SphereOnVertexOfSixTrianglesCarriesItsWeight) {
  // A hexagonal fan: centre vertex shared by six coplanar triangles (normals +z).
  Surface fan;
  fan.vertices.push_back({0, 0, 0});
  for (int k = 0; k < 6; ++k) {
    const double a = std::numbers::pi / 3.0 * k;
    fan.vertices.push_back({0.03 * std::cos(a), 0.03 * std::sin(a), 0.0});
  }
  for (std::uint32_t k = 0; k < 6; ++k) fan.triangles.push_back({0, 1 + k, 1 + (k + 1) % 6});
  fan.reference_vertices = fan.vertices;
  fan.update_normals_and_areas();
  const std::string stl = ::testing::TempDir() + "quarry_vertex_fan.stl";
  write_stl_binary(stl, fan);

  const SimulationSpec spec = sphere_on_surface_spec(stl, 0.05);
  World world = build_world(spec);
  const double radius = 0.005;
  sim::NewParticle ball;
  ball.position = {0, 0, radius * 1.001};
  ball.radius = radius;
  sim::add_particles(world, std::span(&ball, 1));
  sim::initialize(world);
  while (world.time < 0.05) {
    sim::step(world);
    ASSERT_LE(world.wall_contact_count(), 1u);
  }
  const double weight = world.particles.mass(0) * 9.81;  // N
  const Surface& s = world.surfaces[0].mesh;
  // Damped to rest (e = 0.2, 50 ms ≫ contact period): force = weight to 1e-6.
  EXPECT_NEAR(-s.total_force.z / weight, 1.0, 1e-6);
  std::size_t centre = 0;  // the welded index of the shared vertex at the origin
  while (centre < s.vertices.size() && norm(s.vertices[centre]) > 1e-12) ++centre;
  ASSERT_LT(centre, s.vertices.size());
  EXPECT_NEAR(-s.vertex_force[centre].z / weight, 1.0, 1e-6);  // all of it on the shared vertex
  EXPECT_NEAR(std::abs(s.total_force.x) + std::abs(s.total_force.y), 0.0, 1e-9 * weight);
}

}  // namespace
}  // namespace quarry
