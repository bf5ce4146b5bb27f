// The fluid solver against closed-form and tabulated solutions: plane Poiseuille flow, Taylor-
// Green decay (order of accuracy), continuity after each step, the Re = 100 lid-driven cavity
// of Ghia, Ghia & Shin 1982, a packed bed's momentum balance, ∂ε/∂t, and 1 vs 2 threads.
#include "cfd/fluid_solver.h"

#include <gtest/gtest.h>

#include <omp.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <numbers>
#include <vector>

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
  std::printf("body-force Poiseuille, 32 cells across: profile %.3e, flow rate %.3e\n", errors.profile,
              errors.flow_rate);
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
  std::printf("pressure-driven Poiseuille, 32 cells across: profile %.3e, flow rate %.3e, pressure iterations %d\n",
              errors.profile, errors.flow_rate, solver.last_report().pressure.iterations);
  EXPECT_LT(errors.profile, 0.01);
  EXPECT_LT(errors.flow_rate, 0.01);
  // The pressure falls linearly: p(x) = G (L − x) at every cell centre.
  for (int i = 0; i < 8; ++i) {
    const double x = solver.grid().cell_centre(i, 0, 0).x;
    EXPECT_NEAR(solver.pressure(i, 5, 0), gradient * (length - x), 1e-6 * gradient * length);
  }
}

}  // namespace
}  // namespace quarry::cfd
