// JKR cohesion through the whole engine (pair list, surface contacts, checkpoint): impacts of
// two spheres and of a sphere on the floor stick below the sticking velocity of the elastic
// JKR cycle and separate above it with the closed-form rebound; adhesion at negative overlap
// survives a restart bit for bit.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "contact/cohesion_jkr.h"
#include "contact/contact_law.h"
#include "sim/exchange.h"
#include "sim/run.h"
#include "verification/test_support.h"

namespace quarry {
namespace {

using std::numbers::pi;
using testing_support::deck_path;
using testing_support::start_world;

constexpr double kGamma = 2.0;      // J/m², JKR's γ
constexpr double kRadius = 0.005;   // m, the 02 deck's sphere
constexpr double kDensity = 7800.0;  // kg/m³

// The 02 deck without gravity or factory, both interactions JKR and undamped (e = 1).
SimulationSpec jkr_spec() {
  SimulationSpec spec = parse_deck(deck_path("tests/verification/02-bouncing-sphere/deck.yaml"));
  spec.factories.clear();
  spec.simulation.gravity.value = Vec3{};
  for (InteractionSpec& interaction : spec.interactions) {
    interaction.restitution.value = 1.0;
    interaction.cohesion_model.value = CohesionModel::jkr;
    interaction.surface_energy.value = kGamma;
  }
  return spec;
}

// Sticking velocity (m/s) of the undamped JKR impact (cohesion_jkr_test.cpp derives it): the
// approach speed whose kinetic energy ½ m* V² pays W = π γ R* |δ_c| I from δ = 0 to the
// break, I = 1.40325 (the curve's integral in its own units; Thornton & Ning 1998 derive the
// sticking velocity from this energy balance).
double sticking_velocity(const InteractionParameters& law, double effective_radius, double effective_mass) {
  const auto bracket = [](double u) { return std::pow(u, 10) / 15.0 - 2.0 * std::pow(u, 7) / 3.0 + std::pow(u, 4); };
  const double integral = -(bracket(std::cbrt(4.0)) - bracket(1.0)) / 3.0;
  const double gap = -contact::jkr_scales(kGamma, law.effective_youngs_modulus, effective_radius).break_overlap;
  return std::sqrt(2.0 * pi * kGamma * effective_radius * gap * integral / effective_mass);
}

double sphere_mass() { return kDensity * 4.0 / 3.0 * pi * kRadius * kRadius * kRadius; }  // kg

// Two spheres approach head-on at `speed` (relative, m/s) along x, 10 µm apart. Returns their
// relative speed after they separate, or 0 if they are still together after `steps` steps.
double pair_impact(double speed, int steps = 6000) {
  World world = start_world(jkr_spec());
  sim::NewParticle spheres[2];
  spheres[0].position = {-(kRadius + 5e-6), 0.0, 0.1};
  spheres[1].position = {kRadius + 5e-6, 0.0, 0.1};
  spheres[0].velocity = {0.5 * speed, 0.0, 0.0};
  spheres[1].velocity = {-0.5 * speed, 0.0, 0.0};
  sim::add_particles(world, spheres);
  bool touched = false;
  for (int n = 0; n < steps; ++n) {
    sim::step(world);
    const bool together = world.pair_contact_count() > 0;
    touched |= together;
    if (touched && !together) {
      const ParticleStore& p = world.particles;
      return std::fabs(p.velocity[1].x - p.velocity[0].x);
    }
  }
  return 0.0;
}

// 07 — Two spheres (R* = R/2, m* = m/2): stick at 0.8 V_s, separate at 1.25 V_s with the
// relative speed sqrt(V² − V_s²) (energy balance). 2 µs steps resolve the ~0.4 ms contact;
// the force's jumps at snap-in and break cost at most a step's worth of work: 2 %.
TEST(JkrCohesion, TwoSpheresStickBelowAndSeparateAboveTheStickingVelocity) {
  const World world = start_world(jkr_spec());
  const double sticking =
      sticking_velocity(world.materials.between(0, 0), 0.5 * kRadius, 0.5 * sphere_mass());
  EXPECT_EQ(pair_impact(0.8 * sticking), 0.0) << "V_s = " << sticking << " m/s";
  const double rebound = pair_impact(1.25 * sticking);
  EXPECT_NEAR(rebound / (sticking * std::sqrt(1.25 * 1.25 - 1.0)), 1.0, 0.02) << "V_s = " << sticking;
}

// 07 — A sphere on the floor (surface contacts, R* = R, m* = m): the same two outcomes.
TEST(JkrCohesion, SphereOnTheFloorSticksBelowAndLeavesAboveTheStickingVelocity) {
  const auto impact = [](double speed) {
    World world = start_world(jkr_spec());
    sim::NewParticle sphere;
    sphere.position = {0.001, 0.002, kRadius + 5e-6};
    sphere.velocity = {0.0, 0.0, -speed};
    sim::add_particles(world, std::span(&sphere, 1));
    bool touched = false;
    for (int n = 0; n < 6000; ++n) {
      sim::step(world);
      const bool together = world.wall_contact_count() > 0;
      touched |= together;
      if (touched && !together) return world.particles.velocity[0].z;
    }
    return 0.0;
  };
  const World world = start_world(jkr_spec());
  const double sticking = sticking_velocity(world.materials.between(0, 1), kRadius, sphere_mass());
  EXPECT_EQ(impact(0.8 * sticking), 0.0) << "V_s = " << sticking << " m/s";
  EXPECT_NEAR(impact(1.25 * sticking) / (sticking * std::sqrt(1.25 * 1.25 - 1.0)), 1.0, 0.02)
      << "V_s = " << sticking;
}

// A contact holds across a gap of up to |δ_c| (2.4 µm here for R* = R/2, 3.0 µm for the
// largest R*, R): a neighbour skin narrower than that would drop adhering pairs from the list,
// so the world refuses to build, at the interaction's surface_energy.
TEST(JkrCohesion, SkinNarrowerThanTheAdhesionGapIsAUserError) {
  SimulationSpec spec = jkr_spec();
  spec.simulation.skin.value = 1.0e-6;  // m
  try {
    build_world(spec);
    FAIL() << "built";
  } catch (const UserError& e) {
    const std::string text = e.diagnostics().format();
    EXPECT_NE(text.find("not less than the neighbour skin"), std::string::npos) << text;
    EXPECT_NE(text.find("raise simulation.skin"), std::string::npos) << text;
  }
  spec.simulation.skin.value = 1.0e-5;  // m: wide enough
  EXPECT_NO_THROW(build_world(spec));
}

// 07 — The adhesion is contact history: a world checkpointed while its stuck pair and its stuck
// sphere sit at negative overlap (held only by adhesion) goes on bit-identically after a restore.
TEST(JkrCohesion, RestartWhileAdheringAtNegativeOverlapIsBitExact) {
  World world = start_world(jkr_spec());
  const InteractionParameters& law = world.materials.between(0, 0);
  const double sticking = sticking_velocity(law, 0.5 * kRadius, 0.5 * sphere_mass());
  sim::NewParticle spheres[3];
  spheres[0].position = {-(kRadius + 5e-6), 0.0, 0.1};
  spheres[1].position = {kRadius + 5e-6, 0.0, 0.1};
  spheres[0].velocity = {0.4 * sticking, 0.0, 0.0};
  spheres[1].velocity = {-0.4 * sticking, 0.0, 0.0};
  spheres[2].position = {0.03, 0.0, kRadius + 5e-6};
  spheres[2].velocity = {0.0, 0.0, -0.5 * sticking};
  sim::add_particles(world, spheres);
  // Step until both contacts are held at negative overlap (the pair apart, the sphere off the
  // floor), which the oscillation of a stuck contact reaches in each cycle.
  const auto gap_of_pair = [&world] { return norm(world.particles.position[1] - world.particles.position[0]) - 2.0 * kRadius; };
  bool found = false;
  for (int n = 0; n < 20000 && !found; ++n) {
    sim::step(world);
    found = world.pair_contact_count() == 1 && world.wall_contact_count() == 1 && gap_of_pair() > 0.0 &&
            world.particles.position[2].z > kRadius;
  }
  ASSERT_TRUE(found);
  const std::string bytes = sim::checkpoint_bytes(world, 0);
  World restored = sim::read_checkpoint_bytes(bytes, "jkr.qck").world;
  for (int n = 0; n < 500; ++n) sim::step(world), sim::step(restored);
  EXPECT_EQ(world.pair_contact_count(), 1u);
  EXPECT_EQ(world.wall_contact_count(), 1u);
  EXPECT_EQ(sim::state_hash(restored), sim::state_hash(world));
}

}  // namespace
}  // namespace quarry
