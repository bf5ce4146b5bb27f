// Stability of the coupling PERIOD (period_stability.h, docs/fem.md "Stability of PERIOD"): the
// per-period map of one particle on one node against an independent computation, and the real
// coupler below and above the limit it gives.
#include "fsi/period_stability.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <string>

#include "fsi/plate_bulk_data.h"
#include "fsi/structure_adapter.h"
#include "fsi/structure_coupler.h"
#include "io/deck.h"
#include "sim/step.h"

namespace quarry::fsi {
namespace {

// The limit against the spectral radius of the same map computed separately (Python, the 3×3
// map's eigenvalues by Durand–Kerner iteration, scan and bisection; docs/fem.md's table), and
// the small-ζ asymptote ω·P_crit → 2ζ (1 + μ)^{3/2} / √μ (μ = m_n/m_p) of the lag as a negative
// damping k·P·m_p/(m_p + m_n) against the dashpot 2ζ√(k m_p).
TEST(PeriodStability, CriticalOmegaPeriod) {
  EXPECT_NEAR(critical_omega_period(0.2556, 0.46), 0.6942, 1e-3);  // e = 0.4 Hertz–Mindlin
  EXPECT_NEAR(critical_omega_period(0.2556, 0.23), 0.6001, 1e-3);
  EXPECT_NEAR(critical_omega_period(0.05, 1.0), 0.2723, 1e-3);
  EXPECT_NEAR(critical_omega_period(0.3, 0.01), 0.1638, 1e-3);  // light node: c·P/m_n ≈ 1
  EXPECT_NEAR(critical_omega_period(0.001, 1.0), 2.0 * 0.001 * std::pow(2.0, 1.5), 2e-5);
  EXPECT_EQ(critical_omega_period(0.0, 1.0), 0.0);
  EXPECT_EQ(critical_omega_period(0.2556, 10.0), std::numeric_limits<double>::infinity());
  EXPECT_TRUE(exchange_is_stable(0.5, 0.2556, 0.46));
  EXPECT_FALSE(exchange_is_stable(1.0, 0.2556, 0.46));
}

// The smallest coupled scene in which the particle–node pair is the model's two-mass
// oscillator: a 2 × 2 clamped plate whose only free node, the centre, is raised 0.9 mm into a
// shallow pyramid (so that a sphere on it touches the vertex alone: in a dent it would touch
// every face around the node), one frictionless sphere resting on that vertex under gravity.
// The plate is soft (E 15.6 MPa): its stiffness at the node, estimated ~1e3 N/m (clamped square
// plate under a centre load, w = 0.0056 F a²/D, Timoshenko & Woinowsky-Krieger, plates with
// built-in edges; plus the pyramid's membrane part E t (2h/a)²), is ~1 % of the contact's (the
// model with that spring to ground moves the limit by 0.2 %), so the node is a free mass
// m_n = ρ t (a/2)² at the contact's frequency. m_n/m_p ≈ 0.5 and e = 0.4 (ζ = √(5/6)|β| = 0.256),
// the flagship's ratio and restitution. ω = √(S_n/m*) with the Hertz tangent stiffness
// S_n = 2E*√(R δ₀) at the static overlap δ₀ = (3 m_p g / (4 E* √R))^(2/3) (Johnson, Contact
// Mechanics, §4.2): the linearisation the model assumes.
struct Oscillation {
  double omega = 0.0;           // rad/s
  double critical = 0.0;        // s, P_crit from critical_omega_period
  double early = 0.0, late = 0.0;  // J, the largest ½ m* v_rel² in the first and last 2 ms
  std::size_t messages = 0;
};

constexpr double kSide = 0.0182, kThickness = 0.001, kBump = 0.0009, kRadius = 0.005;  // m

std::string pyramid_plate() {
  const testing::PlateCards plate{.divisions = 2, .side = kSide, .thickness = kThickness,
                                  .youngs_modulus = 1.56e7, .poisson_ratio = 0.3, .density = 7850.0};
  std::string text = testing::plate_bulk_data(plate);
  // GRID 5 is the centre node (row 1, column 1 of the 3 × 3 grid): z from 0 to the bump.
  const std::size_t line = text.find("GRID,5,,");
  const std::size_t end = text.find('\n', line);
  const std::size_t z = text.rfind(",0.", end);
  text.replace(z, end - z, "," + testing::bulk_real(kBump));
  return text;
}

const std::string kDeck = R"(simulation:
  end_time: 1.0
  time_step: 1.0e-6
  impact_speed: 0.01                # m/s: read only by the coupler's PERIOD warning
  gravity: [0, 0, -9.81]
  domain: {min: [-0.01, -0.01, -0.01], max: [0.03, 0.03, 0.03]}
materials:
  - {name: rock, density: 2500, youngs_modulus: 1.0e9, poisson_ratio: 0.25}
  - {name: steel, density: 7850, youngs_modulus: 2.0e11, poisson_ratio: 0.3}
interactions:
  - {materials: [rock, rock], restitution: 0.4, static_friction: 0.0}
  - {materials: [rock, steel], restitution: 0.4, static_friction: 0.0}
particle_types:
  - {name: ball, material: rock, size: {distribution: fixed, radius: 0.005}}
factories:
  - name: one
    particle_type: ball
    region: {type: box, min: [0.0039, 0.0039, 0.0012], max: [0.0143, 0.0143, 0.0122]}
    count: 1
output: {directory: out_fsi_period, interval: 0, plots: false}
)";

Oscillation run_at(double fraction_of_critical, double end_time) {
  CoupledStructure structure = coupled_structure_from_text(pyramid_plate(), "pyramid.bdf");
  SimulationSpec spec = parse_deck_string(kDeck, "ball.yaml");
  spec.surfaces.push_back(coupling_surface_spec(structure.mesh, "plate", "steel"));
  const std::size_t surface = spec.surfaces.size() - 1;
  World world = build_world(spec);
  sim::initialize(world);
  EXPECT_EQ(world.particles.size(), 1u);
  const fem::ShellModel& model = structure.adapted.model;
  int centre = -1;
  for (std::size_t n = 0; n < model.nodes.size(); ++n)
    if (model.nodes[n].z > 0.5 * kBump) centre = static_cast<int>(n);
  EXPECT_GE(centre, 0);
  fem::ShellSolver solver(model);
  const double node_mass = solver.nodal_masses()[static_cast<std::size_t>(centre)];  // kg
  const double particle_mass = 1.0 / world.particles.inv_mass[0];                   // kg

  // The linearised contact at rest under the weight.
  const double compliance = (1.0 - 0.25 * 0.25) / 1.0e9 + (1.0 - 0.3 * 0.3) / 2.0e11;  // 1/Pa
  const double modulus = 1.0 / compliance;                                               // E* (Pa)
  const double overlap = std::pow(3.0 * particle_mass * 9.81 / (4.0 * modulus * std::sqrt(kRadius)), 2.0 / 3.0);
  const double stiffness = 2.0 * modulus * std::sqrt(kRadius * overlap);            // N/m
  const double effective_mass = 1.0 / (1.0 / particle_mass + 1.0 / node_mass);      // kg
  const double beta = std::log(0.4) / std::sqrt(std::log(0.4) * std::log(0.4) + std::numbers::pi * std::numbers::pi);
  const double zeta = -std::sqrt(5.0 / 6.0) * beta;
  Oscillation run;
  run.omega = std::sqrt(stiffness / effective_mass);
  run.critical = critical_omega_period(zeta, node_mass / particle_mass) / run.omega;

  // At rest on the apex at the static overlap (the node takes the weight from the second period).
  const Vec3 apex = model.nodes[static_cast<std::size_t>(centre)];
  world.particles.position[0] = {apex.x, apex.y, apex.z + kRadius - overlap};
  world.particles.velocity[0] = {};
  world.particles.angular_velocity[0] = {};

  // Whole DEM steps per period; the structure at a small fraction of its (soft) stable step, so
  // that it takes several steps in each period.
  const double period = std::round(fraction_of_critical * run.critical / world.dt) * world.dt;  // s
  const double fraction = std::min(0.9, 0.1 * period / solver.stable_time_step().time_step);
  StructureCoupler coupler(world, surface, solver, structure.mesh.node_of_vertex,
                           {.schedule = resolve_schedule(period, std::nullopt, 1.0),
                            .structure_step_fraction = fraction});
  while (world.time < end_time) {
    coupler.advance_period();
    const double relative = world.particles.velocity[0].z - solver.velocities()[static_cast<std::size_t>(centre)].z;
    const double energy = 0.5 * effective_mass * relative * relative;  // J
    if (world.time <= 0.002) run.early = std::max(run.early, energy);
    if (world.time >= end_time - 0.002) run.late = std::max(run.late, energy);
  }
  run.messages = coupler.messages().size();
  std::printf("PERIOD %.3f x P_crit: m_p %.4e kg, m_n %.4e kg (ratio %.3f), S_n %.4e N/m, zeta %.4f, omega %.5g rad/s, "
              "P_crit %.4g s (omega P %.4f), PERIOD %.4g s; 1/2 m* v_rel^2 first 2 ms %.3e J, last 2 ms %.3e J; "
              "structure step %.3e s\n",
              fraction_of_critical, particle_mass, node_mass, node_mass / particle_mass, stiffness, zeta, run.omega,
              run.critical, run.critical * run.omega, period, run.early, run.late, coupler.structure_step());
  for (const std::string& line : coupler.messages()) std::printf("  %s\n", line.c_str());
  return run;
}

// Half the limit: the linear map's spectral radius is 0.89 per period, the contact mode decays;
// twice the limit: 1.5 per period, it grows until the particle bounces on the node, as the
// flagship's structure did. Asserted: a factor 10 each way between the largest ½ m* v_rel² of
// the first and of the last 2 ms (measured 0.019 and 34; below, the linear decay would be far
// lower: what is left, ~6e-12 J, is of the size of the slow mode of particle and node together
// on the plate, ~1e-12 J). A sweep of PERIOD with this scene put the
// boundary where the map does (docs/fem.md): decay at 52 µs (ω·P 0.686), near neutral at
// 53–55 µs, growth ×1.4e3 over 40 ms at 56 µs (0.739), against ω·P_crit = 0.707 (53.6 µs).
TEST(PeriodStability, CoupledParticleOnNodeBelowAndAboveTheLimit) {
  const Oscillation below = run_at(0.5, 0.01), above = run_at(2.0, 0.01);
  EXPECT_GT(below.early, 0.0);
  EXPECT_LT(below.late, 0.1 * below.early);
  EXPECT_GT(above.late, 10.0 * above.early);
}

}  // namespace
}  // namespace quarry::fsi
