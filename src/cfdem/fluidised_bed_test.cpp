// A water-fluidised bed of glass beads (issue #18 "Many particles"): above the minimum
// fluidisation velocity the bed's pressure drop, less the hydrostatic head, plateaus at the
// bed's buoyant weight per area, (ρ_p − ρ_f) g N V_p / A (the momentum balance of fluid and
// particles together: nothing else holds the particles up; Kunii & Levenspiel 1991, Fluidization
// Engineering, ch. 3, eq. 1), less what the column's walls and plate carry. Checked at 4 and 8
// times Wen & Yu's (1966) U_mf: the momentum balance within 2 %, the plateau within 10 %.
// The beads rest on a distributor plate two cells above the fluid inlet (a plenum below it): the
// inlet's velocity is interstitial at its faces, so its cells must hold no particle volume for
// the fed flow to be the superficial U A.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "cfdem/fluid_monitors.h"
#include "io/deck.h"
#include "sim/step.h"

namespace quarry::cfdem {
namespace {

constexpr double kDiameter = 1e-3;          // m
constexpr double kParticleDensity = 2500.0; // kg/m³, glass
constexpr double kFluidDensity = 1000.0;    // kg/m³, water
constexpr double kViscosity = 1e-3;         // Pa·s
constexpr double kGravity = 9.81;           // m/s²
constexpr double kCell = 2.1e-3;            // m
constexpr int kCellsAcross = 4, kCellsUp = 24;
constexpr int kParticles = 400;

// Wen & Yu (1966, Chem. Eng. Prog. Symp. Ser. 62:100-111): Re_mf = √(33.7² + 0.0408 Ar) − 33.7,
// Ar = ρ_f (ρ_p − ρ_f) g d³ / μ², U_mf = Re_mf μ / (ρ_f d). Here Ar = 14,715, U_mf = 7.97 mm/s.
double wen_yu_minimum_fluidisation_velocity() {
  const double archimedes = kFluidDensity * (kParticleDensity - kFluidDensity) * kGravity * std::pow(kDiameter, 3) /
                            (kViscosity * kViscosity);
  const double reynolds = std::sqrt(33.7 * 33.7 + 0.0408 * archimedes) - 33.7;
  return reynolds * kViscosity / (kFluidDensity * kDiameter);
}

World bed_world() {
  const double width = kCellsAcross * kCell, height = kCellsUp * kCell;
  const std::string deck = fmt::format(R"(
simulation:
  end_time: 1
  time_step: 2.5e-5
  impact_speed: 0.1
  gravity: [0, 0, -{g}]
  domain: {{min: [-0.001, -0.001, -0.001], max: [{wd}, {wd}, {hd}]}}
materials:
  - {{name: glass, density: {rho}, youngs_modulus: 1.0e6, poisson_ratio: 0.3}}
interactions:
  - {{materials: [glass, glass], restitution: 0.5, static_friction: 0.3}}
particle_types:
  - {{name: bead, material: glass, size: {{distribution: fixed, radius: {r}}}}}
surfaces:
  - {{name: column, type: box, min: [0, 0, {plate}], max: [{w}, {w}, {h}], material: glass}}
factories:
  - {{name: fill, particle_type: bead, count: {n},
     region: {{type: box, min: [0.0006, 0.0006, {fill}], max: [{wr}, {wr}, 0.035]}}}}
output:
  directory: out_fluidised_bed_test
  interval: 0
  plots: false
)",
                                       fmt::arg("g", kGravity), fmt::arg("w", width), fmt::arg("h", height),
                                       fmt::arg("wd", width + 0.001), fmt::arg("hd", height + 0.001),
                                       fmt::arg("wr", width - 0.0006), fmt::arg("rho", kParticleDensity),
                                       fmt::arg("r", 0.5 * kDiameter), fmt::arg("n", kParticles),
                                       fmt::arg("plate", 2.0 * kCell), fmt::arg("fill", 2.0 * kCell + 0.0006));
  return build_world(parse_deck_string(deck, "fluidised_bed.yaml"));
}

// The time-mean dynamic pressure drop from the inlet (z = 0) to 30 mm, well above the bed, over
// t = 0.4 to 0.8 s, sampled at every fluid step.
struct BedMeans {
  double drop = 0.0;         // Pa, dynamic pressure drop
  double wall_support = 0.0; // N, the column's upward force on the beads (walls and plate)
  std::size_t particles = 0;
};

BedMeans mean_bed_pressure_drop(double superficial_velocity) {
  World world = bed_world();
  FluidCouplingOptions options;
  options.grid.origin = {0.0, 0.0, 0.0};
  options.grid.cell_size = {kCell, kCell, kCell};
  options.grid.cells = {kCellsAcross, kCellsAcross, kCellsUp};
  options.properties = {kFluidDensity, kViscosity};
  // Periodic fluid sides: no wall shear on the fluid, so the balance is the bed's alone.
  options.boundaries.set_periodic(0);
  options.boundaries.set_periodic(1);
  options.boundaries.face(2, 0).kind = cfd::BoundaryKind::velocity_inlet;
  options.boundaries.face(2, 0).velocity = {0.0, 0.0, superficial_velocity};
  options.boundaries.face(2, 1).kind = cfd::BoundaryKind::pressure_outlet;
  options.boundaries.face(2, 1).reference_point = {0.0, 0.0, kCellsUp * kCell};
  options.drag_law = cfd::DragLaw::gidaspow;
  options.coupling_steps = 10;
  auto coupling = FluidCoupling::attach(world, std::move(options));
  std::vector<FluidMonitorSpec> monitors(1);
  monitors[0].name.value = "bed";
  monitors[0].type.value = FluidMonitorType::pressure_drop;
  monitors[0].from.value = 0.0;
  monitors[0].to.value = 0.03;
  sim::initialize(world);
  EXPECT_EQ(world.particles.size(), static_cast<std::size_t>(kParticles));  // all placed at once: a bead appearing later displaces fluid in one step
  BedMeans means;
  int samples = 0;
  const auto total = static_cast<std::uint64_t>(std::llround(0.8 / world.dt));
  for (std::uint64_t s = 0; s < total; s += 10) {
    sim::advance(world, 10);
    if (world.time < 0.4) continue;
    means.drop += FluidMonitors::row(monitors, *coupling, world)[2];
    means.wall_support -= world.surfaces[0].mesh.total_force.z;  // the beads push down on it
    ++samples;
  }
  means.drop /= samples;
  means.wall_support /= samples;
  means.particles = world.particles.size();
  return means;
}

TEST(FluidisedBed, PressureDropPlateausAtTheBuoyantWeightPerArea) {
#if defined(__SANITIZE_ADDRESS__)
  // 2 × 32,000 coupled steps: ~15 s optimised, minutes under the sanitizers; the coupling's code
  // is exercised there by the shorter cases of this binary.
  GTEST_SKIP() << "long physics case: run in the optimised build";
#endif
  const double u_mf = wen_yu_minimum_fluidisation_velocity();
  EXPECT_NEAR(u_mf, 7.97e-3, 0.01e-3);
  const double volume = std::numbers::pi / 6.0 * std::pow(kDiameter, 3);
  const double area = std::pow(kCellsAcross * kCell, 2);
  for (const double factor : {4.0, 8.0}) {
    const BedMeans m = mean_bed_pressure_drop(factor * u_mf);
    const double weight_per_area = (kParticleDensity - kFluidDensity) * kGravity * m.particles * volume / area;  // Pa
    std::printf("[ measured ] U = %.1f U_mf (%.4g m/s), %zu beads: mean dynamic pressure drop %.5g Pa, buoyant "
                "weight per area %.5g Pa (ratio %.4f); the column carries %.4g of the weight\n",
                factor, factor * u_mf, m.particles, m.drop, weight_per_area, m.drop / weight_per_area,
                m.wall_support / (weight_per_area * area));
    // Momentum closes: what the fluid holds up plus what the column carries is the buoyant weight
    // (measured +1.6 % and +2.1 %: means over 0.4 s of a fluctuating bed, sampled every fluid step).
    EXPECT_NEAR((m.drop * area + m.wall_support) / (weight_per_area * area), 1.0, 0.03) << factor << " U_mf";
    // The plateau: in this narrow column (8.4 d across) the walls and the plate still carry
    // 3.6 % of the weight at 8 U_mf and 11 % at 4 U_mf (measured), so the fluid holds 90-98 %;
    // the 2 % of issue #18 is not reached here (docs/cfd.md, "Fluidised bed").
    EXPECT_NEAR(m.drop / weight_per_area, 1.0, 0.10) << factor << " U_mf";
  }
}

}  // namespace
}  // namespace quarry::cfdem
