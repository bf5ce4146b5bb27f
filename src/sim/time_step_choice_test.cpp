// The gravity check of choose_time_step: a particle at rest under its weight presses into a
// surface, or into another particle resting there, by the Hertz static overlap
// δ = (3 m g / (4 E* √R*))^(2/3) (Johnson, "Contact Mechanics" 1985, eq. 4.22: F = 4/3 E* √R* δ^(3/2)),
// and a gravity beyond which δ/R passes the overlap guard is an error at simulation.gravity.
#include "sim/time_step_choice.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "io/deck.h"

namespace quarry {
namespace {

// Glass beads of R 2 to 5 mm (E 1e7 Pa, ν 0.25, 2500 kg/m³) on a steel plane; gravity
// `gravity` m/s² down, the overlap guard 10 %.
SimulationSpec beads_on_steel(double gravity) {
  const std::string deck = R"(
simulation:
  end_time: 1.0
  impact_speed: 1.0
  max_overlap_fraction: 0.1
  gravity: [0, 0, -)" + std::to_string(gravity) + R"(]
  domain: {min: [-0.1, -0.1, 0.0], max: [0.1, 0.1, 0.2]}
materials:
  - {name: glass, density: 2500, youngs_modulus: 1.0e7, poisson_ratio: 0.25}
  - {name: steel, density: 7800, youngs_modulus: 2.0e11, poisson_ratio: 0.3}
interactions:
  - {materials: [glass, glass], restitution: 0.5, static_friction: 0.5}
  - {materials: [glass, steel], restitution: 0.5, static_friction: 0.5}
particle_types:
  - {name: bead, material: glass, size: {distribution: uniform, min_radius: 0.002, max_radius: 0.005}}
surfaces:
  - {name: floor, type: plane, point: [0, 0, 0], normal: [0, 0, 1], size: 0.2, material: steel}
factories:
  - {name: pour, particle_type: bead, region: {type: box, min: [-0.05, -0.05, 0.05], max: [0.05, 0.05, 0.15]}, count: 10}
)";
  return parse_deck_string(deck, "beads.yaml");
}

bool has_gravity_error(const TimeStepChoice& choice) {
  for (const Diagnostic& d : choice.problems)
    if (d.severity == Severity::error && d.where.line == 6) return true;
  return false;
}

TEST(TimeStepChoice, AGravityTheRestingContactsCannotCarryIsAnErrorAtItsKey) {
  // The worst contact is the largest bead on another: R* = R/2 and E* = E / (2 (1 − ν²)), softer
  // than glass on steel. The guard is met at g* = 4 E* √R* (0.1 R)^(3/2) / (3 m).
  const double radius = 0.005, youngs = 1.0e7 / (2.0 * (1.0 - 0.25 * 0.25));  // m, Pa
  const double mass = 2500.0 * 4.0 / 3.0 * std::numbers::pi * radius * radius * radius;  // kg
  const double limit =
      4.0 * youngs * std::sqrt(0.5 * radius) * std::pow(0.1 * radius, 1.5) / (3.0 * mass);
  const TimeStepChoice earth = choose_time_step(beads_on_steel(9.81));
  // δ/R at 9.81 m/s²: 0.1 (9.81 / g*)^(2/3).
  EXPECT_NEAR(earth.resting_overlap_fraction, 0.1 * std::pow(9.81 / limit, 2.0 / 3.0),
              1e-9 * earth.resting_overlap_fraction);
  EXPECT_NE(earth.resting_overlap_limiter.find("on another"), std::string::npos)
      << earth.resting_overlap_limiter;
  EXPECT_FALSE(has_gravity_error(earth));
  EXPECT_FALSE(has_gravity_error(choose_time_step(beads_on_steel(0.98 * limit))));
  EXPECT_TRUE(has_gravity_error(choose_time_step(beads_on_steel(1.02 * limit))));
  // What passed check before: the run stopped at its first contact.
  EXPECT_TRUE(has_gravity_error(choose_time_step(beads_on_steel(1e308))));
}

}  // namespace
}  // namespace quarry
