// The fluid section's check of the drag relaxation time at set-up (fluid_setup.h): the bound on
// each built-in law's drag that it rests on, verified against the laws themselves, and the
// deck refused at its viscosity exactly where that bound falls below the DEM step.
#include "cfdem/fluid_setup.h"
#include "cfdem/fluid_test_support.h"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "cfd/drag_laws.h"
#include "io/deck.h"

namespace quarry::cfdem {
namespace {

// weakest_drag_factor is a lower bound of every law's coefficient β_p / (3πμd), at any void
// fraction from the coupling's minimum (0.05) to 1 and any slip from rest to Re_p ≈ 2e4, and it
// is attained: Stokes with the seed's factor ε at ε_min, Di Felice's 4.8²/24 = 0.96 at ε = 1 as
// Re → 0 (C_d = (0.63 + 4.8/√Re)², Di Felice 1994), every other law Stokes' 3πμd there.
TEST(FluidSetup, TheWeakestDragFactorBoundsEveryBuiltInLawAndIsAttained) {
  const double minimum = FluidCouplingOptions{}.minimum_void_fraction;
  ASSERT_EQ(minimum, 0.05);
  const double d = 1e-3, mu = 1e-3, rho = 1000.0;  // m, Pa·s, kg/m³: water, a 1 mm bead
  const double stokes = 3.0 * std::numbers::pi * mu * d;  // kg/s
  for (const cfd::DragLawName& entry : cfd::kDragLawNames) {
    SCOPED_TRACE(std::string(entry.name));
    const double factor = weakest_drag_factor(entry.law, minimum);
    double least = INFINITY;  // the smallest β_p / (3πμd) met
    for (double eps = minimum; eps <= 1.0 + 1e-12; eps += 0.0125) {
      for (const double slip : {0.0, 1e-9, 1e-6, 1e-4, 1e-3, 1e-2, 0.1, 1.0, 20.0}) {
        cfd::DragInput input;
        input.diameter = d;
        input.fluid_velocity = {0.0, 0.0, slip};
        input.porosity = std::min(eps, 1.0);
        input.fluid_density = rho;
        input.fluid_viscosity = mu;
        const double ratio = cfd::drag_force(entry.law, input).coefficient / stokes;
        EXPECT_GE(ratio, factor * (1.0 - 1e-12)) << "ε " << input.porosity << ", slip " << slip;
        least = std::min(least, ratio);
      }
    }
    EXPECT_NEAR(least, factor, 1e-6 * factor);  // the bound is the laws' own least value
  }
}

// The fluidised bed of examples/ with a viscosity `mu` (Pa·s): 1 mm glass beads (2500 kg/m³),
// the Gidaspow law, DEM step 8 µs. Its bound m/β ≤ ρ_p d²/(18 μ) meets the step at
// μ* = 2500 · 1e-6 / (18 · 8e-6) = 17.36 Pa·s.
std::string bed_deck(double mu) {
  return fmt::format(R"(simulation:
  end_time: 0.01
  time_step: 8.0e-6
  impact_speed: 0.2
  domain: {{min: [-0.001, -0.001, -0.001], max: [0.0136, 0.0136, 0.0850]}}
materials:
  - {{name: glass, density: 2500, youngs_modulus: 1.0e7, poisson_ratio: 0.3}}
interactions:
  - {{materials: [glass, glass], restitution: 0.6, static_friction: 0.3}}
particle_types:
  - {{name: bead, material: glass, size: {{distribution: fixed, radius: 5.0e-4}}}}
  - {{name: speck, material: glass, size: {{distribution: fixed, radius: 3.5e-4}}}}
factories:
  - {{name: fill, particle_type: bead, region: {{type: box, min: [0.0006, 0.0006, 0.0048], max: [0.0120, 0.0120, 0.060]}}, count: 20}}
fluid:
  density: 1000
  viscosity: {}
  time_step: 8.0e-5
  grid: {{origin: [0, 0, 0], cell_size: 2.1e-3, cells: [6, 6, 40]}}
  boundaries:
    z_min: {{type: velocity_inlet, velocity: [0, 0, 0.024]}}
    z_max: {{type: pressure_outlet, reference_pressure: 0, reference_point: [0, 0, 0.084]}}
  drag_law: gidaspow
)",
                     mu);
}

std::string setup_errors(const std::string& deck) {
  return testing::fluid_setup_errors(deck, "bed.yaml");
}

// The 0.7 mm type (m/β ≤ 4.0 µs at 0.99 μ*: refused, were it inserted) is defined but inserted by
// nothing: only the particles the deck inserts count.
TEST(FluidSetup, AViscosityAtWhichTheDragAlwaysOvershootsIsRefusedAtItsKey) {
  const double threshold = 2500.0 * 1e-6 / (18.0 * 8e-6);  // Pa·s
  EXPECT_EQ(setup_errors(bed_deck(0.001)), "");
  EXPECT_EQ(setup_errors(bed_deck(0.99 * threshold)), "");
  const std::string errors = setup_errors(bed_deck(1.01 * threshold));
  EXPECT_NE(errors.find("bed.yaml:17:14: error: with viscosity 17.53 Pa·s the smallest particle "
                        "of type 'bead' (d = 1 mm"),
            std::string::npos)
      << errors;
  EXPECT_NE(errors.find("at most m/β = 7.92e-06 s under the gidaspow drag law"), std::string::npos)
      << errors;
  EXPECT_NE(errors.find("hint: the viscosity is dynamic, in Pa·s"), std::string::npos) << errors;
}

}  // namespace
}  // namespace quarry::cfdem
