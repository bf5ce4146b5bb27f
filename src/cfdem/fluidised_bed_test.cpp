// A water-fluidised bed of glass beads (issue #18 "Many particles"), periodic across (beads and
// fluid): nothing but the fluid and the distributor plate holds the beads up. Above the minimum
// fluidisation velocity the bed's pressure drop, less the hydrostatic head, plateaus at the bed's
// buoyant weight per area, (ρ_p − ρ_f) g N V_p / A (the momentum balance of fluid and particles
// together; Kunii & Levenspiel 1991, Fluidization Engineering, ch. 3, eq. 1); below it the bed is
// packed and its drop rises with U as Ergun's law. The U_mf where the packed branch meets the
// plateau is compared with Wen & Yu's (1966) correlation.
// The beads rest on a distributor plate two cells above the fluid inlet (a plenum below it): the
// inlet's velocity is interstitial at its faces, so its cells must hold no particle volume for
// the fed flow to be the superficial U A.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>

#include "cfdem/fluid_monitors.h"
#include "io/deck.h"
#include "sim/estimate.h"
#include "sim/step.h"

namespace quarry::cfdem {
namespace {

constexpr double kDiameter = 1e-3;          // m
constexpr double kParticleDensity = 2500.0; // kg/m³, glass
constexpr double kFluidDensity = 1000.0;    // kg/m³, water
constexpr double kViscosity = 1e-3;         // Pa·s
constexpr double kGravity = 9.81;           // m/s²
constexpr double kCell = 2.1e-3;            // m
constexpr int kCellsAcross = 4, kCellsUp = 40;
constexpr int kParticles = 1600;            // a bed about 9 cells deep when packed
constexpr double kEndTime = 1.0;            // s: the fill has fallen and packed by 0.6 s
constexpr double kAverageFrom = 0.6;        // s
constexpr double kTopPlane = 0.08;          // m: the pressure drop's upper plane, above the bed

// Ar = ρ_f (ρ_p − ρ_f) g d³ / μ² = 14,715 here.
double archimedes_number() {
  return kFluidDensity * (kParticleDensity - kFluidDensity) * kGravity * std::pow(kDiameter, 3) /
         (kViscosity * kViscosity);
}

// Wen & Yu's (1966, Chem. Eng. Prog. Symp. Ser. 62:100-111) correlation without the voidage:
// Re_mf = √(33.7² + 0.0408 Ar) − 33.7, U_mf = Re_mf μ / (ρ_f d) = 7.97 mm/s here
// (sim::minimum_fluidisation_velocity, which `estimate` uses; checked against hand calculations
// in sim/estimate_test.cpp).
double wen_yu_correlation() {
  return sim::minimum_fluidisation_velocity(kFluidDensity, kViscosity, kParticleDensity, kDiameter, kGravity);
}

// Wen & Yu's equation at the bed's voidage ε_mf (Ergun's packed-bed drag equal to the bed's
// buoyant weight; Kunii & Levenspiel 1991, ch. 3, eq. 19, spheres):
// 1.75/ε³ Re_mf² + 150 (1 − ε)/ε³ Re_mf = Ar, solved for Re_mf.
double wen_yu_equation(double voidage) {
  const double a = 1.75 / std::pow(voidage, 3), b = 150.0 * (1.0 - voidage) / std::pow(voidage, 3);
  const double reynolds = (-b + std::sqrt(b * b + 4.0 * a * archimedes_number())) / (2.0 * a);
  return reynolds * kViscosity / (kFluidDensity * kDiameter);
}

// The beads periodic along x and y with the fluid's period (4 cells); a floor plate wider than
// the period (surfaces are not wrapped) on the inlet: the inlet's velocity is superficial, so a
// bed resting on it is fed U A whatever its cells' void fraction.
World bed_world() {
  const double width = kCellsAcross * kCell, height = kCellsUp * kCell;
  const std::string deck = fmt::format(R"(
simulation:
  end_time: 1
  time_step: 2.5e-5
  impact_speed: 0.1
  gravity: [0, 0, -{g}]
  domain: {{min: [0, 0, -0.001], max: [{w}, {w}, {hd}], periodic: [x, y]}}
materials:
  - {{name: glass, density: {rho}, youngs_modulus: 1.0e6, poisson_ratio: 0.3}}
interactions:
  - {{materials: [glass, glass], restitution: 0.5, static_friction: 0.3}}
particle_types:
  - {{name: bead, material: glass, size: {{distribution: fixed, radius: {r}}}}}
surfaces:
  - {{name: plate, type: plane, point: [{c}, {c}, {plate}], normal: [0, 0, 1], size: {ws}, material: glass}}
factories:
  - {{name: fill, particle_type: bead, count: {n},
     region: {{type: box, min: [0.0006, 0.0006, {fill}], max: [{wr}, {wr}, {top}]}}}}
output:
  directory: out_fluidised_bed_test
  interval: 0
  plots: false
)",
                                       fmt::arg("g", kGravity), fmt::arg("w", width),  fmt::arg("hd", height + 0.001),
                                       fmt::arg("c", 0.5 * width), fmt::arg("ws", 3.0 * width),
                                       fmt::arg("wr", width - 0.0006), fmt::arg("rho", kParticleDensity),
                                       fmt::arg("r", 0.5 * kDiameter), fmt::arg("n", kParticles),
                                       fmt::arg("plate", 0.0), fmt::arg("fill", 0.0006), fmt::arg("top", kTopPlane));
  return build_world(parse_deck_string(deck, "fluidised_bed.yaml"));
}

// Time means over t = kAverageFrom to kEndTime, sampled at every fluid step.
struct BedMeans {
  double drop = 0.0;          // Pa, dynamic pressure drop from the inlet (z = 0) to kTopPlane
  double plate_support = 0.0; // N, the plate's upward force on the beads
  double mean_height = 0.0;   // m, the beads' mean centre height
  double least_stable_step = std::numeric_limits<double>::infinity();  // s, the fluid's, over the means
  std::size_t particles = 0;
};

BedMeans mean_bed_pressure_drop(double superficial_velocity, int coupling_steps, cfd::Advection advection) {
  World world = bed_world();
  FluidCouplingOptions options;
  options.grid.origin = {0.0, 0.0, 0.0};
  options.grid.cell_size = {kCell, kCell, kCell};
  options.grid.cells = {kCellsAcross, kCellsAcross, kCellsUp};
  options.properties = {kFluidDensity, kViscosity};
  options.boundaries.set_periodic(0);
  options.boundaries.set_periodic(1);
  options.boundaries.face(2, 0).kind = cfd::BoundaryKind::velocity_inlet;
  options.boundaries.face(2, 0).velocity = {0.0, 0.0, superficial_velocity};
  options.boundaries.face(2, 1).kind = cfd::BoundaryKind::pressure_outlet;
  options.boundaries.face(2, 1).reference_point = {0.0, 0.0, kCellsUp * kCell};
  options.drag_law = cfd::DragLaw::gidaspow;
  options.coupling_steps = coupling_steps;
  options.solver.advection = advection;
  auto coupling = FluidCoupling::attach(world, std::move(options));
  std::vector<FluidMonitorSpec> monitors(1);
  monitors[0].name.value = "bed";
  monitors[0].type.value = FluidMonitorType::pressure_drop;
  monitors[0].from.value = 0.0;
  monitors[0].to.value = kTopPlane;
  sim::initialize(world);
  BedMeans means;
  int samples = 0;
  const auto total = static_cast<std::uint64_t>(std::llround(kEndTime / world.dt));
  const auto interval = static_cast<std::uint64_t>(coupling_steps);
  for (std::uint64_t s = 0; s < total; s += interval) {
    sim::advance(world, interval);
    if (world.time < kAverageFrom) continue;
    // The fill places the last few beads over the first steps (each displaces fluid in one
    // step): all of them are in before the means start.
    if (samples == 0) {
      EXPECT_EQ(world.particles.size(), static_cast<std::size_t>(kParticles));
    }
    means.drop += FluidMonitors::row(monitors, *coupling, world)[2];
    means.plate_support -= world.surfaces[0].mesh.total_force.z;  // the beads push down on it
    double heights = 0.0;
    for (const Vec3& x : world.particles.position) heights += x.z;
    means.mean_height += heights / static_cast<double>(world.particles.size());
    means.least_stable_step = std::min(means.least_stable_step, coupling->fluid().stable_time_step());
    ++samples;
  }
  means.drop /= samples;
  means.plate_support /= samples;
  means.mean_height /= samples;
  means.particles = world.particles.size();
  return means;
}

// One bed at U = factor × the correlation's U_mf, a fluid step of `coupling_steps` DEM steps:
// the time means, printed.
struct BedPoint {
  double ratio = 0.0;    // dynamic pressure drop / buoyant weight per area
  double balance = 0.0;  // (drop A + plate support) / buoyant weight
  double voidage = 0.0;  // of the bed, from its beads' mean height
  double least_stable_step = 0.0;  // s, the fluid's stable_time_step() over the means
};

BedPoint measure_bed(double factor, int coupling_steps = 10, cfd::Advection advection = cfd::Advection::central) {
  const double volume = std::numbers::pi / 6.0 * std::pow(kDiameter, 3);
  const double area = std::pow(kCellsAcross * kCell, 2);
  const double u_mf = wen_yu_correlation();
  const BedMeans m = mean_bed_pressure_drop(factor * u_mf, coupling_steps, advection);
  const double weight_per_area = (kParticleDensity - kFluidDensity) * kGravity * m.particles * volume / area;  // Pa
  BedPoint point;
  point.ratio = m.drop / weight_per_area;
  point.balance = (m.drop * area + m.plate_support) / (weight_per_area * area);
  // A uniform bed from the plate to H holds its beads' centres at H/2 on average.
  point.voidage = 1.0 - m.particles * volume / (area * 2.0 * m.mean_height);
  point.least_stable_step = m.least_stable_step;
  std::printf("[ measured ] U = %.1f x %.4g m/s, fluid step %d DEM steps, %s advection (stable step ≥ %.3g ms): dynamic pressure drop %.5g Pa = %.4f of the buoyant weight per "
              "area (%.5g Pa); the plate carries %.4f; sum %.4f; bed voidage %.4f\n",
              factor, u_mf, coupling_steps, advection == cfd::Advection::hybrid ? "hybrid" : "central",
              m.least_stable_step * 1e3, m.drop, point.ratio, weight_per_area, m.plate_support / (weight_per_area * area),
              point.balance, point.voidage);
  // Momentum closes: what the fluid holds up plus what the plate carries is the buoyant weight
  // (means over 0.4 s of a moving bed; measured within 0.7 %).
  EXPECT_NEAR(point.balance, 1.0, 0.02) << factor;
  return point;
}

// 2 × 40,000 coupled steps of 1,600 beads per test: about 20 s optimised, far longer under the
// sanitizers; the coupling's code is exercised there by the shorter cases of this binary.
#if defined(__SANITIZE_ADDRESS__)
#define SKIP_UNDER_SANITIZERS() GTEST_SKIP() << "long physics case: run in the optimised build"
#else
#define SKIP_UNDER_SANITIZERS() (void)0
#endif

TEST(FluidisedBed, PlateausAtTheBuoyantWeightPerAreaAboveMinimumFluidisation) {
  SKIP_UNDER_SANITIZERS();
  // Issue #18: within 2 % (measured +0.07 % at 3 and −0.06 % at 6 times the correlation's
  // U_mf, 2.4 and 4.9 times this bed's).
  for (const double factor : {3.0, 6.0}) EXPECT_NEAR(measure_bed(factor).ratio, 1.0, 0.02) << factor;
}

// The same bed with longer fluid steps than 10 DEM steps (0.25 ms).
// Central advection at 40 DEM steps (1 ms): about half the fluid's stable_time_step() with the
// drag in bench/fluidised_bed.cpp's beds (1.3-2.0 ms; docs/cfd.md "Time step"). In this
// narrower, bubbling bed that bound (sufficient, not necessary) falls to 0.12-0.17 ms after
// 0.3 s (0.24 ms over the means), below even the 0.25 ms of 10 DEM steps.
// Hybrid advection at 160 DEM steps (4 ms): its bound is the CFL limit alone, and the step is
// within half of it over the whole mean (measured ≥ 15.5 ms; cell Péclet numbers |u|Δx/ν of
// tens: it upwinds). The bed is the same at all three: the plateau holds within the issue's
// 2 %, and the voidage, a time mean over 0.4 s, within 1 % of the shortest step's (measured
// 1.0007 each; 0.5683, 0.5684 and 0.5687).
TEST(FluidisedBed, SameBedWithLongerFluidSteps) {
  SKIP_UNDER_SANITIZERS();
  const BedPoint short_step = measure_bed(3.0, 10);
  const BedPoint central = measure_bed(3.0, 40), hybrid = measure_bed(3.0, 160, cfd::Advection::hybrid);
  for (const BedPoint& long_step : {central, hybrid}) {
    EXPECT_NEAR(long_step.ratio, 1.0, 0.02);
    EXPECT_NEAR(long_step.voidage / short_step.voidage, 1.0, 0.01);
  }
  EXPECT_LE(160 * 2.5e-5, 0.5 * hybrid.least_stable_step);
}

TEST(FluidisedBed, PackedBedMeetsItsWeightAtWenYusMinimumFluidisationVelocity) {
  SKIP_UNDER_SANITIZERS();
  const double correlation = wen_yu_correlation();
  EXPECT_NEAR(correlation, 7.97e-3, 0.01e-3);
  // The packed branch, Ergun's a U + b U² through two packed points (U in units of the
  // correlation's U_mf), meets the weight at the measured U_mf.
  const double x1 = 0.4, x2 = 0.7;
  const BedPoint low = measure_bed(x1), high = measure_bed(x2);
  const double b = (high.ratio / x2 - low.ratio / x1) / (x2 - x1), a = low.ratio / x1 - b * x1;
  const double measured = correlation * (-a + std::sqrt(a * a + 4.0 * b)) / (2.0 * b);
  const double expected = wen_yu_equation(high.voidage);
  std::printf("[ measured ] U_mf %.4g m/s; Wen & Yu at the packed bed's voidage %.4f: %.4g m/s (ratio %.4f); "
              "their correlation without the voidage: %.4g m/s (ratio %.4f)\n",
              measured, high.voidage, expected, measured / expected, correlation, measured / correlation);
  // Within 10 % of Wen & Yu (issue #18; measured +3.1 %). Their correlation without the voidage
  // stands for ε_mf ≈ 0.38; these frictional beads pack at 0.41, which the equation takes in
  // (the correlation: +22 %).
  EXPECT_NEAR(measured / expected, 1.0, 0.10);
  // The plateau test's velocities are above this bed's U_mf by a margin.
  EXPECT_LT(2.0 * measured, 3.0 * correlation);
}

}  // namespace
}  // namespace quarry::cfdem
