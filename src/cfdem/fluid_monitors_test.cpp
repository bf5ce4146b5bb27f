// Fluid monitors against closed forms: the pressure between planes in a fluid at rest is the
// hydrostatic head; the flow rate through every face layer is the inlet's (continuity); and a
// packed bed of fixed particles with Gidaspow's drag gives Ergun's pressure drop (issue #18
// "Many particles": within 5 % over a range of superficial velocities).
#include "cfdem/fluid_monitors.h"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "io/deck.h"
#include "sim/exchange.h"
#include "sim/step.h"

namespace quarry::cfdem {
namespace {

constexpr double kGravity = 9.81;  // m/s²

// A column of 3 x 2 x 10 cells of 2 mm: walls at the sides and the bottom (or an inlet there),
// a pressure outlet at the top with p = 0 at its centre.
cfd::FluidSolver column_solver(double inlet_velocity, double gravity) {
  cfd::FluidGrid grid;
  grid.origin = {0.0, 0.0, 0.0};
  grid.cell_size = {2e-3, 2e-3, 2e-3};
  grid.cells = {3, 2, 10};
  cfd::FluidBoundaries boundaries;
  cfd::FaceBoundary& top = boundaries.face(2, 1);
  top.kind = cfd::BoundaryKind::pressure_outlet;
  top.reference_point = {3e-3, 2e-3, 2e-2};
  if (inlet_velocity != 0.0) {
    boundaries.face(2, 0).kind = cfd::BoundaryKind::velocity_inlet;
    boundaries.face(2, 0).velocity = {0.0, 0.0, inlet_velocity};
    boundaries.set_periodic(0);
    boundaries.set_periodic(1);
  }
  cfd::FluidSolverOptions options;
  options.gravity = {0.0, 0.0, -gravity};
  return cfd::FluidSolver(grid, {1000.0, 1e-3}, boundaries, options);
}

// Hydrostatics, p(z) = p_ref + ρ_f g (z_ref − z): between any two planes p_a − p_b = ρ_f g (z_b −
// z_a), including planes in the half cells at the grid's ends (linear extrapolation is exact).
TEST(FluidMonitors, PlanePressureOfAFluidAtRestIsHydrostatic) {
  cfd::FluidSolver fluid = column_solver(0.0, kGravity);
  for (int n = 0; n < 3; ++n) fluid.step(1e-3);
  for (const auto& [a, b] : {std::pair{0.0, 0.02}, std::pair{0.0005, 0.0131}, std::pair{0.007, 0.0199}}) {
    const double drop = plane_pressure(fluid, 2, a) - plane_pressure(fluid, 2, b);
    EXPECT_NEAR(drop, 1000.0 * kGravity * (b - a), 1e-9 * 1000.0 * kGravity * 0.02) << a << " to " << b;
  }
  // At the outlet's reference height the plane's pressure is p_ref = 0.
  EXPECT_NEAR(plane_pressure(fluid, 2, 0.02), 0.0, 1e-9);
}

// Continuity, ∇·(ε u) = 0 with a steady ε: the flow through every face layer along the column
// equals the inlet's, whatever the void fraction per layer. The inlet's velocity is superficial,
// so its flow is U A even though the cells at the inlet hold particles (ε 0.45 to 0.47 there).
TEST(FluidMonitors, FlowRateEqualsTheInletsThroughEveryLayer) {
  const double inlet = 0.01;  // m/s
  cfd::FluidSolver fluid = column_solver(inlet, kGravity);
  std::vector<double> void_fraction(fluid.grid().cell_count());
  for (int k = 0; k < 10; ++k)
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 3; ++i)
        void_fraction[fluid.grid().cell_index(i, j, k)] = 0.45 + 0.05 * k + 0.01 * i;
  fluid.set_initial_void_fraction(void_fraction);
  fluid.set_void_fraction(void_fraction);
  for (int n = 0; n < 5; ++n) fluid.step(1e-3);
  const double area = plane_area(fluid.grid(), 2);
  EXPECT_DOUBLE_EQ(area, 6e-3 * 4e-3);
  for (int layer = 0; layer <= 10; ++layer) {
    const double q = flow_rate(fluid, void_fraction, 2, 2e-3 * layer);
    EXPECT_NEAR(q / (inlet * area), 1.0, 1e-7) << "layer " << layer;
  }
}

// A packed bed of fixed spheres on a simple cubic lattice (spacing 1.05 d) in a column with
// periodic sides, water flowing up from an inlet: the dynamic pressure drop across the bed's
// interior against Ergun (1952, Chem. Eng. Prog. 48:89-94),
//   Δp / L = 150 μ (1 − ε)² U / (ε³ d²) + 1.75 ρ_f (1 − ε) U² / (ε³ d),
// U the superficial velocity, ε the lattice's void fraction 1 − (π/6)/1.05³. In model A at
// steady state the fluid's −ε ∂p/∂z balances the drag per volume β u (u = U/ε), and Gidaspow's β
// below ε = 0.8 is Ergun's, so the coupled solver must give Ergun's Δp; what it does differently
// (void fraction from the kernel, drag at the interpolated velocity) must stay within 5 %.
struct PackedBed {
  double diameter = 1e-3;     // m
  double spacing = 1.05e-3;   // m, lattice
  int across = 4;             // particles per side (2 cells of 2 spacings)
  int layers = 24;            // particle layers: 12 cells
  double bed_bottom = 4.2e-3; // m: 2 cells of fluid below the bed
  int cells_z = 16;
};

World packed_bed_world(const PackedBed& b) {
  const double cell = 2.0 * b.spacing;
  const double width = b.across * b.spacing, height = b.cells_z * cell;
  const std::string deck = fmt::format(R"(
simulation:
  end_time: 1
  time_step: 1.0e-4
  impact_speed: 0.01
  gravity: [0, 0, -9.81]
  domain: {{min: [0, 0, 0], max: [{w}, {w}, {h}]}}
materials:
  - {{name: glass, density: 2500, youngs_modulus: 1.0e5, poisson_ratio: 0.3}}
interactions:
  - {{materials: [glass, glass], restitution: 0.5, static_friction: 0.3}}
particle_types:
  - {{name: bead, material: glass, size: {{distribution: fixed, radius: {r}}}}}
output:
  directory: out_packed_bed_test
  interval: 0
  plots: false
)",
                                       fmt::arg("w", width), fmt::arg("h", height), fmt::arg("r", 0.5 * b.diameter));
  World world = build_world(parse_deck_string(deck, "packed_bed.yaml"));
  std::vector<sim::NewParticle> lattice;
  for (int k = 0; k < b.layers; ++k)
    for (int j = 0; j < b.across; ++j)
      for (int i = 0; i < b.across; ++i) {
        sim::NewParticle p;
        p.position = {(i + 0.5) * b.spacing, (j + 0.5) * b.spacing, b.bed_bottom + (k + 0.5) * b.spacing};
        p.radius = 0.5 * b.diameter;
        lattice.push_back(p);
      }
  sim::add_particles(world, lattice);
  return world;
}

struct BedResult {
  double dynamic_drop = 0.0;  // Pa, over the interior planes
  double length = 0.0;        // m, between them
  double slip_z = 0.0;        // m/s, the slip monitor
  double superficial = 0.0;   // m/s, the flow-rate monitor
};

BedResult run_packed_bed(const PackedBed& b, double superficial_velocity) {
  World world = packed_bed_world(b);
  const double cell = 2.0 * b.spacing;
  FluidCouplingOptions options;
  options.grid.origin = {0.0, 0.0, 0.0};
  options.grid.cell_size = {cell, cell, cell};
  options.grid.cells = {b.across / 2, b.across / 2, b.cells_z};
  options.properties = {1000.0, 1e-3};
  options.boundaries.set_periodic(0);
  options.boundaries.set_periodic(1);
  options.boundaries.face(2, 0).kind = cfd::BoundaryKind::velocity_inlet;
  options.boundaries.face(2, 0).velocity = {0.0, 0.0, superficial_velocity};
  options.boundaries.face(2, 1).kind = cfd::BoundaryKind::pressure_outlet;
  options.boundaries.face(2, 1).reference_point = {0.0, 0.0, b.cells_z * cell};
  options.drag_law = cfd::DragLaw::gidaspow;
  auto coupling = FluidCoupling::attach(world, std::move(options));
  // The bed is held: after the fluid forces, every particle's force is cancelled (a fixed bed).
  StepHook hold;
  hold.stage = HookStage::post_force;
  hold.name = "hold the bed";
  hold.run = [](World& w) {
    for (std::size_t i = 0; i < w.particles.size(); ++i) w.particles.force[i] = {};
  };
  world.hooks.push_back(hold);
  sim::initialize(world);
  sim::advance(world, 400);  // 0.04 s: many times the flow's development time here

  const double bed_top = b.bed_bottom + b.layers * b.spacing;
  std::vector<FluidMonitorSpec> monitors(3);
  monitors[0].name.value = "bed";
  monitors[0].type.value = FluidMonitorType::pressure_drop;
  monitors[0].from.value = b.bed_bottom + 3 * cell;  // three cells inside either end of the bed
  monitors[0].to.value = bed_top - 3 * cell;
  monitors[1].name.value = "feed";
  monitors[1].type.value = FluidMonitorType::flow_rate;
  monitors[1].at.value = 0.5 * (b.bed_bottom + bed_top);
  monitors[2].name.value = "slip";
  monitors[2].type.value = FluidMonitorType::slip_velocity;
  const std::vector<double> row = FluidMonitors::row(monitors, *coupling, world);
  EXPECT_EQ(FluidMonitors::columns(monitors).size(), row.size());
  BedResult r;
  r.dynamic_drop = row[2];
  r.length = monitors[0].to.value - monitors[0].from.value;
  r.superficial = row[4];
  r.slip_z = row[7];
  return r;
}

TEST(FluidMonitors, PackedBedPressureDropFollowsErgun) {
  const PackedBed b;
  const double porosity = 1.0 - std::numbers::pi / 6.0 / std::pow(b.spacing / b.diameter, 3);  // 0.548
  const double mu = 1e-3, rho = 1000.0;
  for (const double u : {1e-3, 1e-2, 4e-2}) {  // superficial Re_p = ρ U d / μ = 1, 10, 40
    const BedResult r = run_packed_bed(b, u);
    const double ergun = 150.0 * mu * std::pow(1.0 - porosity, 2) * u / (std::pow(porosity, 3) * b.diameter * b.diameter) +
                         1.75 * rho * (1.0 - porosity) * u * u / (std::pow(porosity, 3) * b.diameter);  // Pa/m
    std::printf("[ measured ] U %.3g m/s: Δp/L %.6g Pa/m, Ergun %.6g (ratio %.4f); U from the flow-rate "
                "monitor %.6g; slip %.6g m/s against U/ε %.6g\n",
                u, r.dynamic_drop / r.length, ergun, r.dynamic_drop / r.length / ergun, r.superficial,
                r.slip_z, u / porosity);
    EXPECT_NEAR(r.dynamic_drop / r.length / ergun, 1.0, 0.05) << "U = " << u;
    EXPECT_NEAR(r.superficial / u, 1.0, 1e-6);
    EXPECT_NEAR(r.slip_z / (u / porosity), 1.0, 0.05);
  }
}

}  // namespace
}  // namespace quarry::cfdem
