// Tests of the settled-bed reference problem: the lattice matches the peers' recipe, a settled
// bed is in static equilibrium with its walls, and a saved bed continues bit-identically.
#include "bench/settled_bed_scene.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <set>

#include "sim/run.h"
#include "sim/step.h"

namespace quarry::bench {
namespace {

SettledBedParameters small_bed() {
  SettledBedParameters p;
  p.cells_x = 4;
  p.cells_y = 4;
  p.cells_z = 3;
  return p;
}

TEST(SettledBedScene, LatticeIsThePeersJitteredSimpleCubicLattice) {
  const SettledBedParameters p = small_bed();
  const World world = make_lattice_world(p);
  ASSERT_EQ(world.particles.size(), 48u);
  ASSERT_EQ(world.surfaces.size(), 6u);
  std::set<ParticleId> ids;
  for (std::size_t i = 0; i < world.particles.size(); ++i) {
    const Vec3 x = world.particles.position[i];
    // Site (i + ½)·a of LAMMPS' "lattice sc a origin 0.5 0.5 0.5", displaced by at most jit.
    for (double c : {x.x, x.y, x.z}) {
      const double site = (std::floor(c / p.lattice_spacing) + 0.5) * p.lattice_spacing;
      EXPECT_LE(std::abs(c - site), p.jitter * (1 + 1e-12));
    }
    EXPECT_EQ(world.particles.radius[i], 1e-3);
    // m = ρ 4/3 π R³ for a sphere.
    EXPECT_NEAR(world.particles.mass(i), 2500.0 * 4.0 / 3.0 * M_PI * 1e-9, 1e-18);
    ids.insert(world.particles.id[i]);
  }
  EXPECT_EQ(ids.size(), 48u);
  EXPECT_EQ(world.dt, 1e-5);
  EXPECT_EQ(world.skin, 2e-4);
}

TEST(SettledBedScene, JitterIsDeterministicPerSeed) {
  SettledBedParameters p = small_bed();
  const World a = make_lattice_world(p);
  const World b = make_lattice_world(p);
  p.seed += 1;
  const World c = make_lattice_world(p);
  EXPECT_EQ(a.particles.position[7].x, b.particles.position[7].x);
  EXPECT_NE(a.particles.position[7].x, c.particles.position[7].x);
}

// Translational kinetic energy per particle (J): Σ ½ m v² / n.
double translational_energy_per_particle(const World& world) {
  const ParticleStore& p = world.particles;
  double energy = 0.0;  // J
  for (std::size_t i = 0; i < p.size(); ++i) energy += 0.5 * norm2(p.velocity[i]) / p.inv_mass[i];
  return energy / static_cast<double>(p.size());
}

// Static equilibrium (Newton's second law with zero acceleration): once the bed is at rest the
// pair forces cancel in pairs (Newton's third law), so the six walls together carry Σ m g.
// Tolerance 0.5 %: the residual motion of a bed with translational kinetic energy < 1e-13 J
// per particle (at 1e-12 J the settling is not over: particles still rearrange, and the walls
// were measured carrying 99.5–102 % of the weight at such moments). Spin is not counted: a sphere spinning about its contact normal feels no
// torque without rolling or twisting resistance, so a spin left by the settling survives it
// and pushes on nothing (measured: 2.3e-12 J per particle of rotation, one particle with
// 8e-11 J, while the translation was down to 2e-14 J; how much spin is left depends on the
// chaotic path of the settling).
TEST(SettledBedScene, SettledBedRestsOnItsWalls) {
  World world = make_lattice_world(small_bed());
  prepare_first_step(world);
  for (int s = 0; s < 100000 && (s < 5000 || translational_energy_per_particle(world) > 1e-13); ++s)
    sim::step(world);
  EXPECT_LT(translational_energy_per_particle(world), 1e-13);
  const BedState bed = measure_bed(world);
  EXPECT_NEAR(bed.all_walls_force_z, bed.weight, 5e-3 * bed.weight);
  // The floor carries most of the weight; the side walls' friction (either sign, it depends on
  // how the particles last slid along them) carries the rest.
  EXPECT_GT(bed.floor_force, 0.5 * bed.weight);
  // Settled: every centre is at least one radius above the floor, and the bed sank.
  EXPECT_LT(bed.max_height, 3 * 2.1e-3);
  EXPECT_GT(bed.contact_pairs, 0.0);
}

// The benchmark times a bed loaded from a checkpoint: it must continue exactly as the world
// that wrote it (the same forces, lists and history), bit for bit.
TEST(SettledBedScene, SavedBedContinuesBitIdentically) {
  World world = make_lattice_world(small_bed());
  prepare_first_step(world);
  for (int s = 0; s < 300; ++s) sim::step(world);
  const std::string path = (std::filesystem::path(testing::TempDir()) / "bench_bed_test.qck").string();
  sim::write_checkpoint(world, path, 0);
  World loaded = std::move(sim::read_checkpoint(path).world);
  std::filesystem::remove(path);
  EXPECT_FALSE(loaded.lists_stale);
  for (int s = 0; s < 200; ++s) {
    sim::step(world);
    sim::step(loaded);
  }
  EXPECT_EQ(sim::state_hash(world), sim::state_hash(loaded));
}

}  // namespace
}  // namespace quarry::bench
