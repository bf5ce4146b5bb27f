// Hindered settling (issue #18 "Many particles"): a uniform suspension settles in a column closed
// at the bottom, so the fluid the particles displace flows up through them (zero net volume flux,
// the frame of a batch settling test). Richardson & Zaki (1954, Trans. Inst. Chem. Eng. 32:35-53)
// measured v = v_t ε^n with n = 4.65 for Re_t < 0.2, v_t the single particle's terminal velocity.
// The suspension is a cubic lattice periodic across (particles and fluid), its spacing chosen for
// ε, in cells of two spacings, so every cell inside it holds the same particle volume. Checked:
// the mean settling velocity of the middle layers against the force balance of the drag law
// (Gidaspow's Wen-Yu branch, ε ≥ 0.8; the mixture's weight carried by the pressure gradient)
// within 1 % (measured 1e-5: the coupling adds nothing the law does not say), and against
// Richardson-Zaki within 3 % (measured +0.5, +1.0, +1.5 % at ε = 0.95, 0.9, 0.85: the law's
// finite-Re term is smaller at the slower hindered slip than at v_t).
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "cfdem/fluid_coupling.h"
#include "io/deck.h"
#include "sim/exchange.h"
#include "sim/step.h"

namespace quarry::cfdem {
namespace {

constexpr double kDiameter = 1e-4;           // m
constexpr double kParticleDensity = 1250.0;  // kg/m³
constexpr double kFluidDensity = 1000.0;     // kg/m³
constexpr double kViscosity = 1e-3;          // Pa·s
constexpr double kGravity = 9.81;            // m/s²
constexpr int kAcross = 4;                   // lattice columns per period along x and y
constexpr int kLayers = 48;                  // lattice layers of the suspension
constexpr int kCellsBelow = 8, kCellsAbove = 8;
constexpr double kEndTime = 6e-3;            // s: about 10 relaxation times m/β_p

double particle_volume() { return std::numbers::pi / 6.0 * std::pow(kDiameter, 3); }

// Wen & Yu's drag as Gidaspow's model uses it for ε ≥ 0.8 (Gidaspow 1994, Multiphase Flow and
// Fluidization, eq. 5.76), per particle: F = 3π μ d ε^−2.65 (1 + 0.15 Re_p^0.687) (u − v),
// Re_p = ρ_f ε d |u − v| / μ. Returns β_p (kg/s) at the slip w.
double wen_yu_coefficient(double voidage, double slip) {
  const double reynolds = kFluidDensity * voidage * kDiameter * slip / kViscosity;
  return 3.0 * std::numbers::pi * kViscosity * kDiameter * std::pow(voidage, -2.65) *
         (1.0 + 0.15 * std::pow(reynolds, 0.687));
}

// The settling speed |v| of a uniform suspension at zero volume flux, ε u + (1 − ε) v = 0, so the
// slip is |u − v| = |v|/ε: the pressure gradient carries the mixture, ∇p = ρ_mix g, and each
// particle's drag balances its weight less −V_p ∇p, ε (ρ_p − ρ_f) V_p g = β_p |v|/ε. At ε = 1 it
// is the single particle's terminal velocity with the same law (Schiller-Naumann). Bisection.
double balance_speed(double voidage) {
  const double load = voidage * voidage * (kParticleDensity - kFluidDensity) * particle_volume() * kGravity;  // N
  double low = 0.0, high = 1.0;  // m/s
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (low + high);
    (wen_yu_coefficient(voidage, mid / voidage) * mid > load ? high : low) = mid;
  }
  return 0.5 * (low + high);
}

struct Suspension {
  double voidage = 0.0;
  double spacing = 0.0;  // m, of the lattice: (π/6) d³ / s³ = 1 − ε
  double cell = 0.0;     // m, two spacings
};

Suspension suspension(double voidage) {
  Suspension s;
  s.voidage = voidage;
  s.spacing = kDiameter * std::cbrt(std::numbers::pi / (6.0 * (1.0 - voidage)));
  s.cell = 2.0 * s.spacing;
  return s;
}

struct Settling {
  double velocity = 0.0;           // m/s, mean v_z of the middle third of the layers
  double pressure_gradient = 0.0;  // Pa/m, mean dp/dz across the middle cells
};

// Means over the last 1 ms.
Settling settle(const Suspension& s, cfd::VolumeAveragedModel model) {
  const int cells_across = kAcross / 2, cells_up = kCellsBelow + kLayers / 2 + kCellsAbove;
  const double width = cells_across * s.cell, height = cells_up * s.cell;
  const std::string deck = fmt::format(R"(
simulation:
  end_time: {end}
  time_step: 1.0e-6
  impact_speed: 0.01
  gravity: [0, 0, -{g}]
  domain: {{min: [0, 0, 0], max: [{w}, {w}, {h}], periodic: [x, y]}}
materials:
  - {{name: solid, density: {rho}, youngs_modulus: 1.0e7, poisson_ratio: 0.3}}
interactions:
  - {{materials: [solid, solid], restitution: 0.5, static_friction: 0.3}}
particle_types:
  - {{name: sphere, material: solid, size: {{distribution: fixed, radius: {r}}}}}
output:
  directory: out_hindered_settling_test
  interval: 0
  plots: false
)",
                                       fmt::arg("end", kEndTime), fmt::arg("g", kGravity), fmt::arg("w", width),
                                       fmt::arg("h", height), fmt::arg("rho", kParticleDensity),
                                       fmt::arg("r", 0.5 * kDiameter));
  World world = build_world(parse_deck_string(deck, "hindered_settling.yaml"));
  std::vector<sim::NewParticle> lattice;
  const double bottom = kCellsBelow * s.cell;  // m
  for (int c = 0; c < kLayers; ++c)
    for (int b = 0; b < kAcross; ++b)
      for (int a = 0; a < kAcross; ++a) {
        sim::NewParticle p;
        p.position = {(a + 0.5) * s.spacing, (b + 0.5) * s.spacing, bottom + (c + 0.5) * s.spacing};
        p.radius = 0.5 * kDiameter;
        lattice.push_back(p);
      }
  sim::add_particles(world, lattice);

  FluidCouplingOptions options;
  options.grid.origin = {0.0, 0.0, 0.0};
  options.grid.cell_size = {s.cell, s.cell, s.cell};
  options.grid.cells = {cells_across, cells_across, cells_up};
  options.properties = {kFluidDensity, kViscosity};
  options.boundaries.set_periodic(0);
  options.boundaries.set_periodic(1);
  options.boundaries.face(2, 1).kind = cfd::BoundaryKind::pressure_outlet;  // the top; the bottom a wall
  options.boundaries.face(2, 1).reference_point = {0.0, 0.0, height};
  options.drag_law = cfd::DragLaw::gidaspow;
  options.coupling_steps = 10;
  options.solver.model = model;
  auto coupling = FluidCoupling::attach(world, std::move(options));
  sim::initialize(world);
  // The middle third of the layers, by height at the start (they move a few µm).
  const double from = bottom + kLayers / 3 * s.spacing, to = bottom + 2 * kLayers / 3 * s.spacing;
  double sum = 0.0, gradient = 0.0;
  int samples = 0;
  const int low_cell = kCellsBelow + kLayers / 8, high_cell = kCellsBelow + 3 * kLayers / 8;
  const auto total = static_cast<std::uint64_t>(std::llround(kEndTime / world.dt));
  for (std::uint64_t step = 0; step < total; step += 10) {
    sim::advance(world, 10);
    if (world.time < kEndTime - 1e-3) continue;
    double layer_sum = 0.0;
    int count = 0;
    for (std::size_t i = 0; i < world.particles.size(); ++i) {
      const double z = world.particles.position[i].z;
      if (z < from || z > to) continue;
      layer_sum += world.particles.velocity[i].z;
      ++count;
    }
    EXPECT_EQ(count, kLayers / 3 * kAcross * kAcross);
    sum += layer_sum / count;
    const cfd::FluidSolver& fluid = coupling->fluid();
    gradient += (fluid.pressure(0, 0, high_cell) - fluid.pressure(0, 0, low_cell)) / ((high_cell - low_cell) * s.cell);
    ++samples;
  }
  // The void fraction the middle cells hold is the lattice's.
  const std::size_t middle = coupling->options().grid.cell_index(0, 0, kCellsBelow + kLayers / 4);
  EXPECT_NEAR(coupling->void_fraction()[middle], s.voidage, 1e-12);
  return {sum / samples, gradient / samples};
}

void expect_hindered_settling(cfd::VolumeAveragedModel model) {
  const double single = balance_speed(1.0);  // m/s, Schiller-Naumann at ε = 1
  // 1.313 mm/s (Stokes: (ρ_p − ρ_f) g d² / (18 μ) = 1.3625 mm/s); Richardson and Zaki's n = 4.65
  // holds for Re_t = ρ_f v_t d / μ < 0.2.
  EXPECT_LT(kFluidDensity * single * kDiameter / kViscosity, 0.2);
  for (const double voidage : {0.95, 0.9, 0.85}) {
    const Settling m = settle(suspension(voidage), model);
    const double measured = -m.velocity;
    const double balance = balance_speed(voidage);
    const double richardson_zaki = single * std::pow(voidage, 4.65);
    // The fluid carries the mixture: dp/dz = −ρ_mix g (the column's weight per area and height).
    const double mixture = -(voidage * kFluidDensity + (1.0 - voidage) * kParticleDensity) * kGravity;
    std::printf("[ measured ] model %s, ε = %.2f: settling %.6g m/s; force balance %.6g m/s (ratio %.4f); "
                "Richardson-Zaki v_t ε^4.65 = %.6g m/s (ratio %.4f); dp/dz %.6g Pa/m = %.6f of −ρ_mix g\n",
                model == cfd::VolumeAveragedModel::a ? "A" : "B", voidage, measured, balance, measured / balance,
                richardson_zaki, measured / richardson_zaki, m.pressure_gradient, m.pressure_gradient / mixture);
    EXPECT_NEAR(measured / balance, 1.0, 0.01) << voidage;
    EXPECT_NEAR(measured / richardson_zaki, 1.0, 0.03) << voidage;
    EXPECT_NEAR(m.pressure_gradient / mixture, 1.0, 1e-3) << voidage;
  }
}

TEST(HinderedSettling, FollowsTheDragLawsBalanceAndRichardsonZaki) {
  expect_hindered_settling(cfd::VolumeAveragedModel::a);
}

// Model B: the particles feel the drag ÷ ε and Archimedes' force instead of −V_p ∇p; the
// balance is the same (ε² (ρ_p − ρ_f) V_p g = β_p |v|), and the fluid, which takes both
// reactions, carries the same mixture.
TEST(HinderedSettling, ModelBGivesTheSameBalance) { expect_hindered_settling(cfd::VolumeAveragedModel::b); }

}  // namespace
}  // namespace quarry::cfdem
