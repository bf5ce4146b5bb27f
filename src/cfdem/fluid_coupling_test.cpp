// Verification of the coupled step: single-particle settling against the terminal velocity of
// the force balance (Stokes with the built-in law and with the example's UDF built by `quarry
// udf build`'s code; Schiller-Naumann at finite Re), and 1 vs 2 threads bit-identical.
#include "cfdem/fluid_coupling.h"

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <numbers>
#include <sstream>

#include "cli/udf_build.h"
#include "io/deck.h"
#include "sim/exchange.h"
#include "sim/step.h"

namespace quarry::cfdem {
namespace {

// One particle in a column of fluid: walls on every side but the top, a pressure outlet there
// with the hydrostatic reference at the top (seed 001).
struct SettlingCase {
  double fluid_density = 1000.0;      // kg/m³
  double viscosity = 1e-3;            // Pa·s
  double particle_density = 1500.0;   // kg/m³
  double diameter = 1e-4;             // m
  double start_height = 4.8e-3;       // m above the bottom
  double dem_step = 1e-6;             // s
  int coupling_steps = 50;            // fluid step 5e-5 s
  double end_time = 0.015;            // s
  double cell = 5e-4;                 // m (the seed's mesh size)
  std::array<int, 3> cells{4, 4, 12}; // a 2 x 2 x 6 mm column
  int threads = 1;
};

World settling_world(const SettlingCase& c) {
  const double half_x = 0.5 * c.cells[0] * c.cell, half_y = 0.5 * c.cells[1] * c.cell;
  const double height = c.cells[2] * c.cell;
  const std::string deck = fmt::format(R"(
simulation:
  end_time: {end}
  time_step: {dt}
  impact_speed: 0.01
  gravity: [0, 0, -9.81]
  domain: {{min: [{x0}, {y0}, 0], max: [{x1}, {y1}, {h}]}}
materials:
  - {{name: solid, density: {rho}, youngs_modulus: 1.0e7, poisson_ratio: 0.3}}
interactions:
  - {{materials: [solid, solid], restitution: 0.5, static_friction: 0.3}}
particle_types:
  - {{name: sphere, material: solid, size: {{distribution: fixed, radius: {r}}}}}
output:
  directory: out_cfdem_test
  interval: 0
  plots: false
)",
                                       fmt::arg("end", c.end_time), fmt::arg("dt", c.dem_step),
                                       fmt::arg("x0", -half_x), fmt::arg("y0", -half_y),
                                       fmt::arg("x1", half_x), fmt::arg("y1", half_y),
                                       fmt::arg("h", height), fmt::arg("rho", c.particle_density),
                                       fmt::arg("r", 0.5 * c.diameter));
  World world = build_world(parse_deck_string(deck, "settling.yaml"));
  world.threading = Threading{c.threads, 0};
  sim::NewParticle particle;
  particle.position = {0.0, 0.0, c.start_height};
  particle.radius = 0.5 * c.diameter;
  sim::add_particles(world, std::span<const sim::NewParticle>(&particle, 1));
  return world;
}

FluidCouplingOptions settling_options(const SettlingCase& c) {
  FluidCouplingOptions options;
  options.grid.origin = {-0.5 * c.cells[0] * c.cell, -0.5 * c.cells[1] * c.cell, 0.0};
  options.grid.cell_size = {c.cell, c.cell, c.cell};
  options.grid.cells = c.cells;
  options.properties = {c.fluid_density, c.viscosity};
  cfd::FaceBoundary& top = options.boundaries.face(2, 1);
  top.kind = cfd::BoundaryKind::pressure_outlet;
  top.reference_point = {0.0, 0.0, c.cells[2] * c.cell};
  options.coupling_steps = c.coupling_steps;
  return options;
}

struct SettlingResult {
  double velocity = 0.0;        // m/s, v_z at the end
  double velocity_before = 0.0; // m/s, v_z 2 ms before the end
  double porosity = 0.0;        // ε at the particle at the end
  World world;
};

SettlingResult settle(const SettlingCase& c, FluidCouplingOptions options) {
  SettlingResult result;
  result.world = settling_world(c);
  World& world = result.world;
  auto coupling = FluidCoupling::attach(world, std::move(options));
  sim::initialize(world);
  const auto steps = static_cast<std::uint64_t>(std::llround(c.end_time / c.dem_step));
  const auto before = steps - static_cast<std::uint64_t>(std::llround(0.002 / c.dem_step));
  sim::advance(world, before);
  result.velocity_before = world.particles.velocity[0].z;
  sim::advance(world, steps - before);
  result.velocity = world.particles.velocity[0].z;
  result.porosity = interpolate(coupling->weights()[0], coupling->void_fraction());
  return result;
}

// Stokes' terminal velocity with the seed's porosity factor, from (ρ_p − ρ_f) V_p g =
// 3π ε d μ v: v = (ρ_p − ρ_f) g d² / (18 μ ε) (Stokes 1851; seed 001: 0.002725 m/s at ε = 1).
double stokes_terminal_velocity(const SettlingCase& c, double porosity) {
  return (c.particle_density - c.fluid_density) * 9.81 * c.diameter * c.diameter /
         (18.0 * c.viscosity * porosity);
}

// Seed 001 (AcuSolve-EDEM tutorial ACU-T 6108): 0.1 mm, 1500 kg/m³ particle in water, DEM step
// 1e-6 s, fluid step 5e-5 s, 0.015 s; analytic terminal velocity 0.002725 m/s (EDEM: 0.00274).
TEST(FluidCoupling, StokesSettlingReachesTheSeedsTerminalVelocity) {
  const SettlingCase c;
  const SettlingResult r = settle(c, settling_options(c));
  const double analytic = stokes_terminal_velocity(c, 1.0);
  EXPECT_NEAR(analytic, 0.002725, 0.0000005);
  std::printf("[ measured ] terminal velocity %.7g m/s (analytic %.7g, ε at the particle %.6f, "
              "ε-corrected %.7g), 2 ms earlier %.7g m/s\n",
              -r.velocity, analytic, r.porosity, stokes_terminal_velocity(c, r.porosity),
              -r.velocity_before);
  EXPECT_NEAR(-r.velocity / analytic, 1.0, 0.01);
  // Terminal: the last 2 ms changed it by less than 0.1 %.
  EXPECT_NEAR(r.velocity / r.velocity_before, 1.0, 1e-3);
}


// The same case with the example's user-defined drag (examples/stokes_settling/usrStokesDrag.c)
// compiled by `quarry udf build`'s code into a temporary folder: the same terminal velocity as
// the built-in law (both are 3π ε d μ (u − v); only their rounding may differ).
TEST(FluidCoupling, StokesSettlingWithTheExampleUdfMatchesTheBuiltInLaw) {
  namespace fs = std::filesystem;
  std::string folder = (fs::temp_directory_path() / "quarry_cfdem_udf_XXXXXX").string();
  ASSERT_NE(::mkdtemp(folder.data()), nullptr);
  cli::UdfBuildOptions build;
  build.source = std::string(QUARRY_SOURCE_DIR) + "/examples/stokes_settling/usrStokesDrag.c";
  build.output = folder + "/usrStokesDrag.so";
  std::ostringstream out, err;
  ASSERT_EQ(cli::udf_build(build, out, err), 0) << out.str() << err.str();
  const SettlingCase c;
  FluidCouplingOptions options = settling_options(c);
  options.drag_udf = cfd::load_drag_udf(build.output, "usrStokesDrag");
  const SettlingResult udf = settle(c, options);
  const SettlingResult built_in = settle(c, settling_options(c));
  fs::remove_all(folder);
  std::printf("[ measured ] UDF %.15g m/s, built-in %.15g m/s\n", -udf.velocity, -built_in.velocity);
  EXPECT_NEAR(udf.velocity / built_in.velocity, 1.0, 1e-12);
  EXPECT_NEAR(-udf.velocity / 0.002725, 1.0, 0.01);
}

// Schiller & Naumann (1933) at Re ≈ 0.6: the terminal velocity solves
// (ρ_p − ρ_f) V_p g = ½ ρ_f C_d(Re) (π d²/4) v², C_d = 24/Re (1 + 0.15 Re^0.687),
// Re = ρ_f v d / μ; found here by bisection. About 10 % below Stokes' value, so the test tells
// the laws apart.
TEST(FluidCoupling, SchillerNaumannSettlingReachesTheForceBalance) {
  SettlingCase c;
  c.viscosity = 0.01;
  c.particle_density = 2000.0;
  c.diameter = 5e-4;
  c.cell = 2.5e-3;  // 5 d, as the seed's mesh
  c.cells = {4, 4, 6};
  c.start_height = 1.2e-2;
  c.dem_step = 1e-5;
  c.coupling_steps = 5;
  c.end_time = 0.05;  // ≈ 18 relaxation times ρ_p d²/(18 μ) = 2.8 ms
  const double weight = (c.particle_density - c.fluid_density) * std::numbers::pi *
                        std::pow(c.diameter, 3) / 6.0 * 9.81;  // N, net of buoyancy
  const auto drag = [&](double v) {
    const double re = c.fluid_density * v * c.diameter / c.viscosity;
    const double cd = 24.0 / re * (1.0 + 0.15 * std::pow(re, 0.687));
    return 0.5 * c.fluid_density * cd * std::numbers::pi * c.diameter * c.diameter / 4.0 * v * v;
  };
  double low = 1e-9, high = 1.0;  // m/s
  for (int n = 0; n < 200; ++n) {
    const double mid = 0.5 * (low + high);
    (drag(mid) < weight ? low : high) = mid;
  }
  const double terminal = 0.5 * (low + high);
  FluidCouplingOptions options = settling_options(c);
  options.drag_law = cfd::DragLaw::schiller_naumann;
  const SettlingResult r = settle(c, options);
  std::printf("[ measured ] Schiller-Naumann terminal velocity %.7g m/s, force balance %.7g m/s "
              "(Re %.4g; Stokes %.7g), 2 ms earlier %.7g m/s\n",
              -r.velocity, terminal, c.fluid_density * terminal * c.diameter / c.viscosity,
              stokes_terminal_velocity(c, 1.0), -r.velocity_before);
  EXPECT_NEAR(-r.velocity / terminal, 1.0, 0.01);
  EXPECT_NEAR(r.velocity / r.velocity_before, 1.0, 1e-3);
  EXPECT_LT(terminal, 0.95 * stokes_terminal_velocity(c, 1.0));
}

// Di Felice (1994, Int. J. Multiphase Flow 20:153-159) in the same column: the terminal velocity
// solves (ρ_p − ρ_f) V_p g = ½ C_d ρ_f (π d²/4) ε² v² ε^(−χ), C_d = (0.63 + 4.8/√Re_p)²
// (Dallavalle 1948), χ = 3.7 − 0.65 exp(−(1.5 − log10 Re_p)²/2), Re_p = ρ_f ε v d / μ, with ε
// the void fraction at the particle (the law's input; 0.9991 here); by bisection.
TEST(FluidCoupling, DiFeliceSettlingReachesTheForceBalance) {
  SettlingCase c;
  c.viscosity = 0.01;
  c.particle_density = 2000.0;
  c.diameter = 5e-4;
  c.cell = 2.5e-3;  // 5 d
  c.cells = {4, 4, 6};
  c.start_height = 1.2e-2;
  c.dem_step = 1e-5;
  c.coupling_steps = 5;
  c.end_time = 0.05;
  FluidCouplingOptions options = settling_options(c);
  options.drag_law = cfd::DragLaw::di_felice;
  const SettlingResult r = settle(c, options);
  const double e = r.porosity;
  const double weight = (c.particle_density - c.fluid_density) * std::numbers::pi *
                        std::pow(c.diameter, 3) / 6.0 * 9.81;  // N
  const auto drag = [&](double v) {
    const double re = c.fluid_density * e * v * c.diameter / c.viscosity;
    const double cd = std::pow(0.63 + 4.8 / std::sqrt(re), 2);
    const double chi = 3.7 - 0.65 * std::exp(-std::pow(1.5 - std::log10(re), 2) / 2.0);
    return 0.5 * cd * c.fluid_density * std::numbers::pi * c.diameter * c.diameter / 4.0 * e * e * v *
           v * std::pow(e, -chi);
  };
  double low = 1e-9, high = 1.0;  // m/s
  for (int n = 0; n < 200; ++n) {
    const double mid = 0.5 * (low + high);
    (drag(mid) < weight ? low : high) = mid;
  }
  const double terminal = 0.5 * (low + high);
  std::printf("[ measured ] Di Felice terminal velocity %.7g m/s, force balance %.7g m/s (ε %.6f), "
              "2 ms earlier %.7g m/s\n",
              -r.velocity, terminal, e, -r.velocity_before);
  EXPECT_NEAR(-r.velocity / terminal, 1.0, 0.01);
  EXPECT_NEAR(r.velocity / r.velocity_before, 1.0, 1e-3);
}

// The coupled step on 1 and 2 threads (every loop on the team, threshold 0): the same bits.
TEST(FluidCoupling, OneAndTwoThreadsAreBitIdentical) {
  SettlingCase c;
  c.end_time = 0.001;
  std::vector<double> bits[2];
  for (int t = 0; t < 2; ++t) {
    c.threads = t + 1;
    World world = settling_world(c);
    auto coupling = FluidCoupling::attach(world, settling_options(c));
    sim::initialize(world);
    sim::advance(world, 1000);
    const Vec3 x = world.particles.position[0], v = world.particles.velocity[0];
    bits[t] = {x.x, x.y, x.z, v.x, v.y, v.z};
    for (int k = 0; k < c.cells[2]; ++k) {
      const Vec3 u = coupling->fluid().cell_velocity(1, 2, k);
      bits[t].insert(bits[t].end(), {u.x, u.y, u.z, coupling->fluid().pressure(2, 1, k)});
    }
  }
  ASSERT_EQ(bits[0].size(), bits[1].size());
  for (std::size_t n = 0; n < bits[0].size(); ++n) EXPECT_EQ(bits[0][n], bits[1][n]) << "value " << n;
  EXPECT_NE(bits[0][5], 0.0);
}

// After the coupled steps the fluid's void fraction still holds exactly the particle's volume.
TEST(FluidCoupling, VoidFractionHoldsTheParticleVolume) {
  SettlingCase c;
  c.end_time = 0.001;
  World world = settling_world(c);
  auto coupling = FluidCoupling::attach(world, settling_options(c));
  sim::initialize(world);
  sim::advance(world, 1000);
  EXPECT_EQ(coupling->exchanges(), 1 + 1000 / c.coupling_steps);
  const double cell_volume = c.cell * c.cell * c.cell;  // m³
  double solid = 0.0;                                   // m³
  for (double e : coupling->void_fraction()) solid += (1.0 - e) * cell_volume;
  const double particle = std::numbers::pi * std::pow(c.diameter, 3) / 6.0;
  // Round-off: 192 cells, each 1 − ε to an ulp of 1 (1.1e-16), times V_cell/V_p = 239: 5e-12.
  EXPECT_NEAR(solid / particle, 1.0, 1e-10);
}

// Eight particles moving through a fluid at rest in a box periodic on every side, gravity off
// (the conservation and thread tests).
struct PeriodicBox {
  World world;
  std::shared_ptr<FluidCoupling> coupling;
};

PeriodicBox periodic_box(int threads, cfd::VolumeAveragedModel model = cfd::VolumeAveragedModel::a) {
  const double cell = 3e-3;  // m
  const int cells = 6;
  const double side = cell * cells;
  const std::string deck = fmt::format(R"(
simulation:
  end_time: 0.02
  time_step: 1.0e-5
  impact_speed: 0.05
  gravity: [0, 0, 0]
  integrator: symplectic_euler
  domain: {{min: [0, 0, 0], max: [{s}, {s}, {s}]}}
materials:
  - {{name: solid, density: 2500, youngs_modulus: 1.0e6, poisson_ratio: 0.3}}
interactions:
  - {{materials: [solid, solid], restitution: 0.5, static_friction: 0.3}}
particle_types:
  - {{name: sphere, material: solid, size: {{distribution: fixed, radius: 5.0e-4}}}}
output:
  directory: out_cfdem_test
  interval: 0
  plots: false
)",
                                       fmt::arg("s", side));
  World world = build_world(parse_deck_string(deck, "periodic.yaml"));
  world.threading = Threading{threads, 0};
  std::vector<sim::NewParticle> particles;
  for (int n = 0; n < 8; ++n) {
    sim::NewParticle particle;
    particle.position = {side * (0.3 + 0.4 * (n % 2)) + 1e-4 * n, side * (0.3 + 0.4 * ((n / 2) % 2)),
                         side * (0.3 + 0.4 * (n / 4)) - 2e-4 * n};
    particle.velocity = {0.02 * (n % 3 - 1), 0.01 + 0.005 * n, -0.015 * (n % 2)};
    particle.radius = 5e-4;
    particles.push_back(particle);
  }
  sim::add_particles(world, particles);
  FluidCouplingOptions options;
  options.grid.cell_size = {cell, cell, cell};
  options.grid.cells = {cells, cells, cells};
  options.properties = {1000.0, 0.01};
  for (int axis = 0; axis < 3; ++axis) options.boundaries.set_periodic(axis);
  options.solver.pressure_tolerance = 1e-13;
  options.solver.velocity_tolerance = 1e-13;
  options.coupling_steps = 5;
  options.drag_law = cfd::DragLaw::schiller_naumann;
  options.solver.model = model;
  auto coupling = FluidCoupling::attach(world, options);
  return {std::move(world), std::move(coupling)};
}

// Conservation (issue #18 "Conservation"): in a box periodic on every side, gravity off, the
// momentum of fluid (Σ ρ ε u V, model A's conserved quantity) plus particles, plus what the
// last fluid step took and the particles have yet to feel, stays what it was: drag is deposited
// and interpolated with the same weights, the pressure force −V_p ∇p with central differences
// is the complement of the fluid's −ε_f ∇p on the faces, and the drag the particles felt beyond
// the fluid step's share goes to the fluid at the next exchange. Exact but for the linear
// solves, whose relative residual is set to 1e-13 here (the fluid's momentum is only as
// conserved as its momentum and pressure equations are solved).
void expect_momentum_conserved(cfd::VolumeAveragedModel model) {
  PeriodicBox box = periodic_box(1, model);
  World& world = box.world;
  const std::shared_ptr<FluidCoupling>& coupling = box.coupling;
  const auto total = [&] {
    Vec3 sum = coupling->fluid_momentum() + coupling->pending_particle_impulse();
    for (std::size_t i = 0; i < world.particles.size(); ++i)
      sum += world.particles.velocity[i] * world.particles.mass(i);
    return sum;
  };
  sim::initialize(world);
  const Vec3 start = total();
  double particle_start = 0.0;  // kg·m/s, Σ m |v|: the scale of what is exchanged
  for (std::size_t i = 0; i < world.particles.size(); ++i)
    particle_start += std::sqrt(dot(world.particles.velocity[i], world.particles.velocity[i])) *
                      world.particles.mass(i);
  double largest_change = 0.0;
  for (int interval = 0; interval < 400; ++interval) {
    sim::advance(world, 5);
    const Vec3 change = total() - start;
    largest_change = std::max({largest_change, std::abs(change.x), std::abs(change.y), std::abs(change.z)});
  }
  const Vec3 fluid = coupling->fluid_momentum();
  const double fluid_share = std::max({std::abs(fluid.x), std::abs(fluid.y), std::abs(fluid.z)});
  std::printf("[ measured ] over 400 exchanges: largest change of the total %.3g kg·m/s, Σ m|v| at "
              "the start %.3g kg·m/s, fluid momentum at the end %.3g kg·m/s\n",
              largest_change, particle_start, fluid_share);
  // The particles have given a good part of their momentum to the fluid: the test tests.
  EXPECT_GT(fluid_share, 0.1 * particle_start);
  // 400 fluid steps, each conserving to its solves' 1e-13: 4e-11 of what moves. Without the
  // next-exchange correction the drift measured 1.2e-3 of Σ m|v| (4.3e-10 kg·m/s).
  EXPECT_LT(largest_change, 1e-10 * particle_start);
}

TEST(FluidCoupling, MomentumOfFluidAndParticlesIsConservedInAPeriodicBox) {
  expect_momentum_conserved(cfd::VolumeAveragedModel::a);
}

// Model B: the drag ÷ ε, deposited with the same weights (gravity off: no Archimedes force).
TEST(FluidCoupling, MomentumIsConservedInModelB) { expect_momentum_conserved(cfd::VolumeAveragedModel::b); }

// Model B with the seed's Stokes law, 3π ε d μ (u − v): the particle feels it ÷ ε plus
// Archimedes, so its terminal velocity is Stokes' (ρ_p − ρ_f) g d² / (18 μ) at any ε.
TEST(FluidCoupling, StokesSettlingInModelBReachesStokesVelocity) {
  const SettlingCase c;
  FluidCouplingOptions options = settling_options(c);
  options.solver.model = cfd::VolumeAveragedModel::b;
  const SettlingResult r = settle(c, options);
  const double analytic = stokes_terminal_velocity(c, 1.0);
  std::printf("[ measured ] model B: terminal velocity %.7g m/s (analytic %.7g)\n", -r.velocity, analytic);
  EXPECT_NEAR(-r.velocity / analytic, 1.0, 0.01);
  EXPECT_NEAR(r.velocity / r.velocity_before, 1.0, 1e-3);
}

// The particle relaxation time m/β_p = ρ_p d²/(18 μ) (Stokes) against the steps: shorter than
// the DEM step stops the run (the explicit particle update would overshoot), shorter than the
// coupling step warns once.
TEST(FluidCoupling, ChecksTheParticleRelaxationTime) {
  SettlingCase c;
  c.viscosity = 1.0;  // τ_p = 1500 · 1e-8 / (18 ε) = 0.83 µs < Δt_DEM = 1 µs
  {
    World world = settling_world(c);
    FluidCoupling::attach(world, settling_options(c));
    try {
      sim::initialize(world);
      FAIL() << "a relaxation time shorter than the DEM step was accepted";
    } catch (const PhysicsError& e) {
      EXPECT_NE(std::string(e.what()).find("relaxation time m/β_p = 8.3"), std::string::npos) << e.what();
    }
  }
  c.viscosity = 0.05;  // τ_p = 16.7 µs: > Δt_DEM, < Δt_f = 50 µs
  World world = settling_world(c);
  FluidCoupling::attach(world, settling_options(c));
  sim::initialize(world);
  sim::advance(world, 200);
  int warnings = 0;
  for (const std::string& w : world.warnings)
    warnings += w.find("longer than the drag relaxation time") != std::string::npos;
  EXPECT_EQ(warnings, 1);
}

// Eight particles, every per-particle loop and the fluid's on 1 and 2 threads (threshold 0):
// the same bits after 200 steps with re-sorts every 50.
TEST(FluidCoupling, ManyParticlesOneAndTwoThreadsAreBitIdentical) {
  std::vector<double> bits[2];
  for (int t = 0; t < 2; ++t) {
    PeriodicBox box = periodic_box(t + 1);
    box.world.spec.simulation.sort_interval.value = 50;
    sim::initialize(box.world);
    sim::advance(box.world, 200);
    const ParticleStore& p = box.world.particles;
    for (std::size_t i = 0; i < p.size(); ++i)
      bits[t].insert(bits[t].end(), {static_cast<double>(p.id[i]), p.position[i].x, p.position[i].y,
                                     p.position[i].z, p.velocity[i].x, p.velocity[i].y, p.velocity[i].z});
    const Vec3 momentum = box.coupling->fluid_momentum();
    bits[t].insert(bits[t].end(), {momentum.x, momentum.y, momentum.z});
    for (double e : box.coupling->void_fraction()) bits[t].push_back(e);
  }
  ASSERT_EQ(bits[0].size(), bits[1].size());
  for (std::size_t n = 0; n < bits[0].size(); ++n) EXPECT_EQ(bits[0][n], bits[1][n]) << "value " << n;
}

// A fixed bed (particles on the cell centres, so ε is uniform, 0.7, inside it) with water coming
// in at the bottom: the pressure drop across the bed is Ergun's (1952, Chem. Eng. Prog.
// 48:89-94), −dp/dz = 150 μ (1 − ε)² U/(ε³ d²) + 1.75 ρ_f (1 − ε) U²/(ε³ d), U the superficial
// velocity, with Gidaspow's law (its Ergun branch below ε = 0.8). The fluid holds it through the
// exchange alone (model A: ε ∇p = −β u with β = Σ w β_p / V_cell), so this checks the deposited
// coefficient and the face values against the law the particles use. The particles are held in
// place (an end-of-step hook puts them back at rest where they started: a fixed bed).
TEST(FluidCoupling, FixedBedPressureDropIsErgun) {
  const double cell = 1e-3;                                                 // m
  const double solid_fraction = 0.3;                                        // 1 − ε
  const double diameter = std::cbrt(6.0 * solid_fraction / std::numbers::pi) * cell;  // m
  const double superficial = 0.005;                                         // U (m/s)
  const std::string deck = fmt::format(R"(
simulation:
  end_time: 0.02
  time_step: 2.0e-5
  impact_speed: 0.01
  gravity: [0, 0, 0]
  domain: {{min: [0, 0, 0], max: [0.004, 0.004, 0.012]}}
materials:
  - {{name: solid, density: 2500, youngs_modulus: 1.0e7, poisson_ratio: 0.3}}
interactions:
  - {{materials: [solid, solid]}}
particle_types:
  - {{name: sphere, material: solid, size: {{distribution: fixed, radius: {r}}}}}
)",
                                       fmt::arg("r", 0.5 * diameter));
  World world = build_world(parse_deck_string(deck, "bed.yaml"));
  std::vector<sim::NewParticle> particles;
  for (int k = 3; k < 9; ++k)
    for (int j = 0; j < 4; ++j)
      for (int i = 0; i < 4; ++i) {
        sim::NewParticle particle;
        particle.position = {(i + 0.5) * cell, (j + 0.5) * cell, (k + 0.5) * cell};
        particle.radius = 0.5 * diameter;
        particles.push_back(particle);
      }
  sim::add_particles(world, particles);
  FluidCouplingOptions options;
  options.grid.cell_size = {cell, cell, cell};
  options.grid.cells = {4, 4, 12};
  options.properties = {1000.0, 1e-3};
  options.boundaries.set_periodic(0);
  options.boundaries.set_periodic(1);
  options.boundaries.face(2, 0).kind = cfd::BoundaryKind::velocity_inlet;
  options.boundaries.face(2, 0).velocity = {0.0, 0.0, superficial};
  options.boundaries.face(2, 1).kind = cfd::BoundaryKind::pressure_outlet;
  options.coupling_steps = 5;  // fluid step 1e-4 s
  options.drag_law = cfd::DragLaw::gidaspow;
  auto coupling = FluidCoupling::attach(world, options);
  StepHook hold;
  hold.name = "fixed bed";
  hold.run = [&particles](World& w) {
    for (std::size_t n = 0; n < w.particles.size(); ++n) {
      w.particles.position[n] = particles[w.particles.id[n] - 1].position;
      w.particles.velocity[n] = Vec3{};
    }
  };
  world.hooks.push_back(hold);
  sim::initialize(world);
  sim::advance(world, 1000);
  const double epsilon = 1.0 - solid_fraction;
  // Uniform inside the bed, but for the one step's drift (a dt² ≈ 3e-12 m) before the hook.
  EXPECT_NEAR(coupling->void_fraction()[options.grid.cell_index(1, 2, 5)], epsilon, 1e-8);
  const double mu = 1e-3, rho = 1000.0;
  const double ergun = 150.0 * mu * std::pow(1.0 - epsilon, 2) * superficial /
                           (std::pow(epsilon, 3) * diameter * diameter) +
                       1.75 * rho * (1.0 - epsilon) * superficial * superficial /
                           (std::pow(epsilon, 3) * diameter);  // Pa/m
  const double measured = (coupling->fluid().pressure(1, 2, 4) - coupling->fluid().pressure(1, 2, 7)) /
                          (3.0 * cell);
  std::printf("[ measured ] fixed bed: −dp/dz %.7g Pa/m, Ergun %.7g Pa/m (ε %.3f, d %.4g m, U %.3g m/s)\n",
              measured, ergun, epsilon, diameter, superficial);
  EXPECT_NEAR(measured / ergun, 1.0, 0.01);
}

// Cells smaller than 3 particle volumes are refused with a hint.
TEST(FluidCoupling, RefusesCellsTooSmallForTheParticles) {
  SettlingCase c;
  World world = settling_world(c);
  FluidCouplingOptions options = settling_options(c);
  options.grid.cell_size = {1.1e-4, 1.1e-4, 1.1e-4};  // 1.33e-12 m³ < 3 x 5.24e-13 m³
  try {
    FluidCoupling coupling(world, options);
    FAIL() << "accepted cells of 1.1 particle diameters";
  } catch (const UserError& e) {
    EXPECT_NE(std::string(e.what()).find("less than 3 times the volume"), std::string::npos) << e.what();
  }
  options.grid.cell_size = {1.5e-4, 1.5e-4, 1.5e-4};  // 3.375e-12 m³ > 3 x 5.24e-13 m³
  EXPECT_NO_THROW(FluidCoupling(world, options));
}

}  // namespace
}  // namespace quarry::cfdem
