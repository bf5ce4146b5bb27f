// The split of a calibration's particle stages into a part per step and a part per particle
// (sim/estimate.h, particle_stage_fit): least squares on synthetic timings. The minimum
// fluidisation velocity (Wen & Yu 1966) against hand calculations and its Stokes limit, and the
// test for a deck whose fluid carries its particles.
#include "sim/estimate.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "io/deck.h"

namespace quarry::sim {
namespace {

// t = a + b n exactly, n growing from 0 to 99 (a pour beginning): the fit returns a.
TEST(EstimateFit, RecoversTheFixedPartOfAGrowingCount) {
  const double a = 4.8e-5, b = 2.5e-7;  // s per step, s per particle-step
  std::vector<double> counts, seconds;
  for (int k = 0; k < 400; ++k) {
    counts.push_back(k / 4);
    // ±1 us of alternating timer noise, which least squares averages out.
    seconds.push_back(a + b * (k / 4) + (k % 2 == 0 ? 1e-6 : -1e-6));
  }
  EXPECT_NEAR(particle_stage_fit(counts, seconds), a, 2e-7);
}

// Where the count hardly moves (a filled drum), a fixed part cannot be told from a per-particle
// one: no split. Too few steps, a negative slope or intercept (noise): none either.
TEST(EstimateFit, NoSplitWithoutASpreadOfCountsOrWithAnUnphysicalFit) {
  std::vector<double> counts(100, 2000.0), seconds(100, 1e-3);
  for (int k = 0; k < 100; ++k) counts[k] += k % 3;
  EXPECT_EQ(particle_stage_fit(counts, seconds), 0.0);
  EXPECT_EQ(particle_stage_fit({1, 50, 100}, {1e-5, 2e-5, 3e-5}), 0.0);  // 3 steps
  std::vector<double> n, falling, negative;
  for (int k = 0; k < 100; ++k) {
    n.push_back(k);
    falling.push_back(1e-3 - 1e-6 * k);  // slower with fewer particles: noise, not a cost
    negative.push_back(-1e-5 + 1e-6 * k);
  }
  EXPECT_EQ(particle_stage_fit(n, falling), 0.0);
  EXPECT_EQ(particle_stage_fit(n, negative), 0.0);
}

// Wen & Yu: Re_mf = √(33.7² + 0.0408 Ar) − 33.7, Ar = ρ_f (ρ_p − ρ_f) g d³ / μ².
// 1 mm glass beads (2500 kg/m³) in water (1000 kg/m³, 1 mPa·s), g 9.81: Ar = 14,715,
// Re_mf = √(1135.69 + 600.37) − 33.7 = 7.966, U_mf = Re_mf μ / (ρ_f d) = 7.966 mm/s (the
// fluidised-bed example's figure). 0.5 mm sand (2650) in air (1.2 kg/m³, 18 µPa·s): Ar = 12,030,
// Re_mf = 6.63, U_mf = 0.199 m/s (Kunii & Levenspiel's Geldart B sands: 0.1-0.3 m/s).
TEST(EstimateFluidisation, WenYuMinimumFluidisationVelocity) {
  EXPECT_NEAR(minimum_fluidisation_velocity(1000, 1e-3, 2500, 1e-3, 9.81), 7.966e-3, 0.001e-3);
  EXPECT_NEAR(minimum_fluidisation_velocity(1.2, 18e-6, 2650, 0.5e-3, 9.81), 0.199, 0.001);
  // Particles no denser than the fluid are never held on a bed: no U_mf.
  EXPECT_EQ(minimum_fluidisation_velocity(1000, 1e-3, 900, 1e-3, 9.81), 0.0);
}

// For small Ar the root expands to Re_mf = 0.0408 Ar / (2 · 33.7) = Ar / 1652: U_mf =
// (ρ_p − ρ_f) g d² / (1652 μ), Wen & Yu's fine-particle limit. 20 µm glass in water: Ar = 0.118,
// the next term of the expansion a relative 0.0408 Ar / (4 · 33.7²) = 1e-6.
TEST(EstimateFluidisation, FineParticlesReachTheStokesLimit) {
  const double d = 20e-6, limit = 1500 * 9.81 * d * d / (1652.0 * 1e-3);  // m/s
  EXPECT_NEAR(minimum_fluidisation_velocity(1000, 1e-3, 2500, d, 9.81) / limit, 1.0, 1e-4);
}

std::string bed_deck(double inlet_velocity, const std::string& gravity = "[0, 0, -9.81]") {
  return R"(simulation:
  end_time: 0.1
  time_step: 8.0e-6
  gravity: )" +
         gravity + R"(
  domain: {min: [-0.001, -0.001, -0.001], max: [0.0136, 0.0136, 0.0850]}
materials:
  - {name: glass, density: 2500, youngs_modulus: 1.0e7, poisson_ratio: 0.3}
interactions:
  - {materials: [glass, glass], restitution: 0.6, static_friction: 0.3}
particle_types:
  - {name: fine, material: glass, size: {distribution: fixed, radius: 2.5e-4}}
  - {name: bead, material: glass, size: {distribution: fixed, radius: 5.0e-4}}
factories:
  - {name: fill, particle_type: bead, region: {type: box, min: [0.001, 0.001, 0.005], max: [0.012, 0.012, 0.06]}, count: 100}
fluid:
  density: 1000
  viscosity: 0.001
  time_step: 8.0e-5
  grid: {origin: [0, 0, 0], cell_size: 2.1e-3, cells: [6, 6, 40]}
  boundaries:
    z_min: {type: velocity_inlet, velocity: [0, 0, )" +
         std::to_string(inlet_velocity) + R"(]}
    z_max: {type: pressure_outlet, reference_pressure: 0, reference_point: [0, 0, 0.084]}
)";
}

// The inlet against the largest U_mf of the deck's types (the 1 mm beads: 7.966 mm/s; the
// 0.5 mm fines need 2.19 mm/s): 24 mm/s carries them, 5 mm/s lifts only the fines, which is not
// a fluidised bed; an inlet along gravity (flow downwards) carries nothing.
TEST(EstimateFluidisation, AFluidCarriesTheParticlesAboveTheLargestMinimumVelocity) {
  double inlet = 0, minimum = 0;
  EXPECT_TRUE(
      fluid_carries_particles(parse_deck_string(bed_deck(0.024), "bed.yaml"), inlet, minimum));
  EXPECT_DOUBLE_EQ(inlet, 0.024);
  EXPECT_NEAR(minimum, 7.966e-3, 0.001e-3);
  EXPECT_FALSE(
      fluid_carries_particles(parse_deck_string(bed_deck(0.005), "bed.yaml"), inlet, minimum));
  EXPECT_FALSE(
      fluid_carries_particles(parse_deck_string(bed_deck(-0.024), "bed.yaml"), inlet, minimum));
  EXPECT_FALSE(fluid_carries_particles(parse_deck_string(bed_deck(0.024, "[0, 0, 0]"), "bed.yaml"),
                                       inlet, minimum));
}

}  // namespace
}  // namespace quarry::sim
