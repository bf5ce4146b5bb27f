// 02 — Restitution at the default time step (issue #20): the rebound of a Hertz–Mindlin impact
// with EDEM's dashpot, β = ln e / sqrt(ln² e + π²) (Tsuji et al. 1992; EDEM theory reference
// guide), is v_out / v_in = e; here the whole engine at 0.2 T_R (the default step, ~15 steps in
// the 0.7 ms contact of the ball on the floor at 1 m/s) for e = 0.1 … 0.9, sphere on a wall and
// sphere on sphere, at several phases (where the first step in contact falls). The dashpot's
// window and implicit velocity (contact/dashpot_window.h) make it within 1 % at any phase; the
// force at the centre of each step with an explicit lead gave e_out / e = 0.905–1.007 at
// e = 0.1 and 0.918–1.026 at e = 0.2 over these phases (this test on the code before).
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "io/deck.h"
#include "sim/step.h"
#include "sim/time_step_choice.h"
#include "verification/test_support.h"

namespace quarry {
namespace {

using testing_support::start_world;

// Ball and floor of verification 02 (steel-like density, soft: E = 100 MPa), no gravity (at
// e = 0.1 the 1.8 mm/s that gravity adds during a contact would be 1.8 % of the rebound).
// `particles` places the spheres; the step is the default, fraction × T_R.
std::string impact_deck(double restitution, double rayleigh_fraction,
                        const std::string& particles) {
  return fmt::format(R"(simulation:
  end_time: 0.05
  time_step: {{rayleigh_fraction: {}}}
  impact_speed: 1.0
  gravity: [0, 0, 0]
  domain: {{min: [-0.1, -0.1, -0.1], max: [0.1, 0.1, 0.2]}}
materials:
  - {{name: ball, density: 7800, youngs_modulus: 1.0e8, poisson_ratio: 0.3}}
interactions:
  - {{materials: [ball, ball], restitution: {}, static_friction: 0.3}}
particle_types:
  - {{name: sphere, material: ball, size: {{distribution: fixed, radius: 0.005}}}}
surfaces:
  - {{name: floor, type: plane, point: [0, 0, 0], normal: [0, 0, 1], size: 0.1, material: ball}}
particles:
{}output:
  directory: out_restitution_test
  interval: 0
  plots: false
)",
                     rayleigh_fraction, restitution, particles);
}

// Ratio of the normal speeds after and before the contact (1): `approach` is the closing
// speed (m/s); `separating(world)` the separation speed once nothing touches any more.
template <typename Separating>
double rebound_ratio(const std::string& deck, double approach, Separating separating) {
  World world = start_world(parse_deck_string(deck, "restitution.yaml"));
  bool touched = false;
  for (int step = 0; step < 20000; ++step) {
    sim::step(world);
    const bool touching = world.wall_contact_count() + world.pair_contact_count() > 0;
    touched |= touching;
    if (touched && !touching) {
      // The last step's force has half its kick still to come, and a dashpot window may reach
      // past the last overlap: a few steps more of free flight (no gravity).
      for (int more = 0; more < 4; ++more) sim::step(world);
      return separating(world) / approach;
    }
  }
  ADD_FAILURE() << "the contact did not end";
  return 0.0;
}

// The sphere starts `gap` (m) above the floor at 1 m/s downwards.
double ball_on_floor(double e, double fraction, double gap) {
  const std::string particles = fmt::format(
      "  - {{type: sphere, position: [0, 0, {:.17g}], velocity: [0, 0, -1.0]}}\n", 0.005 + gap);
  return rebound_ratio(impact_deck(e, fraction, particles), 1.0,
                       [](const World& w) { return w.particles.velocity[0].z; });
}

// Two spheres `gap` (m) apart along x, closing at 1 m/s (0.5 m/s each), far above the floor.
double ball_on_ball(double e, double fraction, double gap) {
  const double x = 0.005 + 0.5 * gap;  // m
  const std::string particles = fmt::format(
      "  - {{type: sphere, position: [{:.17g}, 0, 0.1], velocity: [-0.5, 0, 0]}}\n"
      "  - {{type: sphere, position: [{:.17g}, 0, 0.1], velocity: [0.5, 0, 0]}}\n",
      x, -x);
  return rebound_ratio(impact_deck(e, fraction, particles), 1.0, [](const World& w) {
    const ParticleStore& p = w.particles;
    const std::size_t right = p.position[0].x > p.position[1].x ? 0 : 1;
    return p.velocity[right].x - p.velocity[1 - right].x;
  });
}

// The default step of the deck (s): what the phases are fractions of.
double default_step(double fraction) {
  const std::string one = "  - {type: sphere, position: [0, 0, 0.1]}\n";
  return choose_time_step(parse_deck_string(impact_deck(0.5, fraction, one), "restitution.yaml"))
      .dt;
}

TEST(Verification, RestitutionIsTheInputOneAtTheDefaultStepAtAnyPhase) {
  const double dt = default_step(0.2);  // s
  for (const double e : {0.1, 0.2, 0.3, 0.5, 0.9}) {
    double lowest = 2.0, highest = 0.0;  // e_out / e over the phases
    for (int phase = 0; phase < 6; ++phase) {
      // The first contact falls at phase/6 of a step after the step that starts 2 steps away.
      const double gap = (2.0 + phase / 6.0) * dt * 1.0;  // m, at 1 m/s
      const double wall = ball_on_floor(e, 0.2, gap) / e;
      const double pair = ball_on_ball(e, 0.2, gap) / e;
      EXPECT_NEAR(wall, 1.0, 0.01) << "sphere on the floor, e = " << e << ", phase " << phase;
      EXPECT_NEAR(pair, 1.0, 0.01) << "sphere on sphere, e = " << e << ", phase " << phase;
      lowest = std::min({lowest, wall, pair});
      highest = std::max({highest, wall, pair});
    }
    std::printf("e = %.1f at 0.2 T_R: e_out / e in [%.4f, %.4f]\n", e, lowest, highest);
  }
}

// Coarser and finer than the default: 0.4 T_R (the step the EDEM guidance allows for low
// coordination numbers, ~7 steps in the contact) within 2 %, 0.05 T_R within 0.5 %.
TEST(Verification, RestitutionConvergesWithTheStep) {
  for (const auto& [fraction, tolerance] : {std::pair{0.4, 0.02}, std::pair{0.05, 0.005}}) {
    const double dt = default_step(fraction);  // s
    for (const double e : {0.1, 0.5, 0.9}) {
      for (int phase = 0; phase < 3; ++phase) {
        const double gap = (2.0 + phase / 3.0) * dt;  // m
        EXPECT_NEAR(ball_on_floor(e, fraction, gap) / e, 1.0, tolerance)
            << "e = " << e << " at " << fraction << " T_R, phase " << phase;
        EXPECT_NEAR(ball_on_ball(e, fraction, gap) / e, 1.0, tolerance)
            << "e = " << e << " at " << fraction << " T_R, phase " << phase;
      }
    }
  }
}

}  // namespace
}  // namespace quarry
