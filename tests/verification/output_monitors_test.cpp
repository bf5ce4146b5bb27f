// Verification of the data a run writes about contacts and the typed monitors (issue #20): each
// against a closed form, cited per test. Small scenes built from decks in this file.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>

#include "io/deck.h"
#include "io/vtu_test_reader.h"
#include "sim/exchange.h"
#include "sim/frame_contacts.h"
#include "sim/monitor_sensors.h"
#include "sim/monitors.h"
#include "sim/output.h"
#include "sim/run.h"
#include "verification/test_support.h"

namespace quarry {
namespace {

using testing_support::start_world;

// Steel-like balls of radius 5 mm (E = 1e8 Pa, ν = 0.3) over a floor plane at z = 0; restitution
// 1 (no dashpot), so a contact's normal force is Hertz's elastic force alone.
std::string ball_deck(const std::string& gravity, const std::string& monitors) {
  return R"(
simulation:
  end_time: 1.0
  time_step: 5.0e-6
  impact_speed: 1.0
  gravity: )" + gravity + R"(
  domain: {min: [-0.2, -0.2, -0.1], max: [0.2, 0.2, 0.4]}
materials:
  - {name: ball, density: 7800, youngs_modulus: 1.0e8, poisson_ratio: 0.3}
  - {name: floor, density: 7800, youngs_modulus: 1.0e8, poisson_ratio: 0.3}
interactions:
  - {materials: [ball, ball], restitution: 1.0, static_friction: 0.3}
  - {materials: [ball, floor], restitution: 1.0, static_friction: 0.3}
particle_types:
  - {name: sphere, material: ball, size: {distribution: fixed, radius: 0.005}}
surfaces:
  - {name: floor, type: plane, point: [0, 0, 0], normal: [0, 0, 1], size: 0.3, material: floor}
)" + monitors + R"(
output: {interval: 0, plots: false, contacts: true}
)";
}

constexpr double kRadius = 0.005;                                        // m
constexpr double kMass = 7800 * 4.0 / 3.0 * 3.14159265358979323846 * kRadius * kRadius * kRadius;  // kg
// E* = 1 / (2 (1 − ν²) / E) for two equal materials (Hertz 1882; Johnson, Contact Mechanics §4.2).
constexpr double kEffectiveYoungs = 1.0e8 / (2.0 * (1.0 - 0.3 * 0.3));  // Pa

std::string read_text(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

std::size_t column_index(const std::vector<std::string>& columns, const std::string& name) {
  for (std::size_t k = 0; k < columns.size(); ++k)
    if (columns[k] == name) return k;
  ADD_FAILURE() << "no column " << name;
  return 0;
}

World world_with(const std::string& deck, const std::vector<sim::NewParticle>& particles) {
  World world = start_world(parse_deck_string(deck, "test.yaml"));
  if (!particles.empty()) sim::add_particles(world, particles);
  return world;
}

// Writes frame 0 (and a monitor row) of the world as it stands into a fresh `name` folder.
std::filesystem::path write_frame_now(World& world, const std::string& name) {
  const std::filesystem::path directory = std::filesystem::path(::testing::TempDir()) / name;
  std::filesystem::remove_all(directory);
  static std::ostringstream log;
  sim::OutputOptions options;
  options.directory = directory;
  options.end_time = 1.0;
  options.log = &log;
  world.output = std::make_unique<sim::Output>(world, options);
  world.output->start(world);
  world.output.reset();
  return directory;
}

// Two balls pressed together at overlap δ and one resting on the floor at δ: the contacts file
// holds Hertz's normal force F = 4/3 E* sqrt(R*) δ^{3/2} (Hertz 1882; Johnson, Contact Mechanics
// eq. 4.22) with R* = R/2 for the pair and R* = R for the flat floor, along the line between the
// centres (pair) or from the centre to the contact point (floor); the particles' frame has
// coordination number 1 each and max_overlap_ratio δ/R.
TEST(OutputVerification, ContactsFileHoldsHertzForcesAndTheParticlesTheirContactFields) {
  const double pair_overlap = 1e-4, floor_overlap = 5e-5;  // m
  std::vector<sim::NewParticle> balls(3);
  balls[0].position = {0, 0, 0.1};
  balls[1].position = {0, 0, 0.1 + 2 * kRadius - pair_overlap};
  balls[2].position = {0.05, 0, kRadius - floor_overlap};
  World world = world_with(ball_deck("[0, 0, 0]", ""), balls);
  sim::step(world);  // lists and forces for the added balls
  const std::filesystem::path directory = write_frame_now(world, "quarry_contacts_vtu");

  const vtu_test::VtuContent contacts = vtu_test::read_vtu(read_text(directory / "contacts_000000.vtu"));
  ASSERT_EQ(contacts.cell_count, 2u);
  const std::vector<Vec3> normal = vtu_test::vectors_of(contacts.arrays.at("normal_force"));
  const std::vector<Vec3> tangential = vtu_test::vectors_of(contacts.arrays.at("tangential_force"));
  const std::vector<double> overlap = vtu_test::values_of<double>(contacts.arrays.at("overlap"));
  const std::vector<std::uint8_t> kind = vtu_test::values_of<std::uint8_t>(contacts.arrays.at("kind"));
  const std::vector<Vec3> ends = vtu_test::vectors_of(contacts.arrays.at("Points"));
  const double radii[2] = {kRadius / 2, kRadius};  // R* of the pair, of the floor contact
  for (std::size_t c = 0; c < 2; ++c) {
    EXPECT_EQ(kind[c], c);  // pairs first, then surface contacts
    const double hertz = 4.0 / 3.0 * kEffectiveYoungs * std::sqrt(radii[c]) * std::pow(overlap[c], 1.5);  // N
    EXPECT_NEAR(norm(normal[c]) / hertz, 1.0, 1e-9) << "contact " << c;
    EXPECT_NEAR(norm(tangential[c]), 0.0, 1e-12 * hertz);
    // Along the line, pushing the `from` particle away from the `to` end.
    EXPECT_NEAR(dot(normal[c], ends[2 * c] - ends[2 * c + 1]) / (norm(normal[c]) * norm(ends[2 * c] - ends[2 * c + 1])),
                1.0, 1e-12);
  }
  // The step moved the balls by about F dt²/m: the overlaps are the placed ones within 0.1 %.
  EXPECT_NEAR(overlap[0] / pair_overlap, 1.0, 1e-3);
  EXPECT_NEAR(overlap[1] / floor_overlap, 1.0, 1e-3);
  EXPECT_NEAR(ends[3].z, 0.0, 1e-15);  // the floor's contact point

  const vtu_test::VtuContent particles = vtu_test::read_vtu(read_text(directory / "particles_000000.vtu"));
  EXPECT_EQ(vtu_test::values_of<std::int32_t>(particles.arrays.at("coordination_number")),
            (std::vector<std::int32_t>{1, 1, 1}));
  const std::vector<double> ratio = vtu_test::values_of<double>(particles.arrays.at("max_overlap_ratio"));
  EXPECT_DOUBLE_EQ(ratio[0], overlap[0] / kRadius);
  EXPECT_DOUBLE_EQ(ratio[1], overlap[0] / kRadius);
  EXPECT_DOUBLE_EQ(ratio[2], overlap[1] / kRadius);
  EXPECT_EQ(vtu_test::vectors_of(particles.arrays.at("torque")), world.particles.torque);
  const std::string manifest = read_text(directory / sim::kOutputManifest);
  EXPECT_NE(manifest.find("contacts_000000.vtu"), std::string::npos);
  EXPECT_NE(manifest.find("contacts.pvd"), std::string::npos);
  EXPECT_NE(read_text(directory / "contacts.pvd").find("contacts_000000.vtu"), std::string::npos);
}

// A ball sliding on the floor: once the tangential spring has stretched to the Coulomb limit the
// friction force in the contacts file is |Ft| = μs |Fn| (Coulomb's law of sliding friction; μs =
// 0.3 here, no dashpot), against the sliding direction; the same for two balls sliding past
// each other (pair forces evaluated at the frame's state). The monitors count the two contacts,
// one of them between particles.
TEST(OutputVerification, ContactsFileHoldsCoulombFrictionWhileSliding) {
  std::vector<sim::NewParticle> balls(3);
  balls[0].position = {0, 0, kRadius - 5e-5};
  balls[0].velocity = {0.5, 0, 0};
  balls[1].position = {0.05, 0, 0.1};
  balls[1].velocity = {0, 0.25, 0};
  balls[2].position = {0.05, 0, 0.1 + 2 * kRadius - 1e-4};
  balls[2].velocity = {0, -0.25, 0};
  World world = world_with(ball_deck("[0, 0, 0]", ""), balls);
  sim::advance(world, 30);  // the springs reach the limit within about 10 steps
  const vtu_test::VtuContent contacts =
      vtu_test::read_vtu(read_text(write_frame_now(world, "quarry_contacts_friction") / "contacts_000000.vtu"));
  ASSERT_EQ(contacts.cell_count, 2u);
  const std::vector<Vec3> normal = vtu_test::vectors_of(contacts.arrays.at("normal_force"));
  const std::vector<Vec3> tangential = vtu_test::vectors_of(contacts.arrays.at("tangential_force"));
  for (std::size_t c = 0; c < 2; ++c) EXPECT_NEAR(norm(tangential[c]) / norm(normal[c]), 0.3, 1e-9) << "contact " << c;
  // The pair: friction on the line's first ball opposes its sliding relative to the other, +y
  // for the lower ball.
  const std::vector<Vec3> ends = vtu_test::vectors_of(contacts.arrays.at("Points"));
  EXPECT_LT(ends[0].z < ends[1].z ? tangential[0].y : -tangential[0].y, 0.0);
  EXPECT_LT(tangential[1].x, 0.0);  // the floor: on the ball, which slides along +x
  // monitors.csv counts both contacts, and the particle–particle one alone.
  const std::vector<std::string> columns = sim::monitor_columns(world, world.surfaces.size());
  const std::vector<double> row = sim::monitor_row(world, world.surfaces.size());
  EXPECT_EQ(row[column_index(columns, "contacts")], 2.0);
  EXPECT_EQ(row[column_index(columns, "particle_contacts")], 1.0);
}

// A particle monitor follows a ball in free fall: z(t) = z0 − g t²/2. Velocity Verlet integrates a
// constant acceleration exactly (Swope et al., J. Chem. Phys. 76 (1982) 637), so the columns
// match the closed form to rounding; vz = −g t, and the force column is the weight.
TEST(OutputVerification, ParticleMonitorFollowsFreeFall) {
  const std::string monitors = "monitors:\n  - {name: ball, type: particle, id: 1}\n  - {name: ghost, type: particle, id: 99}\n";
  std::vector<sim::NewParticle> ball(1);
  ball[0].position = {0.01, 0.02, 0.3};
  World world = world_with(ball_deck("[0, 0, -9.81]", monitors), ball);
  const std::vector<std::string> columns = sim::monitor_columns(world, world.surfaces.size());
  const std::size_t z = column_index(columns, "ball_z_m");
  const double start = world.time;  // s
  for (int row = 0; row < 5; ++row) {
    sim::advance(world, 4000);  // 0.02 s
    const std::vector<double> values = sim::monitor_row(world, world.surfaces.size());
    const double t = world.time - start;  // s
    EXPECT_NEAR(values[z], 0.3 - 0.5 * 9.81 * t * t, 1e-12) << "t " << t;
    EXPECT_NEAR(values[z + 3], -9.81 * t, 1e-11);                      // vz
    EXPECT_EQ(values[z - 2], 0.01);                                    // x untouched
    EXPECT_NEAR(values[z + 9] / (-9.81 * kMass), 1.0, 1e-12);          // Fz, the weight
    EXPECT_TRUE(std::isnan(values[column_index(columns, "ghost_x_m")]));  // no particle 99
  }
}

// Mass flow through a plane: balls released at rest at heights h_k above the plane cross it at
// t_k = sqrt(2 h_k / g) (free fall, exact under Velocity Verlet). Between two rows the sensor
// must give (number of t_k in the interval) × m / (row interval), and the total crossed mass N m.
// A checkpoint taken between two rows restores the sensor: the restored run's rows are the
// same to the bit.
TEST(OutputVerification, MassFlowCountsTheBallsCrossingAPlane) {
  const std::string monitors =
      "monitors:\n  - {name: outlet, type: mass_flow, point: [0, 0, 0.1], normal: [0, 0, -1]}\n";
  const double g = 9.81, plane = 0.1;  // m/s², m
  const double row_interval = 0.02;    // s (4000 steps)
  // Crossing times 0.013, 0.027, … s: none within 3 ms of a row time.
  std::vector<sim::NewParticle> balls;
  std::vector<double> crossing;  // s
  for (int k = 0; k < 12; ++k) {
    const double t = 0.0125 + 0.01 * k + (k % 3) * 0.001;  // s
    sim::NewParticle b;
    b.position = {-0.12 + 0.02 * k, 0.0, plane + 0.5 * g * t * t};
    balls.push_back(b);
    crossing.push_back(t);
  }
  World world = world_with(ball_deck("[0, 0, -9.81]", monitors), balls);
  const std::vector<std::string> columns = sim::monitor_columns(world, 1);
  const std::size_t flow = column_index(columns, "outlet_mass_flow_kg_s");
  const double start = world.time;
  EXPECT_EQ(sim::monitor_row(world, 1)[flow], 0.0);  // the first row sees no interval
  std::string checkpoint;
  std::vector<std::vector<double>> rows;
  for (int row = 1; row <= 9; ++row) {
    sim::advance(world, 2000);
    if (row == 4) checkpoint = sim::checkpoint_bytes(world, 0);  // between two rows
    sim::advance(world, 2000);
    rows.push_back(sim::monitor_row(world, 1));
    const double t1 = world.time - start, t0 = t1 - row_interval;  // s
    int crossed = 0;
    for (double t : crossing) crossed += t > t0 && t <= t1;
    EXPECT_NEAR(rows.back()[flow], crossed * kMass / row_interval, 1e-9 * kMass / row_interval) << "row " << row;
  }
  EXPECT_NEAR(rows.back()[flow + 1], 12 * kMass, 1e-12);

  sim::RestoredWorld restored = sim::read_checkpoint_bytes(checkpoint, "memory");
  sim::advance(restored.world, 2000);
  for (int row = 4; row <= 9; ++row) {
    const std::vector<double> again = sim::monitor_row(restored.world, 1);
    EXPECT_EQ(again, rows[static_cast<std::size_t>(row - 1)]) << "row " << row << " after the restart";
    sim::advance(restored.world, 4000);
  }
}

// Mass flow through a window of the plane (an outlet): `region`, a cylinder of radius 0.05 m
// about the z axis across the plane z = 0.1 m. Balls released at rest at heights h_k cross the
// plane at t_k = sqrt(2 h_k / g) (free fall, exact under Velocity Verlet) at their own x; only
// those with |x| ≤ 0.05 m count. Two more move sideways at 0.5 m/s: one starts outside the window
// and crosses the plane inside it, the other starts inside and crosses outside — the point where
// a ball crosses decides, not where it is at a row (rows are 4000 steps apart, 0.01 m of
// sideways travel). Between two rows the sensor gives (number of counted t_k in the interval)
// × m / (row interval); a checkpoint taken between two rows (with crossings not yet reported)
// restores it: the restored run's rows are the same to the bit.
TEST(OutputVerification, MassFlowThroughAWindowCountsOnlyWhatCrossesInsideIt) {
  const std::string monitors = R"(monitors:
  - {name: outlet, type: mass_flow, point: [0, 0, 0.1], normal: [0, 0, -1],
     region: {type: cylinder, base: [0, 0, 0.05], axis: [0, 0, 1], radius: 0.05, length: 0.1}}
)";
  const double g = 9.81, plane = 0.1, window = 0.05;  // m/s², m, m
  const double row_interval = 0.02;                   // s (4000 steps)
  std::vector<sim::NewParticle> balls;
  std::vector<double> crossing;  // s, of the balls that count
  for (int k = 0; k < 12; ++k) {
    const double t = 0.0125 + 0.01 * k + (k % 3) * 0.001;  // s: none within 3 ms of a row time
    sim::NewParticle b;
    b.position = {-0.12 + 0.02 * k, 0.0, plane + 0.5 * g * t * t};
    balls.push_back(b);
    if (std::abs(b.position.x) <= window) crossing.push_back(t);
  }
  // Sideways at 0.5 m/s, crossing at t = 0.0825 s (between the rows of 0.08 and 0.1 s): one
  // from (0, −0.02) along x, crossing at (0.04125, −0.02), r = 0.0458 m (inside: counts), at the
  // next row at (0.05, −0.02), r = 0.0539 (outside); the other from (0.035, 0.08) against y,
  // crossing at (0.035, 0.03875), r = 0.0522 (outside: does not count), at the next row at
  // (0.035, 0.03), r = 0.0461 (inside).
  const double t_side = 0.0825;  // s
  for (const auto& [start, velocity] : {std::pair{Vec3{0.0, -0.02, 0.0}, Vec3{0.5, 0.0, 0.0}},
                                        std::pair{Vec3{0.035, 0.08, 0.0}, Vec3{0.0, -0.5, 0.0}}}) {
    sim::NewParticle b;
    b.position = start + Vec3{0.0, 0.0, plane + 0.5 * g * t_side * t_side};
    b.velocity = velocity;
    balls.push_back(b);
  }
  crossing.push_back(t_side);  // the first one
  World world = world_with(ball_deck("[0, 0, -9.81]", monitors), balls);
  const std::vector<std::string> columns = sim::monitor_columns(world, 1);
  const std::size_t flow = column_index(columns, "outlet_mass_flow_kg_s");
  const double start = world.time;
  const auto advance = [](World& w, int steps) {
    for (int n = 0; n < steps; ++n) {
      sim::step(w);
      sim::count_flow_windows(w);  // as Output::after_step
    }
  };
  EXPECT_EQ(sim::monitor_row(world, 1)[flow], 0.0);
  std::string checkpoint;
  std::vector<std::vector<double>> rows;
  for (int row = 1; row <= 9; ++row) {
    advance(world, 2000);
    if (row == 5) {  // between two rows, after the sideways crossings: pending mass to carry
      EXPECT_GT(world.plane_crossings.at(0).pending_mass, 0.0);
      checkpoint = sim::checkpoint_bytes(world, 0);
    }
    advance(world, 2000);
    rows.push_back(sim::monitor_row(world, 1));
    const double t1 = world.time - start, t0 = t1 - row_interval;  // s
    int crossed = 0;
    for (double t : crossing) crossed += t > t0 && t <= t1;
    EXPECT_NEAR(rows.back()[flow], crossed * kMass / row_interval, 1e-9 * kMass / row_interval) << "row " << row;
  }
  EXPECT_NEAR(rows.back()[flow + 1], static_cast<double>(crossing.size()) * kMass, 1e-12);
  EXPECT_EQ(crossing.size(), 6u);  // five of the lattice, one sideways

  sim::RestoredWorld restored = sim::read_checkpoint_bytes(checkpoint, "memory");
  advance(restored.world, 2000);
  for (int row = 5; row <= 9; ++row) {
    const std::vector<double> again = sim::monitor_row(restored.world, 1);
    EXPECT_EQ(again, rows[static_cast<std::size_t>(row - 1)]) << "row " << row << " after the restart";
    advance(restored.world, 4000);
  }
}

// A checkpoint whose mass-flow sensor state is inconsistent (right checksum, written from a world
// changed by hand) is refused with what is wrong, never restored.
TEST(OutputVerification, CheckpointWithADamagedMassFlowStateIsRefused) {
  const std::string monitors =
      "monitors:\n  - {name: outlet, type: mass_flow, point: [0, 0, 0.1], normal: [0, 0, -1]}\n";
  std::vector<sim::NewParticle> ball(1);
  ball[0].position = {0, 0, 0.2};
  World original = world_with(ball_deck("[0, 0, -9.81]", monitors), ball);
  sim::monitor_row(original, 1);
  ASSERT_EQ(original.plane_crossings.size(), 1u);
  const std::vector<std::pair<std::string, std::function<void(World&)>>> cases = {
      {"a side other than -2 to 2", [](World& w) { w.plane_crossings[0].side_by_id[1] = 5; }},
      {"names particle ids never given", [](World& w) { w.plane_crossings[0].side_by_id.resize(w.next_id + 1); }},
      {"more mass-flow monitor states", [](World& w) { w.plane_crossings.resize(2); }},
      {"not finite", [](World& w) { w.plane_crossings[0].crossed_mass = std::nan(""); }},
      {"not finite", [](World& w) { w.plane_crossings[0].pending_mass = std::nan(""); }},
  };
  for (const auto& [expected, damage] : cases) {
    World world = original;
    damage(world);
    try {
      sim::read_checkpoint_bytes(sim::checkpoint_bytes(world, 0), "damaged.qck");
      ADD_FAILURE() << expected << ": restored";
    } catch (const UserError& e) {
      EXPECT_NE(e.diagnostics().format().find(expected), std::string::npos) << e.diagnostics().format();
    }
  }
  EXPECT_EQ(sim::read_checkpoint_bytes(sim::checkpoint_bytes(original, 0), "intact.qck").world.plane_crossings.size(), 1u);
}

// The typed monitors' files through a real run and restart: a run stopped after its checkpoint
// (taken between two monitor rows) and restarted writes the same monitors.csv, velocity profile
// and contacts series, to the bit, as the run that went through (the mass-flow sensor's sides
// come from the checkpoint). A particle monitor whose id never exists is a warning at the end.
TEST(OutputVerification, MonitorFilesOfARestartedRunAreThoseOfTheRunThatWentThrough) {
  namespace fs = std::filesystem;
  const std::string monitors = R"(monitors:
  - {name: outlet, type: mass_flow, point: [0, 0, 0.1], normal: [0, 0, -1]}
  - {name: column, type: stress, region: {type: box, min: [-0.1, -0.1, 0], max: [0.1, 0.1, 0.3]}}
  - {name: fall, type: velocity_profile, region: {type: box, min: [-0.1, -0.1, 0], max: [0.1, 0.1, 0.3]}, axis: z, bins: 6}
  - {name: ghost, type: particle, id: 99}
factories:
  - {name: drop, particle_type: sphere, region: {type: box, min: [-0.08, -0.08, 0.102], max: [0.08, 0.08, 0.16]}, count: 40}
)";
  std::string deck = ball_deck("[0, 0, -9.81]", monitors);
  deck.replace(deck.find("output: {interval: 0,"), 21,
               "output: {interval: 0, monitor_interval: 0.01, checkpoint_interval: 0.035,");
  const SimulationSpec spec = parse_deck_string(deck, "test.yaml");
  const fs::path straight = fs::path(::testing::TempDir()) / "quarry_monitors_straight";
  const fs::path split = fs::path(::testing::TempDir()) / "quarry_monitors_split";
  fs::remove_all(straight);
  fs::remove_all(split);
  sim::RunOptions options;
  options.quiet = true;
  options.threads = 1;  // 40 balls: a team of threads would only cost
  std::ostringstream log;
  options.log = &log;
  options.end_time = 0.08;  // long before the first ball reaches the floor
  World through = build_world(spec);
  options.output_directory = straight.string();
  sim::run(through, options);
  EXPECT_NE(log.str().find("test.yaml:22:39: monitor 'ghost': no particle had id 99"), std::string::npos) << log.str();

  World first = build_world(spec);
  options.output_directory = split.string();
  options.end_time = 0.05;  // the checkpoint at 0.035 s (between the rows of 0.03 and 0.04 s) is the last
  sim::run(first, options);
  options.end_time = 0.08;
  sim::restart((split / "checkpoint.qck").string(), options);
  for (const char* file : {"monitors.csv", "profile_fall.csv", "contacts.pvd", "contacts_000001.vtu"})
    EXPECT_EQ(read_text(split / file), read_text(straight / file)) << file;
  const std::string rows = read_text(straight / "monitors.csv");
  EXPECT_NE(rows.find("outlet_crossed_mass_kg"), std::string::npos);
  EXPECT_GT(through.plane_crossings.at(0).crossed_mass, 5 * kMass) << "the test must see crossings";
}

// Balls at rest on a grid with no contacts, given velocities (±a, ±b, 0) with zero mean: the
// kinetic stress of the box is σk_ab = (1/V) Σ m v_a v_b (e.g. Weinhart et al., Granular Matter
// 14 (2012) 289, eq. 21), i.e. ρ_bulk a², ρ_bulk b², 0 and ρ_bulk a b <s_x s_y> off the diagonal,
// ρ_bulk = N m / V; the contact part is zero. A fast ball outside the box does not count.
TEST(OutputVerification, KineticStressOfPrescribedVelocitiesIsDensityTimesTheirSquares) {
  const std::string monitors =
      "monitors:\n  - {name: box, type: stress, region: {type: box, min: [0, 0, 0.1], max: [0.08, 0.08, 0.14]}}\n";
  const double a = 0.3, b = 0.7;  // m/s
  std::vector<sim::NewParticle> balls;
  double sign_product = 0.0;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      for (int k = 0; k < 2; ++k) {
        sim::NewParticle p;
        p.position = {0.01 + 0.02 * i, 0.01 + 0.02 * j, 0.11 + 0.02 * k};
        const double sx = (i + j + k) % 2 ? 1.0 : -1.0, sy = (i + 2 * k) % 2 ? 1.0 : -1.0;
        p.velocity = {sx * a, sy * b, 0.0};
        sign_product += sx * sy;
        balls.push_back(p);
      }
  sim::NewParticle outside;
  outside.position = {0.15, 0.15, 0.12};
  outside.velocity = {10, 10, 10};
  balls.push_back(outside);
  World world = world_with(ball_deck("[0, 0, 0]", monitors), balls);
  const std::vector<std::string> columns = sim::monitor_columns(world, 1);
  const std::vector<double> row = sim::monitor_row(world, 1);
  const std::size_t contact = column_index(columns, "box_contact_sxx_Pa");
  const std::size_t kinetic = column_index(columns, "box_kinetic_sxx_Pa");
  const double volume = 0.08 * 0.08 * 0.04;       // m³
  const double density = 32 * kMass / volume;      // kg/m³, bulk
  EXPECT_NEAR(row[kinetic] / (density * a * a), 1.0, 1e-12);
  EXPECT_NEAR(row[kinetic + 1] / (density * b * b), 1.0, 1e-12);
  EXPECT_NEAR(row[kinetic + 2], 0.0, 1e-15);
  EXPECT_NEAR(row[kinetic + 3], density * a * b * sign_product / 32, 1e-12 * density * a * b);
  for (int c = 0; c < 6; ++c) EXPECT_EQ(row[contact + static_cast<std::size_t>(c)], 0.0);
}

// 01c — Stress of a settled bed: 300 beads at rest in a box whose side walls are frictionless,
// so they carry no weight (no Janssen effect; Janssen 1895) and a horizontal cut at height z
// carries the weight of the beads above it, W(z) = g Σ_{z_i > z} m_i. The mean σzz over a box
// of cross-section A and height H holding the whole bed is then (1/(A H)) ∫_0^H W(z) dz
// = g Σ m_i z_i / (A H): the hydrostatic-like profile ρ_bulk g (h − z) averaged over the
// column. The Love–Weber sum gives exactly this at static equilibrium (Σ_c f ⊗ l = Σ_i m_i g ⊗ x_i,
// the floor's contact points at z = 0), so what remains is the beads' residual motion (the
// kinetic part and unbalanced forces): 1 %.
TEST(OutputVerification, SettledBedStressIsTheWeightAbovePerArea) {
  SimulationSpec spec = parse_deck(testing_support::deck_path("tests/verification/01-settled-bed/deck.yaml"));
  for (InteractionSpec& interaction : spec.interactions)
    if (interaction.material_b.value == "steel") interaction.static_friction.value = 0.0;
  const double area = 0.03 * 0.03, height = 0.06;  // m², m
  MonitorSpec column;
  column.name.value = "column";
  column.kind.value = MonitorKind::stress;
  column.region = RegionSpec{};
  column.region->min.value = {0, 0, 0};
  column.region->max.value = {0.03, 0.03, height};
  spec.monitors.push_back(column);
  World world = start_world(spec);
  while (world.time < 0.3) sim::step(world);
  const std::vector<std::string> columns = sim::monitor_columns(world, 1);
  const std::vector<double> values = sim::monitor_row(world, 1);
  const double measured =
      values[column_index(columns, "column_contact_szz_Pa")] + values[column_index(columns, "column_kinetic_szz_Pa")];
  double moment = 0.0, top = 0.0;  // kg·m, m
  for (std::size_t i = 0; i < world.particles.size(); ++i) {
    moment += world.particles.position[i].z / world.particles.inv_mass[i];
    top = std::max(top, world.particles.position[i].z);
  }
  ASSERT_LT(top, height) << "the box must hold the whole bed";
  const double expected = 9.81 * moment / (area * height);  // Pa
  EXPECT_NEAR(measured / expected, 1.0, 0.01) << "measured " << measured << " Pa, expected " << expected << " Pa";
}

// A velocity profile of a shear field v_x = γ̇ z, balls at the bins' centres: each bin's mean
// velocity is γ̇ z_centre (the mass-weighted mean of equal values); an empty bin gives NaN.
TEST(OutputVerification, VelocityProfileOfAShearFieldIsLinear) {
  const std::string monitors =
      "monitors:\n  - {name: shear, type: velocity_profile, region: {type: box, min: [0, 0, 0.1], max: [0.1, 0.1, 0.2]},"
      " axis: z, bins: 5}\n";
  const double rate = 20.0;  // 1/s
  std::vector<sim::NewParticle> balls;
  for (int bin = 0; bin < 4; ++bin)  // the top bin stays empty
    for (int i = 0; i < 3; ++i) {
      sim::NewParticle p;
      p.position = {0.02 + 0.03 * i, 0.05 + 0.01 * bin, 0.11 + 0.02 * bin};
      p.velocity = {rate * p.position.z, 0.0, 0.0};
      balls.push_back(p);
    }
  World world = world_with(ball_deck("[0, 0, 0]", monitors), balls);
  const std::vector<sim::VelocityBin> profile = sim::velocity_profile(world, world.spec.monitors[0]);
  ASSERT_EQ(profile.size(), 5u);
  for (std::size_t bin = 0; bin < 4; ++bin) {
    EXPECT_NEAR(profile[bin].centre, 0.11 + 0.02 * static_cast<double>(bin), 1e-15);
    EXPECT_EQ(profile[bin].particles, 3u);
    EXPECT_NEAR(profile[bin].mean_velocity.x, rate * profile[bin].centre, 1e-13);
    EXPECT_EQ(profile[bin].mean_velocity.y, 0.0);
  }
  EXPECT_EQ(profile[4].particles, 0u);
  EXPECT_TRUE(std::isnan(profile[4].mean_velocity.x));
}

}  // namespace
}  // namespace quarry
