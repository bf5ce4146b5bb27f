// What `check` and build_world verify about a deck before a run (issue 19): the memory it needs
// against this machine's, and geometry no particle can reach.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <functional>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "io/deck.h"
#include "sim/exchange.h"
#include "sim/memory_estimate.h"
#include "sim/step.h"
#include "sim/time_step_choice.h"
#include "sim/world.h"

namespace quarry {
namespace {

// A deck with one factory and one surface line given by the caller.
SimulationSpec deck_with(const std::string& factory, const std::string& surface) {
  return parse_deck_string(R"(simulation:
  end_time: 0.5
  domain: {min: [-0.1, -0.1, 0], max: [0.1, 0.1, 0.3]}
materials:
  - {name: glass, density: 2500, youngs_modulus: 1.0e7, poisson_ratio: 0.25}
interactions:
  - {materials: [glass, glass]}
particle_types:
  - {name: bead, material: glass, size: {distribution: fixed, radius: 0.005}}
surfaces:
  - )" + surface + R"(
factories:
  - )" + factory + "\n",
                           "deck.yaml");
}

const std::string kPour =
    "{name: pour, particle_type: bead, region: {type: box, min: [-0.05, -0.05, 0.1], max: [0.05, "
    "0.05, 0.2]}, ";
const std::string kFloor =
    "{name: floor, type: plane, point: [0, 0, 0], normal: [0, 0, 1], material: glass}";

// The estimate counts what the deck asks for: a count target as given; a mass target over the
// mean particle mass (2500 kg/m³ · 4/3 π (5 mm)³ = 1.309e-3 kg, so 1.309 kg is 1000 particles);
// a cylinder's triangles as make_cylinder makes them.
TEST(MemoryEstimate, CountsTheParticlesAndTrianglesTheDeckAsksFor) {
  const sim::MemoryEstimate counted =
      sim::estimate_memory(deck_with(kPour + "count: 20000}", kFloor));
  EXPECT_EQ(counted.particles, 20000.0);
  EXPECT_EQ(counted.triangles, 2.0);
  EXPECT_DOUBLE_EQ(counted.bytes,
                   sim::kBaseBytes + 20000 * sim::kBytesPerParticle + 2 * sim::kBytesPerTriangle);
  const double bead_mass = 2500.0 * 4.0 / 3.0 * 3.14159265358979323846 * 0.005 * 0.005 * 0.005;
  const sim::MemoryEstimate by_mass = sim::estimate_memory(
      deck_with(kPour + "mass: " + std::to_string(1000 * bead_mass) + "}", kFloor));
  EXPECT_NEAR(by_mass.particles, 1000.0, 1e-3);
  const std::string drum =
      "{name: drum, type: cylinder, base: [0, 0, 0], axis: [0, 0, 1], radius: 0.08, length: 0.25, "
      "capped: true, resolution: 64, material: glass}";
  const SimulationSpec spec = deck_with(kPour + "count: 20}", drum);
  EXPECT_EQ(sim::estimate_memory(spec).triangles,
            static_cast<double>(build_world(spec).surfaces[0].mesh.triangle_count()));
}

// Refused above the memory given, with the figure, the machine's memory and the largest part,
// at that part's deck location; accepted below it.
TEST(MemoryEstimate, ADeckThatCannotFitIsRefusedAtItsLargestPart) {
  const SimulationSpec spec = deck_with(kPour + "count: 100000}", kFloor);
  const double need = sim::estimate_memory(spec).bytes;  // about 92 MB
  EXPECT_NO_THROW(sim::refuse_if_it_cannot_fit(spec, static_cast<std::uint64_t>(need) + 1));
  try {
    sim::refuse_if_it_cannot_fit(spec, static_cast<std::uint64_t>(need / 2));
    FAIL() << "expected a UserError";
  } catch (const UserError& e) {
    const std::string text = e.diagnostics().format();
    EXPECT_NE(text.find("deck.yaml:13:"), std::string::npos) << text;  // the factory's line
    EXPECT_NE(text.find("needs about 92 MB of memory"), std::string::npos) << text;
    EXPECT_NE(text.find("more than this machine's 46 MB"), std::string::npos) << text;
    EXPECT_NE(text.find("factory 'pour' (1e+05 particles)"), std::string::npos) << text;
    EXPECT_NE(text.find("hint:"), std::string::npos) << text;
  }
  EXPECT_GT(sim::machine_memory_bytes(), std::uint64_t{1} << 28);  // any machine that builds this
}

// A fixed surface wholly outside the domain is an error naming both boxes; one partly outside
// is built, with a warning counting the triangles no particle can reach.
TEST(WorldChecks, GeometryOutsideTheDomainIsReported) {
  try {
    build_world(deck_with(
        kPour + "count: 20}",
        "{name: floor, type: plane, point: [0, 0, -10], normal: [0, 0, 1], material: glass}"));
    FAIL() << "expected a UserError";
  } catch (const UserError& e) {
    const std::string text = e.diagnostics().format();
    EXPECT_NE(text.find("deck.yaml:11:"), std::string::npos) << text;
    EXPECT_NE(text.find("surface 'floor' lies wholly outside the domain"), std::string::npos)
        << text;
    EXPECT_NE(text.find("[-0.1, -0.1, 0] to [0.1, 0.1, 0.3] m"), std::string::npos) << text;
  }
  // A drum 1 m long through a 0.2 m domain: most of its side rings lie outside.
  const World world = build_world(deck_with(kPour + "count: 20}",
                                            "{name: drum, type: cylinder, base: [-0.5, 0, 0.15], "
                                            "axis: [1, 0, 0], radius: 0.1, length: 1.0, "
                                            "capped: false, resolution: 32, material: glass}"));
  const Surface& drum = world.surfaces[0].mesh;
  std::size_t outside = 0;
  for (const auto& t : drum.triangles) {
    Aabb box;
    for (int k = 0; k < 3; ++k) box.expand(drum.vertices[t[k]]);
    outside += overlaps(box, world.spec.simulation.domain.value) ? 0 : 1;
  }
  ASSERT_GT(outside, 0u);
  ASSERT_LT(outside, drum.triangle_count());
  const std::string expected = "surface 'drum': " + std::to_string(outside) + " of its " +
                               std::to_string(drum.triangle_count()) +
                               " triangles lie wholly outside the domain";
  bool warned = false;
  for (const std::string& w : world.warnings) warned |= w.find(expected) != std::string::npos;
  EXPECT_TRUE(warned) << expected;
}

// Surfaces are not wrapped across periodic faces: a floor that reaches past the face x = 0 of a
// periodic cell 0.1 m long but ends inside the cell is warned about (a particle wrapping through
// the face would land inside it); one spanning the period and a diameter (10 mm) beyond each
// face, or one wholly inside the cell, is not.
TEST(WorldChecks, ASurfaceCutByAPeriodicFaceIsWarnedAbout) {
  const auto warnings_with_floor = [](double centre_x, double size) {
    const SimulationSpec spec = parse_deck_string(fmt::format(R"(simulation:
  end_time: 0.5
  domain: {{min: [0, 0, -0.01], max: [0.1, 0.1, 0.1], periodic: [x, y]}}
materials:
  - {{name: glass, density: 2500, youngs_modulus: 1.0e7, poisson_ratio: 0.25}}
interactions:
  - {{materials: [glass, glass]}}
particle_types:
  - {{name: bead, material: glass, size: {{distribution: fixed, radius: 0.005}}}}
surfaces:
  - {{name: floor, type: plane, point: [{}, 0.05, 0], normal: [0, 0, 1], size: {}, material: glass}}
)",
                                                              centre_x, size),
                                                  "deck.yaml");
    std::string cut;
    for (const std::string& w : build_world(spec).warnings)
      if (w.find("surfaces are not wrapped") != std::string::npos) cut += w + "\n";
    return cut;
  };
  EXPECT_EQ(warnings_with_floor(0.05, 0.14), "");  // spans x and y by 20 mm beyond each face
  EXPECT_EQ(warnings_with_floor(0.05, 0.04), "");  // wholly inside the cell
  const std::string cut = warnings_with_floor(0.0, 0.14);  // x from -0.07 to 0.07
  EXPECT_NE(cut.find("surface 'floor' reaches past a periodic face of the domain along x but "
                     "spans only -0.07 to 0.07 m of the period 0 to 0.1 m"),
            std::string::npos)
      << cut;
  EXPECT_EQ(cut.find("along y"), std::string::npos) << cut;  // y still spans -0.02 to 0.12
  // Reaching past both faces but by less than a diameter on one side.
  EXPECT_NE(warnings_with_floor(0.054, 0.1 + 2 * 0.012).find("along x"), std::string::npos);
}

// A prescribed motion is refused when its fastest vertex moves more than half the smallest
// radius (5 mm beads) in one step, the run's tunnelling measure, at the key that sets its speed:
// a translation |v|, a vibration 2π f |A|, a rotation |ω| × the farthest vertex from the axis.
// Just below the bound the same motions are built.
TEST(WorldChecks, ASurfaceMovingMoreThanHalfTheSmallestRadiusPerStepIsRefused) {
  const SimulationSpec plain = deck_with(kPour + "count: 20}", kFloor);
  const double dt = choose_time_step(plain).dt;  // s
  const double limit = 0.5 * 0.005 / dt;               // m/s
  const auto floor_line = [](const std::string& motion) {
    return "{name: floor, type: plane, point: [0, 0, 0], normal: [0, 0, 1], size: 0.2, "
           "material: glass, motion: " + motion + "}";
  };
  const auto floor_moving = [&](const std::string& motion) {
    return deck_with(kPour + "count: 20}", floor_line(motion));
  };
  const auto translation = [&](double speed) {
    return fmt::format("{{type: translation, velocity: [{:.17g}, 0, 0]}}", speed);
  };
  // A square plate of side 0.2 m turning about the z axis through its centre: the corners are
  // 0.1 √2 m from the axis.
  const double arm = 0.1 * std::sqrt(2.0);  // m
  const auto rotation = [&](double speed) {
    return fmt::format("{{type: rotation, axis_point: [0, 0, 0], axis_direction: [0, 0, 1], "
                       "angular_velocity: {:.17g}}}", speed / arm);
  };
  const auto vibration = [&](double speed) {  // 100 Hz, amplitude along z
    return fmt::format("{{type: vibration, amplitude: [0, 0, {:.17g}], frequency: 100}}",
                       speed / (2.0 * std::numbers::pi * 100.0));
  };
  const std::vector<std::pair<std::function<std::string(double)>, std::string>> cases{
      {translation, "velocity"}, {rotation, "angular_velocity"}, {vibration, "amplitude"}};
  for (const auto& [motion, key] : cases) {
    EXPECT_NO_THROW(build_world(floor_moving(motion(0.9 * limit)))) << key;
    try {
      build_world(floor_moving(motion(1.1 * limit)));
      ADD_FAILURE() << "expected a UserError for " << key;
    } catch (const UserError& e) {
      const std::string text = e.diagnostics().format();
      EXPECT_NE(text.find("surface 'floor' moves at up to"), std::string::npos) << text;
      EXPECT_NE(text.find("more than half the radius of the smallest particle (0.005 m)"),
                std::string::npos)
          << text;
      // At the key's value on the surface's line (11; the line is "  - " + the surface).
      const std::string line = "  - " + floor_line(motion(1.1 * limit));
      const std::size_t column = line.find(key + ": ") + key.size() + 2 + 1;
      EXPECT_NE(text.find(fmt::format("deck.yaml:11:{}: error:", column)), std::string::npos)
          << text;
    }
  }
}

// A deck of soft spheres (issue 19: E = 5 MPa, R = 4 mm, impacts at 1.5 m/s) whose sound
// impacts overlap more than the 10 % guard: check warns with the Hertz peak, the guard and the
// modulus that would meet it. Peak overlap of two equal spheres, δ = (15 m* v² / (16 E* √R*))^(2/5)
// with m* = m/2, R* = R/2, E* = E / (2 (1 − ν²)) (Johnson 1985, eq. 11.23): 12.7 % of R.
TEST(WorldChecks, CheckWarnsWhenHertzPredictsAnOverlapAboveTheGuard) {
  const std::string deck = R"(simulation:
  end_time: 0.5
  impact_speed: 1.5
  domain: {min: [-0.1, -0.1, 0], max: [0.1, 0.1, 0.3]}
materials:
  - {name: soft, density: 2500, youngs_modulus: 5.0e6, poisson_ratio: 0.25}
  - {name: steel, density: 7800, youngs_modulus: 2.0e11, poisson_ratio: 0.3}
interactions:
  - {materials: [soft, soft]}
  - {materials: [soft, steel]}
particle_types:
  - {name: bead, material: soft, size: {distribution: fixed, radius: 0.004}}
surfaces:
  - {name: floor, type: plane, point: [0, 0, 0], normal: [0, 0, 1], material: steel}
)";
  const double radius = 0.004, v = 1.5;
  const double mass = 2500.0 * 4.0 / 3.0 * std::numbers::pi * radius * radius * radius;
  const double e_star = 5.0e6 / (2.0 * (1.0 - 0.25 * 0.25));
  const double peak =
      std::pow(15.0 * (mass / 2) * v * v / (16.0 * e_star * std::sqrt(radius / 2)), 0.4);
  EXPECT_NEAR(peak / radius, 0.127, 0.001);
  const TimeStepChoice choice = choose_time_step(parse_deck_string(deck, "soft.yaml"));
  EXPECT_NEAR(choice.peak_overlap_fraction, peak / radius, 1e-12);
  bool warned = false;
  for (const Diagnostic& d : choice.problems) {
    if (d.message.find(fmt::format(
            "Hertz theory predicts a peak overlap of {:.1f} % of the radius (two 'bead' "
            "particles",
            100 * peak / radius)) == std::string::npos)
      continue;
    warned = true;
    EXPECT_EQ(d.severity, Severity::warning);
    EXPECT_NE(d.message.find("above the overlap guard 10 %"), std::string::npos) << d.message;
    // (0.127 / 0.1)^(5/2) = 1.82: that modulus brings the peak down to the guard.
    EXPECT_NE(d.hint.find(fmt::format("{:.3g}-fold", std::pow(peak / radius / 0.1, 2.5))),
              std::string::npos)
        << d.hint;
  }
  EXPECT_TRUE(warned) << (choice.problems.empty() ? "no problems" : choice.problems.back().message);
  // Slower impacts (0.5 m/s: 8.4 %) stay under the guard: no warning.
  std::string slow = deck;
  slow.replace(slow.find("impact_speed: 1.5"), 17, "impact_speed: 0.5");
  EXPECT_LT(choose_time_step(parse_deck_string(slow, "slow.yaml")).peak_overlap_fraction, 0.1);
}

// The message of the physics error that stops 20,000 steps of the world, or "no stop".
std::string stop_of(World& world) {
  try {
    for (int n = 0; n < 20000; ++n) sim::step(world);
  } catch (const PhysicsError& e) {
    return e.what();
  }
  return "no stop";
}

// A wall that moves adds its speed to the expected impact speed: a particle at rest is struck
// at the wall's speed V (a particle falling at v meets it at up to v + V). A plate rams a bead
// at rest at 3 m/s, with no gravity and no impact_speed in the deck: the estimate is 0 + 3 m/s.
// Hertz (Johnson 1985, eq. 11.23 with m* = m, R* = R, E* = E / (2 (1 − ν²)) for glass on glass):
// δ = (15 m V² / (16 E* √R))^(2/5), 19.4 % of the radius at 3 m/s. `check` warns of it. A guard
// well below it (the dashpot takes some of the peak) stops on a sound impact, named as such,
// where it had been called energy created numerically, "far above the expected 0 m/s"; above
// it the bead is thrown ahead. An impact_speed below V is warned about.
TEST(WorldChecks, AMovingWallAddsItsSpeedToTheExpectedImpactSpeed) {
  constexpr double kSpeed = 3.0, kRadius = 0.005;  // m/s, m
  const std::string ram =
      fmt::format("{{name: ram, type: plane, point: [0.012, 0, 0.15], normal: [-1, 0, 0], "
                  "size: 0.1, material: glass, motion: {{type: translation, velocity: "
                  "[{}, 0, 0]}}}}",
                  -kSpeed);
  const auto spec_with = [&](double guard) {
    SimulationSpec spec = deck_with(kPour + "count: 1}", ram);
    spec.factories.clear();
    spec.simulation.gravity = Vec3{};
    spec.simulation.max_overlap_fraction = guard;
    return spec;
  };
  const double mass = 2500.0 * 4.0 / 3.0 * std::numbers::pi * std::pow(kRadius, 3);  // kg
  const double e_star = 1.0e7 / (2.0 * (1.0 - 0.25 * 0.25));                           // Pa
  const double peak =
      std::pow(15.0 * mass * kSpeed * kSpeed / (16.0 * e_star * std::sqrt(kRadius)), 0.4);  // m
  EXPECT_NEAR(peak / kRadius, 0.194, 0.001);

  const SimulationSpec spec = spec_with(0.6 * peak / kRadius);
  const World built = build_world(spec);
  EXPECT_EQ(built.fastest_surface.speed, kSpeed);
  EXPECT_EQ(built.fastest_surface.name, "ram");
  EXPECT_EQ(choose_time_step(spec).impact_speed, 0.0);  // nothing falls, nothing is launched
  const TimeStepChoice choice = choose_time_step(spec, built.fastest_surface);
  EXPECT_EQ(choice.impact_speed, kSpeed);
  EXPECT_EQ(choice.dt, choose_time_step(spec).dt);  // the step does not depend on it
  // Bead on the wall: the softest impact at 3 m/s (two beads, m/2 and R/2: 16.9 %).
  EXPECT_NEAR(choice.peak_overlap_fraction, peak / kRadius, 1e-12);
  bool warned = false;
  for (const std::string& w : built.warnings)
    warned |= w.find(fmt::format("at the impact speed 3 m/s Hertz theory predicts a peak overlap "
                                 "of {:.1f} %", 100 * peak / kRadius)) != std::string::npos;
  EXPECT_TRUE(warned) << (built.warnings.empty() ? "no warnings" : built.warnings.back());

  World world = build_world(spec);
  sim::initialize(world);
  std::vector<sim::NewParticle> bead(1);
  bead[0].position = {0.0, 0, 0.15};  // 7 mm from the plate
  sim::add_particles(world, bead);
  const std::string stop = stop_of(world);
  EXPECT_NE(stop.find("penetrates surface 'ram'"), std::string::npos) << stop;
  EXPECT_NE(stop.find("within the expected 3 m/s: this overlap is what contact theory predicts"),
            std::string::npos)
      << stop;
  // Under a guard above the peak the same impact runs on.
  World above = build_world(spec_with(1.1 * peak / kRadius));
  sim::initialize(above);
  sim::add_particles(above, bead);
  for (int n = 0; n < 100; ++n) sim::step(above);  // struck after 2.3 ms, 8 ms ago
  ASSERT_EQ(above.particles.size(), 1u);
  // Thrown ahead of the plate: at V (1 + e) against the plate, between V and 2V.
  EXPECT_LT(above.particles.velocity[0].x, -kSpeed);
  EXPECT_GT(above.particles.velocity[0].x, -2.0 * kSpeed);

  SimulationSpec slow = spec_with(0.2);
  slow.simulation.impact_speed = Located<double>(1.0);
  bool below = false;
  for (const Diagnostic& d : choose_time_step(slow, build_world(slow).fastest_surface).problems)
    below |= d.severity == Severity::warning &&
             d.message.find("impact_speed 1 m/s is below the speed 3 m/s of surface 'ram'") !=
                 std::string::npos;
  EXPECT_TRUE(below);
}

// The overlap guard's message tells physics from a blow-up: two beads meeting at the deck's
// expected speed overlap as Hertz predicts (a guard set below that peak trips on it); two beads
// given 30 times that speed hold energy no impact of the deck could bring.
TEST(WorldChecks, OverlapGuardSaysWhetherTheOverlapIsPhysicsOrABlowUp) {
  const auto stop_message = [](double speed, double guard, double stiffening = 1.0) -> std::string {
    SimulationSpec spec = deck_with(kPour + "count: 1}", kFloor);
    spec.factories.clear();
    for (MaterialSpec& m : spec.materials) m.youngs_modulus = m.youngs_modulus.value * stiffening;
    spec.simulation.gravity = Vec3{};
    spec.simulation.impact_speed = Located<double>(1.0);
    spec.simulation.max_overlap_fraction = guard;
    World world = build_world(spec);
    sim::initialize(world);
    std::vector<sim::NewParticle> pair(2);
    pair[0].position = {-0.0052, 0, 0.15};
    pair[1].position = {0.0052, 0, 0.15};
    pair[0].velocity = {0.5 * speed, 0, 0};
    pair[1].velocity = {-0.5 * speed, 0, 0};
    sim::add_particles(world, pair);
    return stop_of(world);
  };
  const std::string physics = stop_message(1.0, 0.02);
  EXPECT_NE(physics.find("within the expected 1 m/s: this overlap is what contact theory predicts"),
            std::string::npos)
      << physics;
  EXPECT_NE(physics.find("stiffen the material"), std::string::npos) << physics;
  // The stiffening the hint names is enough: the same impact with that modulus stays under the
  // guard (its peak at 80 % of the limit, Hertz: E ~ delta^(-5/2)).
  const std::size_t fold = physics.find("-fold Young's modulus");
  ASSERT_NE(fold, std::string::npos) << physics;
  const double stiffening = std::stod(physics.substr(physics.rfind(' ', fold) + 1));
  EXPECT_GT(stiffening, 1.2) << physics;
  EXPECT_EQ(stop_message(1.0, 0.02, stiffening), "no stop");
  const std::string blow_up = stop_message(30.0, 0.1);
  EXPECT_NE(blow_up.find("far above the expected 1 m/s: energy was created numerically"),
            std::string::npos)
      << blow_up;
  EXPECT_NE(blow_up.find("reduce simulation.time_step"), std::string::npos) << blow_up;
}

// A heavy particle landing on a light one that lies on the floor presses it further than any
// impact of two light ones at the deck's speed (a 15 mm boulder, 27 bead masses, at 1 m/s on a
// 5 mm bead): the guard's message says a heavier particle can do that, with the stiffening and
// the time step both named, and the same landing under a guard of 50 % runs to the end (it is
// physics, not an instability). Hertz at 1 m/s, bead on the floor: 9.3 % of its radius, under
// the 12 % guard; the pressed bead goes beyond it.
TEST(WorldChecks, OverlapGuardNamesAHeavierParticlePressingAPair) {
  const auto stop_message = [](double guard) -> std::string {
    SimulationSpec spec = deck_with(kPour + "count: 1}", kFloor);
    spec.factories.clear();
    spec.simulation.gravity = Vec3{};
    spec.simulation.impact_speed = Located<double>(1.0);
    ParticleTypeSpec boulder = spec.particle_types.front();
    boulder.name.value = "boulder";
    boulder.size.radius.value = 0.015;  // m
    spec.particle_types.push_back(boulder);
    spec.simulation.max_overlap_fraction = guard;
    World world = build_world(spec);
    sim::initialize(world);
    std::vector<sim::NewParticle> pair(2);
    pair[0].type = 0;  // the bead, resting on the floor
    pair[0].position = {0, 0, 0.005};
    pair[1].type = 1;  // the boulder, 1 mm above it, landing at 1 m/s
    pair[1].position = {0, 0, 0.005 + 0.020 + 0.001};
    pair[1].velocity = {0, 0, -1.0};
    sim::add_particles(world, pair);
    return stop_of(world);
  };
  const std::string pressed = stop_message(0.12);
  std::printf("%s\n", pressed.c_str());
  EXPECT_NE(pressed.find("but a 'boulder' particle"), std::string::npos) << pressed;
  EXPECT_NE(pressed.find("a heavier particle or a dense stream pressing the pair"),
            std::string::npos)
      << pressed;
  EXPECT_NE(pressed.find("-fold Young's modulus"), std::string::npos) << pressed;
  EXPECT_NE(pressed.find("simulation.time_step"), std::string::npos) << pressed;
  EXPECT_EQ(stop_message(0.5), "no stop");
}

}  // namespace
}  // namespace quarry
