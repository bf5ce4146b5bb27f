// Lists rebuilt only when they must be give the bits of lists rebuilt at every step (the
// forces see the touching pairs and triangles in the same order either way), on the two
// occasions issue 21 found them rebuilt too often against LIGGGHTS:
// - Moving surfaces (a drum rebuilt its lists 1.6× as often as LIGGGHTS). A triangle is a particle's candidate when its box comes within R + skin of the
// centre, so it can touch the particle only after the two have closed that gap by more than the
//   skin: the lists are rebuilt when the particle's move d plus the surface's s exceed the whole
//   skin (pairs still at d > skin/2). A plate driven towards a resting sphere must be found at
//   the first step it touches, while the lists wait until the plate has moved one skin.
// - Particles leaving the domain (a hopper's outflow rebuilt the lists at every step one left):
//   the lists drop them instead. A stream falling out through the floor of the domain.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

#include "io/deck.h"
#include "sim/run.h"
#include "verification/test_support.h"

namespace quarry {
namespace {

using testing_support::start_world;

// No gravity; a bead at rest at the origin (R = 5 mm); a plate starting 1.05 skins below its
// reach (gap R + 1.05 skin under the centre) and rising at 1 m/s: 0.01 skin per step of 10 µs
// (skin 1 mm). It touches after 105 steps and pushes the bead up from then on.
constexpr const char* kDeck = R"(
simulation:
  end_time: 0.01
  time_step: 1.0e-5
  skin: 0.001
  impact_speed: 0.05
  max_overlap_fraction: 0.5
  gravity: [0, 0, 0]
  domain: {min: [-0.1, -0.1, -0.1], max: [0.1, 0.1, 0.1]}
materials:
  - {name: steel, density: 7800, youngs_modulus: 1.0e8, poisson_ratio: 0.3}
interactions:
  - {materials: [steel, steel], restitution: 0.5, static_friction: 0.5}
particle_types:
  - {name: ball, material: steel, size: {distribution: fixed, radius: 0.005}}
particles:
  - {type: ball, position: [0, 0, 0]}
surfaces:
  - name: plate
    type: plane
    point: [0, 0, -0.00605]
    normal: [0, 0, 1]
    size: 0.04
    material: steel
    motion: {type: translation, velocity: [0, 0, 1.0]}
)";

TEST(LazyLists, APlateIsFoundAtTheStepItTouchesWhileTheListsWaitForAWholeSkin) {
  const SimulationSpec spec = parse_deck_string(kDeck, "moving_plate.yaml");
  World lazy = start_world(spec, 1);
  World eager = start_world(spec, 1);
  const std::uint64_t builds_at_start = lazy.rebuilds;
  int first_touch = -1;  // step at which the bead first moves
  for (int step = 1; step <= 300; ++step) {
    eager.lists_stale = true;  // rebuilt at every step: nothing can be missed
    sim::step(eager);
    sim::step(lazy);
    ASSERT_EQ(lazy.particles.velocity[0].z, eager.particles.velocity[0].z) << "step " << step;
    ASSERT_EQ(lazy.particles.position[0].z, eager.particles.position[0].z) << "step " << step;
    if (first_touch < 0 && lazy.particles.velocity[0].z != 0.0) first_touch = step;
    // The plate has moved 0.01 skin per step and the bead not at all: no rebuild before one skin.
    if (step == 99) {
      EXPECT_EQ(lazy.rebuilds, builds_at_start) << "rebuilt before the plate moved a skin";
    }
  }
  EXPECT_GE(first_touch, 105);  // the gap of 1.05 skins closes at 0.01 skin per step
  EXPECT_LE(first_touch, 106);
  EXPECT_GT(lazy.particles.velocity[0].z, 0.5);  // pushed along by the plate
  EXPECT_LT(lazy.rebuilds - builds_at_start, 20u);
}

// 400 beads (R = 2 mm) in a loose column falling out through the bottom of the domain: every
// few steps some leave. No re-sort (sort_interval 0), so both worlds keep one particle order.
constexpr const char* kStream = R"(
simulation:
  end_time: 1.0
  time_step: 2.0e-5
  impact_speed: 2.0
  sort_interval: 0
  gravity: [0, 0, -9.81]
  domain: {min: [-0.02, -0.02, 0.0], max: [0.02, 0.02, 0.2]}
materials:
  - {name: glass, density: 2500, youngs_modulus: 1.0e7, poisson_ratio: 0.25}
interactions:
  - {materials: [glass, glass], restitution: 0.5, static_friction: 0.5}
particle_types:
  - {name: bead, material: glass, size: {distribution: uniform, min_radius: 0.0018, max_radius: 0.002}}
factories:
  - {name: column, particle_type: bead, region: {type: box, min: [-0.015, -0.015, 0.01], max: [0.015, 0.015, 0.19]}, count: 400, velocity: [0, 0, -0.5]}
)";

TEST(LazyLists, ParticlesLeavingTheDomainAreDroppedFromTheListsWithTheBitsOfRebuilds) {
  // The beads land on a tilted plate and slide off it out of the domain: the surface
  // candidates and wall contacts of those leaving go too.
  const std::string deck = std::string(kStream) +
                           "surfaces:\n  - {name: chute, type: plane, point: [0, 0, 0.05], "
                           "normal: [0.5, 0, 1], size: 0.1, material: glass}\n";
  const SimulationSpec spec = parse_deck_string(deck, "stream.yaml");
  World lazy = start_world(spec, 1);
  World eager = start_world(spec, 1);
  ASSERT_EQ(lazy.particles.size(), 400u);
  std::uint64_t steps_with_removals = 0, removals_without_rebuild = 0, chute_contacts = 0;
  for (int step = 1; step <= 12000; ++step) {
    eager.lists_stale = true;
    sim::step(eager);
    const std::uint64_t removed_before = lazy.removed_outside;
    const std::uint64_t builds_before = lazy.rebuilds;
    sim::step(lazy);
    ASSERT_EQ(lazy.particles.size(), eager.particles.size()) << "step " << step;
    chute_contacts += lazy.wall_contacts.size();
    if (lazy.removed_outside != removed_before) {
      ++steps_with_removals;
      removals_without_rebuild += lazy.rebuilds == builds_before;  // a removal alone does not rebuild
    }
  }
  EXPECT_GT(lazy.removed_outside, 100u);
  EXPECT_GT(steps_with_removals, 50u);
  EXPECT_GT(removals_without_rebuild, steps_with_removals / 2);
  EXPECT_EQ(lazy.particles.position, eager.particles.position);
  EXPECT_EQ(lazy.particles.velocity, eager.particles.velocity);
  EXPECT_EQ(lazy.particles.angular_velocity, eager.particles.angular_velocity);
  EXPECT_LT(lazy.rebuilds, eager.rebuilds / 4);
  EXPECT_GT(chute_contacts, 1000u);  // the chute carried them
}

// `skin: auto` (issue 21): the skin of each build grows with the fastest particle, from 10 % of
// the smallest diameter; the lists stay complete (the bits of lists rebuilt, each with its own
// skin, at every step) and a checkpoint restarts to the bit (the skin is the last build's).
TEST(LazyLists, AnAutomaticSkinGrowsWithTheFallAndKeepsTheBits) {
  std::string deck = kStream;
  const std::string sort_line = "  sort_interval: 0";
  deck.replace(deck.find(sort_line), sort_line.size(), sort_line + "\n  skin: auto");
  const SimulationSpec spec = parse_deck_string(deck, "stream_auto.yaml");
  ASSERT_LT(spec.simulation.skin.value, 0.0);
  World lazy = start_world(spec, 1);
  World eager = start_world(spec, 1);
  const double floor = lazy.skin_choice.floor;  // m
  EXPECT_DOUBLE_EQ(floor, 0.2 * 0.0018);
  double largest = 0.0;  // m
  for (int step = 1; step <= 6000; ++step) {
    eager.lists_stale = true;
    sim::step(eager);
    sim::step(lazy);
    largest = std::max(largest, lazy.skin);
    EXPECT_LE(lazy.skin, lazy.skin_choice.ceiling);
    EXPECT_GE(lazy.skin, floor);
  }
  EXPECT_GT(largest, 1.5 * floor);  // the column falls at 1–2 m/s: u ≈ 30 µm per step
  EXPECT_EQ(lazy.particles.position, eager.particles.position);
  EXPECT_EQ(lazy.particles.velocity, eager.particles.velocity);
  EXPECT_EQ(lazy.particles.angular_velocity, eager.particles.angular_velocity);

  sim::RestoredWorld restored = sim::read_checkpoint_bytes(sim::checkpoint_bytes(lazy, 0), "memory");
  restored.world.threading = lazy.threading;
  EXPECT_EQ(restored.world.skin, lazy.skin);
  sim::advance(lazy, 3000);
  sim::advance(restored.world, 3000);
  EXPECT_EQ(sim::state_hash(restored.world), sim::state_hash(lazy));
}

// The automatic skin is the default: a deck without `skin` gets it, a number fixes the skin.
TEST(LazyLists, TheSkinIsAutomaticUnlessTheDeckFixesIt) {
  std::string deck = kStream;
  ASSERT_EQ(deck.find("skin:"), std::string::npos);
  EXPECT_TRUE(start_world(parse_deck_string(deck, "stream.yaml"), 1).skin_choice.automatic);
  const World fixed = start_world(parse_deck_string(kDeck, "plate.yaml"), 1);
  EXPECT_FALSE(fixed.skin_choice.automatic);
  EXPECT_EQ(fixed.skin, 0.001);
}

}  // namespace
}  // namespace quarry
