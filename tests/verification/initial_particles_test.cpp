// Starting a run from given particles (deck `particles:`, issue #20): a frame or a CSV table of
// one run gives the next run exactly the same particles (bit for bit), ids are kept, overlaps
// are refused with both particles named, and a 10k-particle bed loads in well under a second;
// factories' initial angular velocity; a rigid surface material against the Hertz closed form.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <bit>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>

#include "contact/contact_law.h"
#include "io/deck.h"
#include "io/vtu_writer.h"
#include "sim/run.h"
#include "sim/step.h"
#include "sim/world.h"

namespace quarry {
namespace {

namespace fs = std::filesystem;

fs::path scratch(const std::string& name) {
  const fs::path folder = fs::temp_directory_path() / "quarry_initial_particles_test";
  fs::create_directories(folder);
  return folder / name;
}

// The settling deck: beads poured onto a floor; `tail` adds sections (particles:, factories:).
std::string deck(const std::string& tail, const std::string& floor_material = "glass") {
  return R"(simulation:
  end_time: 0.5
  time_step: 2.0e-5
  domain: {min: [-0.05, -0.05, 0], max: [0.05, 0.05, 0.2]}
materials:
  - {name: glass, density: 2500, youngs_modulus: 1.0e7, poisson_ratio: 0.25}
  - {name: anvil, density: 7800, rigid: true}
interactions:
  - {materials: [glass, glass], restitution: 0.5}
  - {materials: [glass, anvil], restitution: 0.5}
particle_types:
  - {name: bead, material: glass, size: {distribution: uniform, min_radius: 0.003, max_radius: 0.004}}
  - {name: ball, material: glass, size: {distribution: fixed, radius: 0.005}}
surfaces:
  - {name: floor, type: plane, point: [0, 0, 0], normal: [0, 0, 1], size: 0.2, material: )" +
         floor_material + "}\n" + tail;
}

const std::string kPour =
    "factories:\n  - {name: pour, particle_type: bead, region: {type: box, min: [-0.04, -0.04, "
    "0.02], max: [0.04, "
    "0.04, 0.1]}, count: 60, velocity: [0.1, 0, -0.5], angular_velocity: [3, -2, 1]}\n";

SimulationSpec parse(const std::string& text) {
  return parse_deck_string(text, "deck.yaml");
}

// A world that ran a while (50 ms): particles hitting the floor and each other, moving and
// spinning; mid-impact overlaps, hence allow_overlap in the runs that start from it.
World settled_world() {
  World world = build_world(parse(deck(kPour)));
  sim::initialize(world);
  sim::advance(world, 2500);
  return world;
}

std::uint64_t bits(double value) {
  return std::bit_cast<std::uint64_t>(value);
}

void expect_same_particles(const ParticleStore& a, const ParticleStore& b) {
  ASSERT_EQ(a.size(), b.size());
  const auto same = [](const Vec3& u, const Vec3& v) {
    return bits(u.x) == bits(v.x) && bits(u.y) == bits(v.y) && bits(u.z) == bits(v.z);
  };
  for (std::size_t i = 0; i < a.size(); ++i) {
    SCOPED_TRACE(i);
    EXPECT_EQ(a.id[i], b.id[i]);
    EXPECT_EQ(a.type[i], b.type[i]);
    EXPECT_EQ(bits(a.radius[i]), bits(b.radius[i]));
    EXPECT_EQ(bits(a.inv_mass[i]), bits(b.inv_mass[i]));
    EXPECT_TRUE(same(a.position[i], b.position[i]));
    EXPECT_TRUE(same(a.velocity[i], b.velocity[i]));
    EXPECT_TRUE(same(a.angular_velocity[i], b.angular_velocity[i]));
  }
}

TEST(InitialParticles, FactoriesGiveTheirAngularVelocity) {
  World started = build_world(parse(deck(kPour)));
  sim::initialize(started);
  ASSERT_EQ(started.particles.size(), 60u);
  for (std::size_t i = 0; i < started.particles.size(); ++i) {
    EXPECT_EQ(started.particles.angular_velocity[i].x, 3.0);
    EXPECT_EQ(started.particles.angular_velocity[i].y, -2.0);
    EXPECT_EQ(started.particles.angular_velocity[i].z, 1.0);
  }
}

TEST(InitialParticles, AFrameOfOneRunStartsTheNextBitForBit) {
  const World first = settled_world();
  const fs::path frame = scratch("particles_000060.vtu");
  std::ofstream(frame, std::ios::binary) << particles_vtu(first.particles, first.type_names);
  // The next run: the frame, and a factory whose ids must come after the frame's.
  const std::string factory =
      "factories:\n  - {name: top, particle_type: ball, region: {type: box, min: [-0.04, -0.04, "
      "0.15], max: [0.04, "
      "0.04, 0.19]}, count: 3}\n";
  World next = build_world(parse(
      deck(fmt::format("particles:\n  - {{file: {}, allow_overlap: true}}\n", frame.string()) +
           factory)));
  expect_same_particles(first.particles, next.particles);
  EXPECT_EQ(next.next_id, first.next_id);
  sim::initialize(next);
  ASSERT_EQ(next.particles.size(), first.particles.size() + 3);
  for (std::size_t i = first.particles.size(); i < next.particles.size(); ++i)
    EXPECT_GE(next.particles.id[i], first.next_id) << "a factory id collides with the frame's";
}

TEST(InitialParticles, ACsvTableOfOneRunStartsTheNextBitForBit) {
  const World first = settled_world();
  const fs::path table = scratch("settled.csv");
  {
    // Shortest round-trip numbers, as the CSV writers of Quarry print them.
    std::ofstream out(table, std::ios::binary);
    out << "x,y,z,radius,type,vx,vy,vz,wx,wy,wz,id\n";
    const ParticleStore& p = first.particles;
    for (std::size_t i = 0; i < p.size(); ++i)
      out << fmt::format("{},{},{},{},{},{},{},{},{},{},{},{}\n", p.position[i].x, p.position[i].y,
                         p.position[i].z, p.radius[i], first.type_names[p.type[i]], p.velocity[i].x,
                         p.velocity[i].y, p.velocity[i].z, p.angular_velocity[i].x,
                         p.angular_velocity[i].y, p.angular_velocity[i].z, p.id[i]);
  }
  const World next = build_world(parse(
      deck(fmt::format("particles:\n  - {{file: {}, allow_overlap: true}}\n", table.string()))));
  expect_same_particles(first.particles, next.particles);
}

TEST(InitialParticles, OneParticleGivenInTheDeck) {
  const World world =
      build_world(parse(deck("particles:\n  - {type: ball, position: [0.01, 0, 0.05], velocity: "
                             "[0, 0, -1], angular_velocity: [0, 5, 0]}\n"
                             "  - {type: bead, position: [-0.02, 0, 0.05]}\n")));
  ASSERT_EQ(world.particles.size(), 2u);
  EXPECT_EQ(world.particles.radius[0], 0.005);
  EXPECT_EQ(world.particles.velocity[0].z, -1.0);
  EXPECT_EQ(world.particles.angular_velocity[0].y, 5.0);
  // No radius given: drawn from the type's distribution.
  EXPECT_GE(world.particles.radius[1], 0.003);
  EXPECT_LE(world.particles.radius[1], 0.004);
  EXPECT_EQ(world.particles.id[0], 1u);
  EXPECT_EQ(world.particles.id[1], 2u);
}

std::string build_error(const std::string& text) {
  try {
    build_world(parse(text));
  } catch (const UserError& error) {
    return error.diagnostics().format();
  }
  return "no error";
}

TEST(InitialParticles, OverlapsAreRefusedNamingBothUnlessAllowed) {
  const std::string pair =
      "particles:\n  - {type: ball, position: [0, 0, 0.05]}\n  - {type: ball, position: [0.009, 0, "
      "0.05]}\n";
  const std::string message = build_error(deck(pair));
  EXPECT_NE(message.find("deck.yaml:17:5: error: the particle of the entry on line 17 and the "
                         "particle of the entry "
                         "on line 18 overlap by 1 mm"),
            std::string::npos)
      << message;
  EXPECT_EQ(build_error(
                deck(pair + "  - {type: ball, position: [0.03, 0, 0.05], allow_overlap: true}\n")),
            build_error(deck(pair)));
  const std::string allowed =
      "particles:\n  - {type: ball, position: [0, 0, 0.05], allow_overlap: true}\n  - {type: ball, "
      "position: [0.009, "
      "0, 0.05]}\n";
  EXPECT_EQ(build_error(deck(allowed)), "no error");
  // A contact of 0.4 % of R (a resting bed's are smaller still) is not a mistake.
  EXPECT_EQ(build_error(deck(
                "particles:\n  - {type: ball, position: [0, 0, 0.05]}\n  - {type: ball, position: "
                "[0.00998, 0, 0.05]}\n")),
            "no error");
  const std::string on_floor = "particles:\n  - {type: ball, position: [0, 0, 0.004]}\n";
  EXPECT_NE(build_error(deck(on_floor)).find("overlaps surface \"floor\" by 1 mm"),
            std::string::npos)
      << build_error(deck(on_floor));
}

TEST(InitialParticles, RadiusOutsideTheTypeOrCentreOutsideTheDomainIsRefused) {
  const std::string message =
      build_error(deck("particles:\n  - {type: ball, position: [0, 0, 0.05], radius: 0.006}\n"));
  EXPECT_NE(
      message.find("radius 6 mm is outside the sizes of particle type \"ball\" (5 mm to 5 mm)"),
      std::string::npos)
      << message;
  const std::string outside =
      build_error(deck("particles:\n  - {type: ball, position: [0, 0, 0.5]}\n"));
  EXPECT_NE(outside.find("centre [0, 0, 0.5] m is outside the domain"), std::string::npos)
      << outside;
}

TEST(InitialParticles, TwoFilesSharingAnIdAreRefused) {
  const fs::path table = scratch("one.csv");
  std::ofstream(table, std::ios::binary) << "x,y,z,radius,type,id\n0,0,0.05,0.005,ball,7\n";
  const std::string twice = fmt::format(
      "particles:\n  - {{file: {0}}}\n  - {{file: {0}, allow_overlap: true}}\n", table.string());
  const std::string message = build_error(deck(twice));
  EXPECT_NE(
      message.find(
          "the particle on line 2 of one.csv has id 7, as the particle on line 2 of one.csv has"),
      std::string::npos)
      << message;
}

// A 10 000-particle bed on a lattice (spacing 2.05 R: no overlap) is read and checked in O(n).
TEST(InitialParticles, ATenThousandParticleTableLoadsFast) {
  const fs::path table = scratch("bed_10k.csv");
  {
    std::ofstream out(table, std::ios::binary);
    out << "x,y,z,radius,type\n";
    const double spacing = 2.05 * 0.003;  // m
    for (int k = 0; k < 10000; ++k)
      out << fmt::format("{},{},{},0.003,bead\n", -0.045 + spacing * (k % 14),
                         -0.045 + spacing * (k / 14 % 14), 0.004 + spacing * (k / 196));
  }
  std::string text = deck(fmt::format("particles:\n  - {{file: {}}}\n", table.string()));
  text.replace(text.find("max: [0.05, 0.05, 0.2]"), 22, "max: [0.05, 0.05, 0.4]");
  const auto start = std::chrono::steady_clock::now();
  const World world = build_world(parse(text));
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_EQ(world.particles.size(), 10000u);
  // Measured about 0.05 s in the optimised build; 10x for the sanitizers, and a margin.
  EXPECT_LT(seconds, 3.0);
  std::printf("10k-particle table read and checked in %.3f s\n", seconds);
}

// A sphere on a rigid plane: with e = 1 the contact lasts the Hertz time
// t_c = 2.868 (m*² / (R* E*² v))^(1/5) (Johnson 1985, §11.4; m* = m, R* = R for a wall) with
// E* = E/(1 − ν²) (Johnson eq. 4.22, E_wall → ∞).
TEST(RigidMaterial, HertzContactTimeOfASphereOnARigidPlane) {
  std::string text = deck(
      "particles:\n  - {type: ball, position: [0, 0, 0.0051], velocity: [0, 0, -1]}\n", "anvil");
  text.replace(text.find("time_step: 2.0e-5"), 17, "time_step: 1.0e-7");
  text.replace(text.find("restitution: 0.5}\nparticle_types"), 17, "restitution: 1.0}");
  text.replace(text.find("  end_time: 0.5"), 15, "  end_time: 0.5\n  gravity: [0, 0, 0]");
  text.replace(text.find("youngs_modulus: 1.0e7"), 21, "youngs_modulus: 7.0e10");
  World world = build_world(parse(text));
  const InteractionParameters& pair = world.materials.between(0, 1);
  EXPECT_EQ(pair.effective_youngs_modulus, 1.0 / ((1.0 - 0.25 * 0.25) / 7.0e10));
  EXPECT_EQ(pair.effective_shear_modulus, 1.0 / (2.0 * (2.0 - 0.25) * (1.0 + 0.25) / 7.0e10));
  sim::initialize(world);
  int steps_in_contact = 0;
  for (int step = 0; step < 2000 && (steps_in_contact == 0 || world.wall_contact_count() > 0);
       ++step) {
    sim::step(world);
    steps_in_contact += world.wall_contact_count() > 0;
  }
  const double radius = 0.005,
               mass = 2500.0 * 4.0 / 3.0 * std::numbers::pi * radius * radius * radius;
  const double modulus = 7.0e10 / (1.0 - 0.25 * 0.25);  // Pa
  const double expected =
      2.868 * std::pow(mass * mass / (radius * modulus * modulus * 1.0), 0.2);  // s
  const double measured = steps_in_contact * 1.0e-7;                            // s
  // ± one step at each end, and the 4-digit constant.
  EXPECT_NEAR(measured, expected, 2.0e-7 + 1e-3 * expected) << "expected " << expected << " s";
  std::printf("rigid plane: contact %.4g s, Hertz closed form %.4g s\n", measured, expected);
  EXPECT_NEAR(world.particles.velocity[0].z, 1.0, 1e-6);  // e = 1: rebounds at the impact speed
}

// ---- fixed particles (particle_types[].fixed) ----

// A ball launched at 1 m/s (no gravity) onto a target: a fixed particle of the ball's type or the
// floor plane; returns the contact time (s) and the rebound speed over the impact speed.
struct Bounce {
  double contact_time = 0.0, restitution = 0.0;
};
Bounce bounce(const std::string& restitution, bool on_fixed_particle) {
  std::string text =
      deck(on_fixed_particle
               ? "particles:\n  - {type: stud, position: [0, 0, 0.05]}\n"
                 "  - {type: ball, position: [0, 0, 0.0601], velocity: [0, 0, -1]}\n"
               : "particles:\n  - {type: ball, position: [0, 0, 0.0051], velocity: [0, 0, -1]}\n");
  text.replace(text.find("time_step: 2.0e-5"), 17, "time_step: 1.0e-7");
  text.replace(text.find("  end_time: 0.5"), 15, "  end_time: 0.5\n  gravity: [0, 0, 0]");
  text.replace(text.find("youngs_modulus: 1.0e7"), 21, "youngs_modulus: 7.0e10");
  text.replace(text.find("restitution: 0.5}"), 17, "restitution: " + restitution + "}");
  text.replace(text.find("surfaces:"), 9,
               "  - {name: stud, material: glass, size: {distribution: fixed, radius: 0.005}, "
               "fixed: true}\nsurfaces:");
  World world = build_world(parse(text));
  sim::initialize(world);
  const std::size_t ball = world.particles.size() - 1;
  const Vec3 stud_at = world.particles.position[0];
  int steps_in_contact = 0;
  const auto touching = [&] { return world.pair_contact_count() + world.wall_contact_count() > 0; };
  for (int step = 0; step < 3000 && (steps_in_contact == 0 || touching()); ++step) {
    sim::step(world);
    steps_in_contact += touching();
  }
  if (on_fixed_particle) {
    // The fixed particle took the impact without moving: position, velocity and spin unchanged.
    EXPECT_EQ(world.particles.position[0].z, stud_at.z);
    EXPECT_EQ(norm(world.particles.velocity[0]), 0.0);
    EXPECT_EQ(norm(world.particles.angular_velocity[0]), 0.0);
  }
  return {steps_in_contact * 1.0e-7, world.particles.velocity[ball].z / 1.0};
}

// Hertz contact of a ball (mass m, radius R) with a fixed ball of the same radius and material:
// m* = m (the fixed one's mass is infinite), R* = R/2, E* = E/(2(1 − ν²)), so with e = 1 the
// contact lasts t_c = 2.868 (m*² / (R* E*² v))^(1/5) (Johnson 1985, §11.4) and the ball comes
// back at its impact speed.
TEST(FixedParticles, ABallBouncesOffAFixedOneInTheHertzTime) {
  const Bounce elastic = bounce("1.0", true);
  const double radius = 0.005,
               mass = 2500.0 * 4.0 / 3.0 * std::numbers::pi * radius * radius * radius;
  const double modulus = 7.0e10 / (2.0 * (1.0 - 0.25 * 0.25));  // Pa
  const double expected =
      2.868 * std::pow(mass * mass / (0.5 * radius * modulus * modulus * 1.0), 0.2);  // s
  EXPECT_NEAR(elastic.contact_time, expected, 2.0e-7 + 1e-3 * expected)
      << "expected " << expected << " s";
  EXPECT_NEAR(elastic.restitution, 1.0, 1e-6);
  std::printf("on a fixed ball: contact %.4g s, Hertz closed form %.4g s\n", elastic.contact_time,
              expected);
}

// With damping, the Hertz–Mindlin dashpot (β from e; Tsuji et al. 1992) gives a restitution that
// depends on β only, not on m*, R* or E*: a ball rebounds off a fixed ball exactly as off a wall
// of the same material (up to the time discretisation, ~1e-3 at ~300 steps per contact).
TEST(FixedParticles, RestitutionOffAFixedParticleIsThatOffAWall) {
  const Bounce on_particle = bounce("0.5", true), on_wall = bounce("0.5", false);
  EXPECT_GT(on_particle.restitution, 0.3);
  EXPECT_NEAR(on_particle.restitution, on_wall.restitution, 2e-3)
      << "off a fixed particle " << on_particle.restitution << ", off the wall "
      << on_wall.restitution;
  std::printf("restitution 0.5: off a fixed ball %.5f, off the wall %.5f\n",
              on_particle.restitution, on_wall.restitution);
}

// A run started from a table (with fixed particles among them) restarts from its checkpoint bit
// for bit without the table: the particles are in the checkpoint, the file is not read again.
TEST(InitialParticles, ACheckpointRestartsWithoutTheTable) {
  const fs::path table = scratch("restart_bed.csv");
  {
    std::ofstream out(table, std::ios::binary);
    out << "x,y,z,radius,type\n";
    for (int k = 0; k < 5; ++k) out << fmt::format("{},0,0.005,0.005,stud\n", -0.02 + 0.01 * k);
    for (int k = 0; k < 5; ++k) out << fmt::format("{},0.001,0.03,0.0035,bead\n", -0.02 + 0.01 * k);
  }
  std::string text = deck(fmt::format("particles:\n  - {{file: {}}}\n", table.string()) + kPour);
  text.replace(text.find("surfaces:"), 9,
               "  - {name: stud, material: glass, size: {distribution: fixed, radius: 0.005}, "
               "fixed: true}\nsurfaces:");
  World world = build_world(parse(text));
  sim::initialize(world);
  sim::advance(world, 200);
  const std::string bytes = sim::checkpoint_bytes(world, 0);
  fs::remove(table);
  World restored = sim::read_checkpoint_bytes(bytes, "restart.qck").world;
  EXPECT_EQ(restored.particles.size(), world.particles.size());
  sim::advance(world, 200);
  sim::advance(restored, 200);
  EXPECT_EQ(sim::state_hash(restored), sim::state_hash(world));
  for (std::size_t i = 0; i < 5; ++i) {  // the fixed ones have not moved
    EXPECT_EQ(world.particles.position[i].z, 0.005);
    EXPECT_EQ(world.particles.inv_mass[i], 0.0);
  }
}

// A factory at a point places each particle with its centre exactly there, one at a time: the
// next waits until the one before has moved off the place (a nozzle).
TEST(InitialParticles, AFactoryAtAPointPlacesEachParticleThereInTurn) {
  World world =
      build_world(parse(deck("factories:\n  - {name: nozzle, particle_type: ball, region: {type: "
                             "point, position: [0.01, -0.02, 0.1]}, "
                             "count: 3, velocity: [0, 0, -2], angular_velocity: [0, 7, 0]}\n")));
  sim::initialize(world);
  ASSERT_EQ(world.particles.size(), 1u);  // the others wait for the place to be free
  EXPECT_EQ(world.particles.position[0].x, 0.01);
  EXPECT_EQ(world.particles.position[0].y, -0.02);
  EXPECT_EQ(world.particles.position[0].z, 0.1);
  EXPECT_EQ(world.particles.angular_velocity[0].y, 7.0);
  sim::advance(world, 1000);  // 20 ms: each ball leaves its diameter in 5 ms
  ASSERT_EQ(world.particles.size(), 3u);
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(world.particles.position[i].x, 0.01);  // straight down the z axis, no spin-off
    EXPECT_LT(world.particles.position[i].z, 0.1);
  }
}
}  // namespace
}  // namespace quarry
