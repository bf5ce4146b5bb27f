// The fluid solver against closed-form and tabulated solutions: plane Poiseuille flow, Taylor-
// Green decay (order of accuracy), continuity after each step, the Re = 100 lid-driven cavity
// of Ghia, Ghia & Shin 1982, a packed bed's momentum balance, ∂ε/∂t, and 1 vs 2 threads.
#include "cfd/fluid_solver.h"

#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <numbers>
#include <stdexcept>
#include <vector>

#include "core/diagnostics.h"

namespace quarry::cfd {
namespace {

constexpr double kPi = std::numbers::pi;

// A channel 0 ≤ y ≤ 1 between no-slip walls, periodic in z; `cells_y` cells across.
FluidGrid channel_grid(int cells_x, int cells_y, double length) {
  FluidGrid grid;
  grid.cells = {cells_x, cells_y, 1};
  grid.cell_size = {length / cells_x, 1.0 / cells_y, 1.0 / cells_y};
  return grid;
}

// Plane Poiseuille flow (e.g. White, Viscous Fluid Flow, 3rd ed., §3-3.2): with the driving
// gradient G = −dp/dx (or a body force density G) between walls at y = 0 and y = h,
// u(y) = G/(2μ) y (h − y) and the flow rate per unit width Q = G h³/(12μ).
struct PoiseuilleErrors {
  double profile = 0.0;    // max |u − u_exact| / u_exact,max over the cell centres
  double flow_rate = 0.0;  // |Q − Q_exact| / Q_exact
};

PoiseuilleErrors poiseuille_errors(const FluidSolver& solver, double gradient, double viscosity) {
  const FluidGrid& grid = solver.grid();
  const double height = 1.0;
  const double peak = gradient / (2.0 * viscosity) * 0.25 * height * height;
  PoiseuilleErrors errors;
  double flow_rate = 0.0;
  for (int j = 0; j < grid.cells[1]; ++j) {
    const double y = grid.cell_centre(0, j, 0).y;
    const double exact = gradient / (2.0 * viscosity) * y * (height - y);
    for (int i = 0; i < grid.cells[0]; ++i) {
      const double u = solver.face_velocity(0, i, j, 0);
      errors.profile = std::max(errors.profile, std::abs(u - exact) / peak);
    }
    flow_rate += solver.face_velocity(0, 0, j, 0) * grid.cell_size.y;
  }
  const double exact_rate = gradient * height * height * height / (12.0 * viscosity);
  errors.flow_rate = std::abs(flow_rate - exact_rate) / exact_rate;
  return errors;
}

TEST(FluidSolverTest, PoiseuilleDrivenByBodyForce) {
  FluidBoundaries boundaries;
  boundaries.set_periodic(0);
  boundaries.set_periodic(2);
  FluidProperties fluid{1.0, 1.0};
  FluidSolver solver(channel_grid(4, 32, 1.0), fluid, boundaries);
  const double gradient = 8.0;  // G (N/m³)
  for (Vec3& f : solver.force_density()) f = {gradient, 0.0, 0.0};
  // Implicit viscosity: steps of 10 diffusion times h²/ν reach the steady state in a few.
  for (int n = 0; n < 20; ++n) solver.step(10.0);
  const PoiseuilleErrors errors = poiseuille_errors(solver, gradient, fluid.viscosity);
  std::printf("body-force Poiseuille, 32 cells across: profile %.3e, flow rate %.3e\n",
              errors.profile, errors.flow_rate);
  EXPECT_LT(errors.profile, 0.01);
  EXPECT_LT(errors.flow_rate, 0.01);
}

TEST(FluidSolverTest, PoiseuilleDrivenByPressureOutlets) {
  const double length = 2.0, gradient = 8.0;
  FluidBoundaries boundaries;
  boundaries.set_periodic(2);
  // p = G L at x = 0 and p = 0 at x = L (two outlets with their reference pressures).
  boundaries.face(0, 0).kind = BoundaryKind::pressure_outlet;
  boundaries.face(0, 0).reference_pressure = gradient * length;
  boundaries.face(0, 1).kind = BoundaryKind::pressure_outlet;
  FluidProperties fluid{1.0, 1.0};
  FluidSolver solver(channel_grid(8, 32, length), fluid, boundaries);
  // The incremental projection corrects the pressure by dt/ρ ∇φ while the implicit viscous
  // response is Δy²/μ: its pressure settles in few steps only for ν dt/Δy² of order 10 or less
  // (here 20); the velocity develops over h²/ν = 1 s, run 4 s.
  for (int n = 0; n < 200; ++n) solver.step(0.02);
  const PoiseuilleErrors errors = poiseuille_errors(solver, gradient, fluid.viscosity);
  std::printf(
      "pressure-driven Poiseuille, 32 cells across: profile %.3e, flow rate %.3e, pressure "
      "iterations %d\n",
      errors.profile, errors.flow_rate, solver.last_report().pressure.iterations);
  EXPECT_LT(errors.profile, 0.01);
  EXPECT_LT(errors.flow_rate, 0.01);
  // The pressure falls linearly: p(x) = G (L − x) at every cell centre.
  for (int i = 0; i < 8; ++i) {
    const double x = solver.grid().cell_centre(i, 0, 0).x;
    EXPECT_NEAR(solver.pressure(i, 5, 0), gradient * (length - x), 1e-6 * gradient * length);
  }
}

// Taylor-Green vortex (Taylor & Green 1937): in the periodic box [0, 2π)², u = sin x cos y F,
// v = −cos x sin y F, p = ρ/4 (cos 2x + cos 2y) F², F = exp(−2νt), solves Navier-Stokes
// exactly. dt ∝ Δx², so the first-order time error shrinks as Δx² too and the error ratio per
// halving measures the spatial order: 4 for second order.
double taylor_green_error(int cells) {
  const double length = 2.0 * kPi, nu = 0.1, end_time = 0.5;
  FluidGrid grid;
  grid.cells = {cells, cells, 1};
  const double h = length / cells;
  grid.cell_size = {h, h, h};
  FluidBoundaries boundaries;
  for (int a = 0; a < 3; ++a) boundaries.set_periodic(a);
  const FluidProperties fluid{1.0, nu};
  FluidSolverOptions options;
  options.threading.threads = 1;  // fast on shared CI cores; OneAndTwoThreads covers 2 threads
  FluidSolver solver(grid, fluid, boundaries, options);
  solver.set_velocity([](const Vec3& x) {
    return Vec3{std::sin(x.x) * std::cos(x.y), -std::cos(x.x) * std::sin(x.y), 0.0};
  });
  solver.set_pressure([&](const Vec3& x) {
    return fluid.density / 4.0 * (std::cos(2.0 * x.x) + std::cos(2.0 * x.y));
  });
  const int steps = static_cast<int>(std::ceil(end_time / (0.13 * h * h)));
  const double dt = end_time / steps;
  for (int n = 0; n < steps; ++n) solver.step(dt);
  const double decay = std::exp(-2.0 * nu * end_time);
  double sum = 0.0;
  for (int j = 0; j < cells; ++j) {
    for (int i = 0; i < cells; ++i) {
      const double x = i * h, y = (j + 0.5) * h;  // the u face at the low side of cell (i, j)
      const double exact = std::sin(x) * std::cos(y) * decay;
      sum +=
          (solver.face_velocity(0, i, j, 0) - exact) * (solver.face_velocity(0, i, j, 0) - exact);
    }
  }
  return std::sqrt(sum / (cells * cells)) / decay;
}

TEST(FluidSolverTest, TaylorGreenSecondOrderInSpace) {
  const double coarse = taylor_green_error(12), medium = taylor_green_error(24),
               fine = taylor_green_error(48);
  const double order_coarse = std::log2(coarse / medium), order_fine = std::log2(medium / fine);
  std::printf(
      "Taylor-Green L2 errors (relative): 12² %.3e, 24² %.3e, 48² %.3e; orders %.3f, %.3f\n",
      coarse, medium, fine, order_coarse, order_fine);
  EXPECT_GT(order_coarse, 1.8);
  EXPECT_GT(order_fine, 1.8);
  EXPECT_LT(order_fine, 2.3);
}

// A 3-D box with every boundary kind but periodic in z, a blocked block, ε varying in space and
// time and drag: after each step ∇·(εu) + ∂ε/∂t vanishes to the pressure tolerance, i.e.
// ‖r‖∞ ≤ ‖r‖₂ ≤ tol ‖r*‖₂ ≤ tol √N ‖r*‖∞ with r* the residual of the predicted velocity.
FluidSolver mixed_box(const Threading& threading, Advection advection = Advection::central) {
  FluidGrid grid;
  grid.cells = {16, 12, 8};
  grid.cell_size = {0.1, 0.1, 0.1};
  FluidBoundaries boundaries;
  boundaries.face(0, 0).kind = BoundaryKind::velocity_inlet;
  boundaries.face(0, 0).velocity = {0.2, 0.05, 0.0};
  boundaries.face(0, 1).kind = BoundaryKind::pressure_outlet;
  boundaries.face(1, 1).velocity = {0.1, 0.0, 0.05};  // a sliding wall
  boundaries.set_periodic(2);
  FluidSolverOptions options;
  options.gravity = {0.0, -9.81, 0.0};
  options.threading = threading;
  options.advection = advection;
  FluidSolver solver(grid, FluidProperties{1000.0, 1.0}, boundaries, options);
  for (int k = 0; k < 8; ++k) {
    for (int j = 3; j < 6; ++j) {
      for (int i = 6; i < 9; ++i) solver.blocked()[grid.cell_index(i, j, k)] = 1;
    }
  }
  for (std::size_t c = 0; c < grid.cell_count(); ++c) solver.drag_coefficient()[c] = 50.0 * (c % 7);
  return solver;
}

std::vector<double> porosity_at(const FluidGrid& grid, double time) {
  std::vector<double> eps(grid.cell_count());
  for (int k = 0; k < grid.cells[2]; ++k) {
    for (int j = 0; j < grid.cells[1]; ++j) {
      for (int i = 0; i < grid.cells[0]; ++i) {
        const Vec3 x = grid.cell_centre(i, j, k);
        eps[grid.cell_index(i, j, k)] =
            0.7 + 0.2 * std::sin(4.0 * x.x + 2.0 * time) * std::cos(3.0 * x.y + x.z);
      }
    }
  }
  return eps;
}

TEST(FluidSolverTest, DivergenceFreeToSolverToleranceAfterEveryStep) {
  FluidSolver solver = mixed_box(Threading{});
  const FluidGrid& grid = solver.grid();
  const double dt = 0.01;
  solver.set_void_fraction(porosity_at(grid, 0.0));
  const double tolerance = 1e-10;
  for (int n = 1; n <= 10; ++n) {
    solver.set_void_fraction(porosity_at(grid, n * dt));
    solver.step(dt);
    const FluidStepReport& report = solver.last_report();
    std::printf("step %d: pressure %d iterations, momentum %d/%d/%d, |r*| %.3e -> |r| %.3e 1/s\n",
                n, report.pressure.iterations, report.momentum[0].iterations,
                report.momentum[1].iterations, report.momentum[2].iterations,
                report.predicted_divergence, report.divergence);
    EXPECT_TRUE(report.pressure.converged);
    EXPECT_GT(report.predicted_divergence, 1e-4);
    EXPECT_LE(report.divergence, tolerance * std::sqrt(static_cast<double>(grid.cell_count())) *
                                     report.predicted_divergence);
  }
  // No flow through the blocked block's faces (cells 6-8 × 3-5 × all k).
  for (int k = 0; k < 8; ++k) {
    for (int j = 3; j < 6; ++j) {
      for (int i = 6; i < 10; ++i) EXPECT_EQ(solver.face_velocity(0, i, j, k), 0.0);
    }
    for (int j = 3; j < 7; ++j) {
      for (int i = 6; i < 9; ++i) EXPECT_EQ(solver.face_velocity(1, i, j, k), 0.0);
    }
  }
}

// Same inputs and steps on 1 and on 2 threads (every loop on a team: threshold 0), and with the
// team switched between steps as the run loop's thread governor does: identical bits.
// Both advection schemes (hybrid upwinds here: face Péclet numbers up to about 20).
TEST(FluidSolverTest, OneAndTwoThreadsBitIdentical) {
  for (const Advection advection : {Advection::central, Advection::hybrid}) {
    std::vector<std::vector<double>> results;
    for (int threads : {1, 2, 0}) {  // 0: 2, 1, 2, 1, … from step to step
      Threading threading;
      threading.threads = threads == 0 ? 2 : threads;
      threading.threshold = 0;
      FluidSolver solver = mixed_box(threading, advection);
      const FluidGrid& grid = solver.grid();
      for (int n = 1; n <= 5; ++n) {
        if (threads == 0) {
          threading.threads = n % 2 == 1 ? 2 : 1;
          solver.set_threading(threading);
        }
        solver.set_void_fraction(porosity_at(grid, n * 0.01));
        solver.step(0.01);
      }
      std::vector<double> state;
      for (int k = 0; k < grid.cells[2]; ++k) {
        for (int j = 0; j < grid.cells[1]; ++j) {
          for (int i = 0; i < grid.cells[0]; ++i) {
            for (int a = 0; a < 3; ++a) state.push_back(solver.face_velocity(a, i, j, k));
            state.push_back(solver.pressure(i, j, k));
          }
        }
      }
      results.push_back(state);
    }
    for (std::size_t r = 1; r < results.size(); ++r) {
      ASSERT_EQ(results[0].size(), results[r].size());
      EXPECT_EQ(std::memcmp(results[0].data(), results[r].data(), results[0].size() * sizeof(double)), 0)
          << "variant " << r << (advection == Advection::hybrid ? ", hybrid" : ", central");
    }
  }
}

// Lid-driven cavity at Re = U L/ν = 100 (n × n cells, one deep, periodic in z) against Ghia,
// Ghia & Shin 1982 (J. Comput. Phys. 48:387-411), Table I (u on the vertical centreline x = 0.5)
// and Table II (v on the horizontal centreline y = 0.5), Re = 100 columns; run until
// |∂u/∂t| < 1e-4 m/s² at (0.5, 0.25).
void check_cavity_against_ghia(int n, double dt) {
  constexpr std::array<double, 17> kGhiaY{1.0,    0.9766, 0.9688, 0.9609, 0.9531, 0.8516,
                                          0.7344, 0.6172, 0.5,    0.4531, 0.2813, 0.1719,
                                          0.1016, 0.0703, 0.0625, 0.0547, 0.0};
  constexpr std::array<double, 17> kGhiaU{
      1.0,      0.84123,  0.78871,  0.73722,  0.68717,  0.23151,  0.00332,  -0.13641, -0.20581,
      -0.21090, -0.15662, -0.10150, -0.06434, -0.04775, -0.04192, -0.03717, 0.0};
  constexpr std::array<double, 17> kGhiaX{1.0,    0.9688, 0.9609, 0.9531, 0.9453, 0.9063,
                                          0.8594, 0.8047, 0.5,    0.2344, 0.2266, 0.1563,
                                          0.0938, 0.0781, 0.0703, 0.0625, 0.0};
  constexpr std::array<double, 17> kGhiaV{
      0.0,     -0.05906, -0.07391, -0.08864, -0.10313, -0.16914, -0.22445, -0.24533, 0.05454,
      0.17527, 0.17507,  0.16077,  0.12317,  0.10890,  0.10091,  0.09233,  0.0};
  FluidGrid grid;
  grid.cells = {n, n, 1};
  grid.cell_size = {1.0 / n, 1.0 / n, 1.0 / n};
  FluidBoundaries boundaries;
  boundaries.face(1, 1).velocity = {1.0, 0.0, 0.0};  // the lid, U = 1 m/s
  boundaries.set_periodic(2);
  FluidSolverOptions options;
  options.threading.threads = 1;  // fast on shared CI cores; OneAndTwoThreads covers 2 threads
  FluidSolver solver(grid, FluidProperties{1.0, 0.01}, boundaries, options);
  double change = 1.0;
  int steps = 0;
  while (steps < 4000 && change > 1e-4) {
    const double before = solver.face_velocity(0, n / 2, n / 4, 0);
    solver.step(dt);
    ++steps;
    change = std::abs(solver.face_velocity(0, n / 2, n / 4, 0) - before) / dt;
  }
  // u on x = 0.5 (faces i = n/2) at cell-centre heights, v on y = 0.5 (faces j = n/2) at
  // cell-centre abscissae; the walls' values at 0 and 1; linear in between.
  auto interpolate = [&](double position, auto&& value_at_cell, double at_zero, double at_one) {
    const double s = position * n - 0.5;
    if (s <= 0.0) return at_zero + (value_at_cell(0) - at_zero) * (position * n / 0.5);
    if (s >= n - 1)
      return value_at_cell(n - 1) + (at_one - value_at_cell(n - 1)) * ((s - (n - 1)) / 0.5);
    const int c = static_cast<int>(s);
    return value_at_cell(c) + (value_at_cell(c + 1) - value_at_cell(c)) * (s - c);
  };
  double worst_u = 0.0, worst_v = 0.0;
  for (std::size_t p = 0; p < kGhiaY.size(); ++p) {
    const double u = interpolate(
        kGhiaY[p], [&](int j) { return solver.face_velocity(0, n / 2, j, 0); }, 0.0, 1.0);
    const double v = interpolate(
        kGhiaX[p], [&](int i) { return solver.face_velocity(1, i, n / 2, 0); }, 0.0, 0.0);
    worst_u = std::max(worst_u, std::abs(u - kGhiaU[p]));
    worst_v = std::max(worst_v, std::abs(v - kGhiaV[p]));
  }
  std::printf(
      "cavity Re 100, %d²: %d steps (t = %.1f s), max |u − u_Ghia| %.4f, max |v − v_Ghia| %.4f (× "
      "U)\n",
      n, steps, steps * dt, worst_u, worst_v);
  EXPECT_LT(change, 1e-4);
  EXPECT_LT(worst_u, 0.03);
  EXPECT_LT(worst_v, 0.03);
}

TEST(FluidSolverTest, LidDrivenCavityRe100MatchesGhia) {
  check_cavity_against_ghia(32, 0.02);  // dt = 2ν/U², the explicit advection limit at the lid
}

// The same on 64² (about ten times the work; run with --gtest_also_run_disabled_tests).
TEST(FluidSolverTest, DISABLED_LidDrivenCavityRe100At64MatchesGhia) {
  check_cavity_against_ghia(64, 0.01);
}

// A packed bed: uniform ε < 1 and β > 0, periodic across, driven by two pressure outlets
// (Δp over L). At steady state u is uniform and the momentum balance is the drag alone:
// model A: ε Δp/L = β u; model B: Δp/L = β u (Zhou et al. 2010, eqs. for the fluid phase).
double packed_bed_velocity(VolumeAveragedModel model, double porosity, double drag,
                           double gradient) {
  FluidGrid grid;
  grid.cells = {12, 4, 4};
  grid.cell_size = {0.05, 0.05, 0.05};
  const double length = 12 * 0.05;
  FluidBoundaries boundaries;
  boundaries.face(0, 0).kind = BoundaryKind::pressure_outlet;
  boundaries.face(0, 0).reference_pressure = gradient * length;
  boundaries.face(0, 1).kind = BoundaryKind::pressure_outlet;
  boundaries.set_periodic(1);
  boundaries.set_periodic(2);
  FluidSolverOptions options;
  options.model = model;
  FluidSolver solver(grid, FluidProperties{1000.0, 1e-3}, boundaries, options);
  solver.set_initial_void_fraction(std::vector<double>(grid.cell_count(), porosity));
  for (double& beta : solver.drag_coefficient()) beta = drag;
  // Relaxation time ρε/β = 0.1 s; 100 relaxation times.
  for (int n = 0; n < 200; ++n) solver.step(0.05);
  double largest_spread = 0.0;
  const double u = solver.face_velocity(0, 0, 0, 0);
  for (int i = 0; i <= 12; ++i)
    largest_spread = std::max(largest_spread, std::abs(solver.face_velocity(0, i, 2, 1) - u));
  EXPECT_LT(largest_spread, 1e-12 * std::abs(u));
  return u;
}

TEST(FluidSolverTest, PackedBedPressureDropBalancesDrag) {
  const double porosity = 0.4, drag = 4000.0, gradient = 1000.0;  // β (kg/(m³ s)), Δp/L (Pa/m)
  const double u_a = packed_bed_velocity(VolumeAveragedModel::a, porosity, drag, gradient);
  const double u_b = packed_bed_velocity(VolumeAveragedModel::b, porosity, drag, gradient);
  std::printf(
      "packed bed: model A u = %.12g (ε Δp/L / β = %.12g), model B u = %.12g (Δp/L / β = %.12g)\n",
      u_a, porosity * gradient / drag, u_b, gradient / drag);
  EXPECT_NEAR(u_a, porosity * gradient / drag, 1e-9 * u_a);
  EXPECT_NEAR(u_b, gradient / drag, 1e-9 * u_b);
}

// Fluid at rest in a column under gravity, top outlet with the hydrostatic pressure of seed
// 001 (p = p_ref + ρ g·(x − x_ref)), uniform ε (model A: ε∇p = ερg): it stays at rest.
TEST(FluidSolverTest, HydrostaticColumnStaysAtRest) {
  FluidGrid grid;
  grid.cells = {4, 4, 16};
  grid.cell_size = {0.01, 0.01, 0.01};
  FluidBoundaries boundaries;
  boundaries.face(2, 1).kind = BoundaryKind::pressure_outlet;
  boundaries.face(2, 1).reference_pressure = 101325.0;
  boundaries.face(2, 1).reference_point = {0.0, 0.0, 0.16};
  FluidSolverOptions options;
  options.gravity = {0.0, 0.0, -9.81};
  FluidSolver solver(grid, FluidProperties{1000.0, 1e-3}, boundaries, options);
  solver.set_initial_void_fraction(std::vector<double>(grid.cell_count(), 0.6));
  for (int n = 0; n < 10; ++n) solver.step(1e-3);
  double fastest = 0.0;
  for (int k = 0; k < 16; ++k) fastest = std::max(fastest, norm(solver.cell_velocity(1, 2, k)));
  EXPECT_LT(fastest, 1e-12);
  // p at the bottom cell centre: p_ref + ρ g (0.16 − 0.005).
  EXPECT_NEAR(solver.pressure(1, 1, 0), 101325.0 + 1000.0 * 9.81 * 0.155, 1e-6);
}

// ∂ε/∂t: with u = 0 and no forcing the first step's velocity is what continuity asks for,
// ∂(εu)/∂x = −∂ε/∂t. Uniform rate r in a channel closed at x = 0 with an outlet at x = L:
// εu(x) = −r x at every face. A closed box with ε^{n+1} − ε^n = δ cos(2πx/L): the flux at
// face x_f is −(1/dt) Σ_{cells left of x_f} (ε^{n+1} − ε^n) Δx.
TEST(FluidSolverTest, VoidFractionRateDrivesConsistentVelocity) {
  const int n = 20;
  const double dx = 0.05, dt = 0.01;
  FluidGrid grid;
  grid.cells = {n, 3, 3};
  grid.cell_size = {dx, dx, dx};
  for (bool closed : {false, true}) {
    FluidBoundaries boundaries;
    boundaries.set_periodic(1);
    boundaries.set_periodic(2);
    if (!closed) boundaries.face(0, 1).kind = BoundaryKind::pressure_outlet;
    FluidSolver solver(grid, FluidProperties{1000.0, 1e-3}, boundaries);
    std::vector<double> before(grid.cell_count()), after(grid.cell_count());
    for (int k = 0; k < 3; ++k) {
      for (int j = 0; j < 3; ++j) {
        for (int i = 0; i < n; ++i) {
          const std::size_t c = grid.cell_index(i, j, k);
          before[c] = 0.6;
          after[c] = closed ? 0.6 + 0.05 * std::cos(2.0 * kPi * (i + 0.5) / n) : 0.6 - 0.1 * dt;
        }
      }
    }
    solver.set_initial_void_fraction(before);
    solver.set_void_fraction(after);
    solver.step(dt);
    double cumulative = 0.0, worst = 0.0, scale = 0.0;
    for (int i = 0; i <= n; ++i) {
      const double eps_face =
          i == 0   ? after[grid.cell_index(0, 1, 1)]
          : i == n ? after[grid.cell_index(n - 1, 1, 1)]
                   : 0.5 * (after[grid.cell_index(i - 1, 1, 1)] + after[grid.cell_index(i, 1, 1)]);
      const double expected = -cumulative / dt;
      const double flux = eps_face * solver.face_velocity(0, i, 1, 1);
      worst = std::max(worst, std::abs(flux - expected));
      scale = std::max(scale, std::abs(expected));
      if (i < n)
        cumulative += (after[grid.cell_index(i, 1, 1)] - before[grid.cell_index(i, 1, 1)]) * dx;
    }
    std::printf("dε/dt %s: max |εu − expected| %.3e of %.3e m/s\n",
                closed ? "closed box" : "outlet", worst, scale);
    EXPECT_GT(scale, 1e-3);
    EXPECT_LT(worst, 1e-8 * scale);
  }
}

TEST(FluidSolverTest, RefusesBadInputAndReportsAFailedSolve) {
  FluidGrid grid;
  grid.cells = {8, 8, 8};
  grid.cell_size = {0.1, 0.1, 0.1};
  FluidBoundaries boundaries;
  boundaries.face(0, 0).kind = BoundaryKind::periodic;  // x+ stays a wall: unpaired
  EXPECT_THROW(FluidSolver(grid, FluidProperties{}, boundaries), std::invalid_argument);
  EXPECT_THROW(FluidSolver(grid, FluidProperties{-1.0, 1e-3}, FluidBoundaries{}),
               std::invalid_argument);
  FluidSolver solver(grid, FluidProperties{}, FluidBoundaries{});
  EXPECT_THROW(solver.step(0.0), std::invalid_argument);
  EXPECT_THROW(solver.set_void_fraction(std::vector<double>(grid.cell_count(), 1.5)),
               std::invalid_argument);
  EXPECT_THROW(solver.set_void_fraction(std::vector<double>(3, 0.5)), std::invalid_argument);

  // One Krylov iteration cannot reach 1e-14 on a nontrivial pressure solve.
  FluidSolverOptions options;
  options.max_iterations = 1;
  options.pressure_tolerance = 1e-14;
  FluidBoundaries inlet;
  inlet.face(0, 0).kind = BoundaryKind::velocity_inlet;
  inlet.face(0, 0).velocity = {1.0, 0.0, 0.0};
  inlet.face(0, 1).kind = BoundaryKind::pressure_outlet;
  FluidSolver stalled(grid, FluidProperties{}, inlet, options);
  // A physics fault of the run (exit code 3), not an internal error (4).
  EXPECT_THROW(stalled.step(0.01), PhysicsError);

  // A source out of range (gravity of 1e308 m/s², a value a deck fuzzer found accepted): the
  // momentum solve's right-hand side overflows; said as such, not as a solve too slow.
  FluidSolverOptions huge;
  huge.gravity = {0.0, 1e308, -9.81};
  FluidSolver overflowing(grid, FluidProperties{}, inlet, huge);
  try {
    overflowing.step(0.01);
    ADD_FAILURE() << "a step with gravity 1e308 m/s² passed";
  } catch (const PhysicsError& e) {
    EXPECT_NE(std::strstr(e.what(), "not finite"), nullptr) << e.what();
    EXPECT_NE(std::strstr(e.what(), "check gravity"), nullptr) << e.what();
  }
}

// A velocity inlet facing a pressure outlet across a box periodic in y and z: plug flow, which
// is an exact solution (u = U, p = p_outlet) that the scheme keeps to round-off.
TEST(FluidSolverTest, InletToOutletPlugFlowStaysUniform) {
  FluidGrid grid;
  grid.cells = {10, 4, 4};
  grid.cell_size = {0.1, 0.1, 0.1};
  FluidBoundaries boundaries;
  boundaries.face(0, 0).kind = BoundaryKind::velocity_inlet;
  boundaries.face(0, 0).velocity = {0.3, 0.0, 0.0};
  boundaries.face(0, 1).kind = BoundaryKind::pressure_outlet;
  boundaries.face(0, 1).reference_pressure = 5.0;
  boundaries.set_periodic(1);
  boundaries.set_periodic(2);
  FluidSolver solver(grid, FluidProperties{1000.0, 1e-3}, boundaries);
  solver.set_velocity([](const Vec3&) { return Vec3{0.3, 0.0, 0.0}; });
  for (int n = 0; n < 20; ++n) solver.step(0.1);
  for (int i = 0; i < 10; ++i) {
    EXPECT_NEAR(norm(solver.cell_velocity(i, 1, 2) - Vec3{0.3, 0.0, 0.0}), 0.0, 1e-12);
    EXPECT_NEAR(solver.pressure(i, 1, 2), 5.0, 1e-9);
  }
}

// A velocity inlet gives the superficial velocity U: its face carries U/ε of the cell inside,
// so the volume flux ε u A is U A through the inlet and, by continuity, through every layer of
// faces, whatever particle volume the cells near the inlet hold (a bed resting on a
// distributor). ε = 0.5, 0.6, 0.8 in the first three layers, 1 beyond; steady.
TEST(FluidSolverTest, VelocityInletFeedsItsSuperficialVelocityIntoAPackedCell) {
  FluidGrid grid;
  grid.cells = {10, 3, 3};
  grid.cell_size = {0.1, 0.1, 0.1};
  FluidBoundaries boundaries;
  boundaries.face(0, 0).kind = BoundaryKind::velocity_inlet;
  boundaries.face(0, 0).velocity = {0.3, 0.0, 0.0};
  boundaries.face(0, 1).kind = BoundaryKind::pressure_outlet;
  boundaries.set_periodic(1);
  boundaries.set_periodic(2);
  FluidSolver solver(grid, FluidProperties{1000.0, 1e-3}, boundaries);
  const std::array<double, 10> layer{0.5, 0.6, 0.8, 1, 1, 1, 1, 1, 1, 1};
  std::vector<double> eps(grid.cell_count());
  for (int k = 0; k < 3; ++k)
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 10; ++i) eps[grid.cell_index(i, j, k)] = layer[static_cast<std::size_t>(i)];
  for (int n = 0; n < 20; ++n) {
    solver.set_void_fraction(eps);
    solver.step(0.05);
  }
  for (int i = 0; i <= 10; ++i) {
    const double face_eps = i == 0    ? layer[0]
                            : i == 10 ? layer[9]
                                      : 0.5 * (layer[static_cast<std::size_t>(i - 1)] + layer[static_cast<std::size_t>(i)]);
    EXPECT_NEAR(face_eps * solver.face_velocity(0, i, 1, 1), 0.3, 1e-10) << "face layer " << i;
  }
  EXPECT_DOUBLE_EQ(solver.face_velocity(0, 0, 2, 0), 0.3 / 0.5);  // interstitial at the inlet
}

// stable_time_step = min(1/Σ_a(max|u_a|/Δx_a), 2ν/Σ_a max u_a²): uniform u = (2, 0, 0) m/s,
// Δx = 0.1 m, ν = 1e-3 m²/s gives min(0.05, 5e-4) s; at rest it is unbounded.
TEST(FluidSolverTest, StableTimeStepFromAdvectionLimits) {
  FluidGrid grid;
  grid.cells = {4, 4, 4};
  grid.cell_size = {0.1, 0.1, 0.1};
  FluidBoundaries boundaries;
  for (int a = 0; a < 3; ++a) boundaries.set_periodic(a);
  FluidSolver solver(grid, FluidProperties{1000.0, 1.0}, boundaries);
  EXPECT_TRUE(std::isinf(solver.stable_time_step()));
  solver.set_velocity([](const Vec3&) { return Vec3{2.0, 0.0, 0.0}; });
  EXPECT_DOUBLE_EQ(solver.stable_time_step(), 2.0 * 1e-3 / 4.0);
}

// The limit with drag. One step of the predictor multiplies the Fourier mode u_y ∝ sin(θ x/Δx)
// carried by a uniform u_x = U through a uniform bed (ε, β) by
// g = (1 − i c sin θ)/(1 + d + 2r(1 − cos θ)), c = U dt/Δx, r = ν dt/Δx², d = β dt/(ρ ε)
// (von Neumann's Fourier analysis: Richtmyer & Morton 1967, Difference Methods for
// Initial-Value Problems, 2nd ed., ch. 4; docs/cfd.md "Time step"): the measured |g|² of three
// modes matches it, every mode is damped at stable_time_step() with the drag, and the shortest
// grows at that step without it.
// Water (ν = 1e-6 m²/s), U = 0.05 m/s, Δx = 1 mm, ε = 0.5, β = 5,000 kg/(m³·s) (β/(ρε) = 10/s):
// the drag lets the step go from 2ν/U² = 0.8 ms to 2(β/ρε)/((U/Δx)² − (β/ρε)²) = 8.3 ms.
// The Fourier mode of the two tests below: water (ρ = 1000 kg/m³, μ = 1e-3 Pa·s) in a periodic
// row of 16 x 2 x 2 cells of Δx = 1 mm at ε = 0.5, u = (U, 1e-3 U sin(θ x/Δx), 0), U = 0.05 m/s.
namespace mode {
constexpr double kRho = 1000.0, kMu = 1e-3, kH = 1e-3, kU = 0.05, kEps = 0.5, kAmplitude = 1e-3 * kU;
constexpr double kNu = kMu / kRho;  // m²/s

std::unique_ptr<FluidSolver> bed(double theta, double beta, Advection advection = Advection::central) {
  FluidGrid grid;
  grid.cells = {16, 2, 2};
  grid.cell_size = {kH, kH, kH};
  FluidBoundaries boundaries;
  for (int a = 0; a < 3; ++a) boundaries.set_periodic(a);
  FluidSolverOptions options;
  options.advection = advection;
  auto solver = std::make_unique<FluidSolver>(grid, FluidProperties{kRho, kMu}, boundaries, options);
  solver->set_void_fraction(std::vector<double>(grid.cell_count(), kEps));
  std::fill(solver->drag_coefficient().begin(), solver->drag_coefficient().end(), beta);
  solver->set_velocity([&](const Vec3& x) { return Vec3{kU, kAmplitude * std::sin(theta * x.x / kH), 0.0}; });
  return solver;
}

double energy(const FluidSolver& solver) {  // Σ u_y² over the y faces (m²/s²)
  double sum = 0.0;
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 16; ++i) sum += std::pow(solver.face_velocity(1, i, j, k), 2);
  return sum;
}

double growth(FluidSolver& solver, double dt) {  // |g|² of the mode over one step
  const double before = energy(solver);
  solver.step(dt);
  return energy(solver) / before;
}
}  // namespace mode

TEST(FluidSolverTest, StableTimeStepWithDragDampsEveryMode) {
  using namespace mode;
  constexpr double kBeta = 5000.0;
  const double nu = kNu;
  const double dt = bed(std::numbers::pi / 2.0, kBeta)->stable_time_step();
  const double drag_free = 2.0 * nu / (kU * kU);
  EXPECT_GT(dt, 10.0 * drag_free);
  EXPECT_LT(dt, kH / kU);  // the CFL limit
  for (const double theta : {std::numbers::pi / 2.0, std::numbers::pi / 4.0, std::numbers::pi / 8.0}) {
    for (const double beta : {kBeta, 0.0}) {
      const auto solver = bed(theta, beta);
      const double measured = growth(*solver, dt);
      const double c = kU * dt / kH, r = nu * dt / (kH * kH), d = beta * dt / (kRho * kEps);
      const double expected =
          (1.0 + std::pow(c * std::sin(theta), 2)) / std::pow(1.0 + d + 2.0 * r * (1.0 - std::cos(theta)), 2);
      EXPECT_NEAR(measured, expected, 1e-8) << theta << " " << beta;
      if (beta > 0.0) {
        EXPECT_LE(measured, 1.0) << theta;
      }
    }
  }
  // Without the drag the same step lets the shortest mode grow: the drag is what makes it stable.
  EXPECT_GT(growth(*bed(std::numbers::pi / 2.0, 0.0), dt), 1.1);
}


// Hybrid advection (Spalding 1972; Patankar 1980, Numerical Heat Transfer and Fluid Flow, §5.2.6)
// needs only the CFL limit. The same mode as above, in water without drag at a cell Péclet number
// UΔx/ν = 50: each x face takes (U/2 − ν/Δx)(u_high − u_low) off the central flux, so
// g = (1 − i c sin θ − (c − 2r)(1 − cos θ))/(1 + d + 2r(1 − cos θ)) (c > 2r; docs/cfd.md "Time
// step"). stable_time_step() is the CFL limit, 1/(U/Δx + max|u_y|/Δx), 25 times 2ν/U²'s bound
// on central advection here; at it and at half of it every mode is damped, as measured to the
// formula, while central advection at the same step makes the shortest mode grow by 85 %.
TEST(FluidSolverTest, HybridAdvectionDampsEveryModeUpToTheCflLimit) {
  using namespace mode;
  const double nu = kNu;
  const double stable = bed(std::numbers::pi / 2.0, 0.0, Advection::hybrid)->stable_time_step();
  // max|u_y| over the faces is the amplitude times the largest |sin| sampled at the cell centres.
  double largest_sine = 0.0;
  for (int i = 0; i < 16; ++i)
    largest_sine = std::max(largest_sine, std::abs(std::sin(std::numbers::pi / 2.0 * (i + 0.5))));
  EXPECT_NEAR(stable, 1.0 / (kU / kH + kAmplitude * largest_sine / kH), 1e-15);
  EXPECT_GT(stable, 20.0 * 2.0 * nu / (kU * kU));
  for (const double dt : {stable, 0.5 * stable}) {
    for (const double theta : {std::numbers::pi / 2.0, std::numbers::pi / 4.0, std::numbers::pi / 8.0}) {
      for (const double beta : {0.0, 5000.0}) {
        const auto solver = bed(theta, beta, Advection::hybrid);
        const double measured = growth(*solver, dt);
        const double c = kU * dt / kH, r = nu * dt / (kH * kH), d = beta * dt / (kRho * kEps);
        const double real = 1.0 - (c - 2.0 * r) * (1.0 - std::cos(theta)), imaginary = c * std::sin(theta);
        const double expected =
            (real * real + imaginary * imaginary) / std::pow(1.0 + d + 2.0 * r * (1.0 - std::cos(theta)), 2);
        EXPECT_NEAR(measured, expected, 1e-8) << dt << " " << theta << " " << beta;
        EXPECT_LE(measured, 1.0) << dt << " " << theta << " " << beta;
      }
    }
  }
  EXPECT_GT(growth(*bed(std::numbers::pi / 2.0, 0.0, Advection::central), stable), 1.8);
}

// Where every face's Péclet number |εu|Δx/(νε) is at most 2, hybrid advection is central to the
// bit; where it is not (the same flow, 4000 times less viscous), it is not.
TEST(FluidSolverTest, HybridAdvectionIsCentralWherePecletNumbersAreSmall) {
  FluidGrid grid;
  grid.cells = {8, 6, 5};
  grid.cell_size = {0.1, 0.1, 0.1};
  FluidBoundaries boundaries;
  boundaries.set_periodic(0);
  boundaries.face(1, 0).kind = BoundaryKind::velocity_inlet;
  boundaries.face(1, 0).velocity = {0.1, 0.5, 0.0};
  boundaries.face(1, 1).kind = BoundaryKind::pressure_outlet;
  boundaries.face(2, 1).velocity = {0.3, 0.0, 0.0};  // a sliding wall
  const auto velocities = [&](double viscosity, Advection advection) {
    FluidSolverOptions options;
    options.advection = advection;
    FluidSolver solver(grid, FluidProperties{1000.0, viscosity}, boundaries, options);
    std::vector<double> eps(grid.cell_count());
    for (std::size_t c = 0; c < eps.size(); ++c) eps[c] = 0.7 + 0.1 * std::sin(0.7 * static_cast<double>(c));
    solver.set_void_fraction(eps);
    solver.set_velocity([](const Vec3& x) {
      return Vec3{0.5 * std::sin(6.0 * x.y), 0.5 + 0.3 * std::cos(5.0 * x.x), 0.4 * std::sin(7.0 * x.x + 3.0 * x.y)};
    });
    for (int n = 0; n < 3; ++n) solver.step(2e-3);
    std::vector<double> u;
    for (int a = 0; a < 3; ++a)
      for (int k = 0; k < grid.cells[2]; ++k)
        for (int j = 0; j < grid.cells[1]; ++j)
          for (int i = 0; i < grid.cells[0]; ++i) u.push_back(solver.face_velocity(a, i, j, k));
    return u;
  };
  // |u| ≤ 1.5 m/s with the ghost values, Δx = 0.1 m, face ε from 0.6 to 0.8: Péclet ≤ 2 needs
  // ν ≥ 0.1 m²/s; ν = 0.2 m²/s (μ = 200 Pa·s).
  EXPECT_EQ(velocities(200.0, Advection::hybrid), velocities(200.0, Advection::central));
  EXPECT_NE(velocities(0.05, Advection::hybrid), velocities(0.05, Advection::central));
}

}  // namespace
}  // namespace quarry::cfd
