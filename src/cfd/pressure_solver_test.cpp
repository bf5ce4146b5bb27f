// The multigrid-CG pressure solver: a variable-coefficient 7-point system with blocked cells,
// Dirichlet and periodic boundaries, and a singular all-Neumann one, against a known solution
// (b = A x_exact with A applied by an independent loop here); iteration counts per grid size.
#include "cfd/pressure_solver.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>
#include <vector>

namespace quarry::cfd {
namespace {

// y = A x straight from the definition in stencil_system.h.
std::vector<double> apply_reference(const StencilSystem& s, const std::vector<double>& x) {
  std::vector<double> y(s.count(), 0.0);
  for (int k = 0; k < s.size[2]; ++k) {
    for (int j = 0; j < s.size[1]; ++j) {
      for (int i = 0; i < s.size[0]; ++i) {
        const std::size_t p = s.index(i, j, k);
        if (!s.active[p]) {
          y[p] = x[p];
          continue;
        }
        double value = (s.mass[p] + s.boundary[0][p] + s.boundary[1][p] + s.boundary[2][p]) * x[p];
        const int at[3] = {i, j, k};
        for (int a = 0; a < 3; ++a) {
          if (s.size[a] == 1) continue;
          for (int side = -1; side <= 1; side += 2) {
            int other[3] = {i, j, k};
            other[a] += side;
            if (other[a] < 0 || other[a] >= s.size[a]) {
              if (!s.periodic[a]) continue;
              other[a] = (other[a] + s.size[a]) % s.size[a];
            }
            const std::size_t q = s.index(other[0], other[1], other[2]);
            const double g = side < 0 ? s.conductance[a][p] : s.conductance[a][q];
            (void)at;
            value += g * x[p];
            if (s.active[q]) value -= g * x[q];
          }
        }
        y[p] = value;
      }
    }
  }
  return y;
}

// −∇·(ε∇p) with per-cell random ε in [0.35, 1] (harmonic face means), as coupling-notes §4.2.
StencilSystem rough_poisson(std::array<int, 3> size, std::array<bool, 3> periodic, bool dirichlet,
                            double blocked_fraction, unsigned seed) {
  StencilSystem s;
  s.reset(size, periodic);
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> porosity(0.35, 1.0), unit(0.0, 1.0);
  std::vector<double> eps(s.count());
  for (double& e : eps) e = porosity(random);
  for (std::size_t p = 0; p < s.count(); ++p) s.active[p] = unit(random) < blocked_fraction ? 0 : 1;
  for (int k = 0; k < size[2]; ++k) {
    for (int j = 0; j < size[1]; ++j) {
      for (int i = 0; i < size[0]; ++i) {
        const std::size_t p = s.index(i, j, k);
        const int at[3] = {i, j, k};
        for (int a = 0; a < 3; ++a) {
          int other[3] = {i, j, k};
          other[a] -= 1;
          if (other[a] < 0) {
            if (periodic[a]) {
              other[a] = size[a] - 1;
            } else {
              if (dirichlet) s.boundary[a][p] += 2.0 * eps[p];
              continue;
            }
          }
          const std::size_t q = s.index(other[0], other[1], other[2]);
          if (!s.active[p] || !s.active[q]) continue;
          s.conductance[a][p] = 2.0 * eps[p] * eps[q] / (eps[p] + eps[q]);
          (void)at;
        }
      }
    }
  }
  return s;
}

double relative_error(const std::vector<double>& x, const std::vector<double>& exact) {
  double difference = 0.0, norm = 0.0;
  for (std::size_t p = 0; p < x.size(); ++p) {
    difference += (x[p] - exact[p]) * (x[p] - exact[p]);
    norm += exact[p] * exact[p];
  }
  return std::sqrt(difference / norm);
}

TEST(PressureSolverTest, RecoversKnownSolutionWithBlockedCells) {
  StencilSystem s = rough_poisson({24, 20, 10}, {true, false, false}, true, 0.05, 1);
  std::mt19937 random(2);
  std::uniform_real_distribution<double> value(-1.0, 1.0);
  std::vector<double> exact(s.count());
  for (std::size_t p = 0; p < s.count(); ++p) exact[p] = s.active[p] ? value(random) : 0.0;
  const std::vector<double> b = apply_reference(s, exact);
  auto solver = make_multigrid_cg_solver(Threading{});
  solver->set_system(s);
  std::vector<double> x(s.count(), 0.0);
  const SolveReport report = solver->solve(b, x, 1e-12, 200);
  std::printf("rough Dirichlet 24x20x10, 5%% blocked: %d iterations\n", report.iterations);
  EXPECT_TRUE(report.converged);
  EXPECT_LT(relative_error(x, exact), 1e-9);
}

// take_system (the fluid solver's call: no copy of the operator) solves as set_system does, to
// the bit, step after step, and hands back the sizes and active flags it was given.
TEST(PressureSolverTest, TakingTheSystemSolvesAsSettingItAndKeepsTheActiveFlags) {
  auto copying = make_multigrid_cg_solver(Threading{});
  auto taking = make_multigrid_cg_solver(Threading{});
  for (int step = 0; step < 3; ++step) {
    StencilSystem s = rough_poisson({20, 16, 12}, {true, false, false}, true, 0.05, 10 + step);
    std::mt19937 random(20 + step);
    std::uniform_real_distribution<double> value(-1.0, 1.0);
    std::vector<double> b(s.count());
    for (std::size_t p = 0; p < s.count(); ++p) b[p] = s.active[p] ? value(random) : 0.0;
    const StencilSystem given = s;
    copying->set_system(s);
    taking->take_system(s);
    EXPECT_EQ(s.size, given.size);
    EXPECT_EQ(s.periodic, given.periodic);
    EXPECT_EQ(s.active, given.active);
    std::vector<double> x(s.count(), 0.0), y(s.count(), 0.0);
    const SolveReport a = copying->solve(b, x, 1e-10, 200);
    const SolveReport c = taking->solve(b, y, 1e-10, 200);
    EXPECT_TRUE(a.converged);
    EXPECT_EQ(a.iterations, c.iterations);
    EXPECT_EQ(0, std::memcmp(x.data(), y.data(), x.size() * sizeof(double))) << "step " << step;
  }
}

TEST(PressureSolverTest, SingularNeumannSystemReturnsZeroMeanSolution) {
  StencilSystem s = rough_poisson({16, 12, 8}, {true, false, true}, false, 0.0, 3);
  std::mt19937 random(4);
  std::uniform_real_distribution<double> value(-1.0, 1.0);
  std::vector<double> exact(s.count());
  double mean = 0.0;
  for (double& e : exact) mean += (e = value(random));
  mean /= static_cast<double>(exact.size());
  for (double& e : exact) e -= mean;
  std::vector<double> b = apply_reference(s, exact);
  b[7] += 1e-3;  // an inconsistent part, removed as the mean of b
  auto solver = make_multigrid_cg_solver(Threading{});
  solver->set_system(s);
  std::vector<double> x(s.count(), 0.0);
  const SolveReport report = solver->solve(b, x, 1e-12, 200);
  EXPECT_TRUE(report.converged);
  EXPECT_NEAR(report.removed_mean, 1e-3 / static_cast<double>(s.count()), 1e-15);
  // The solution of the consistent part differs from x_exact by A⁺ of a constant-free remainder.
  b[7] -= 1e-3;
  std::vector<double> y(s.count(), 0.0);
  solver->solve(b, y, 1e-12, 200);
  EXPECT_LT(relative_error(y, exact), 1e-9);
}

// Multigrid: the iteration count does not grow with the grid (coupling-notes §4.2's problem:
// rough ε, homogeneous Dirichlet, relative residual 1e-8).
TEST(PressureSolverTest, IterationsIndependentOfGridSize) {
  std::vector<int> iterations;
  for (int n : {16, 32, 48}) {
    StencilSystem s = rough_poisson({n, n, n}, {false, false, false}, true, 0.0, 5);
    std::vector<double> b(s.count(), 1.0), x(s.count(), 0.0);
    auto solver = make_multigrid_cg_solver(Threading{});
    solver->set_system(s);
    const SolveReport report = solver->solve(b, x, 1e-8, 200);
    EXPECT_TRUE(report.converged);
    iterations.push_back(report.iterations);
    std::printf("rough Poisson %d^3: %d iterations\n", n, report.iterations);
  }
  EXPECT_LE(iterations[2], iterations[0] + 6);
  EXPECT_LE(iterations[2], 30);
}

// Anisotropic cells (Δx = 8 Δy: couplings along y 64 times those along x): semi-coarsening keeps
// the count near the isotropic one, where full coarsening with a point smoother needed 36.
TEST(PressureSolverTest, AnisotropicCellsKeepFewIterations) {
  StencilSystem s = rough_poisson({16, 64, 4}, {false, false, true}, true, 0.0, 6);
  for (double& g : s.conductance[1]) g *= 64.0;
  for (double& g : s.boundary[1]) g *= 64.0;
  std::vector<double> b(s.count(), 1.0), x(s.count(), 0.0);
  auto solver = make_multigrid_cg_solver(Threading{});
  solver->set_system(s);
  const SolveReport report = solver->solve(b, x, 1e-8, 200);
  std::printf("anisotropic 16x64x4, couplings 1:64: %d iterations\n", report.iterations);
  EXPECT_TRUE(report.converged);
  EXPECT_LE(report.iterations, 15);
}

// The half sweeps, transfers and sums split their rows among the team: any team must give the
// bits of one thread. Teams of 1 to 3 on every loop (threshold 0); a periodic z, a bounded z
// with blocked cells, and the singular periodic box.
TEST(PressureSolverTest, AnyTeamGivesTheSameBits) {
  struct Case {
    std::array<int, 3> size;
    std::array<bool, 3> periodic;
    bool dirichlet;
    double blocked;
  };
  for (const Case& c : {Case{{12, 10, 8}, {false, true, true}, true, 0.0},
                        Case{{10, 8, 5}, {true, false, false}, true, 0.08},
                        Case{{8, 8, 6}, {true, true, true}, false, 0.0}}) {
    const StencilSystem s = rough_poisson(c.size, c.periodic, c.dirichlet, c.blocked, 7);
    std::mt19937 random(8);
    std::uniform_real_distribution<double> value(-1.0, 1.0);
    std::vector<double> exact(s.count());
    for (std::size_t p = 0; p < s.count(); ++p) exact[p] = s.active[p] ? value(random) : 0.0;
    const std::vector<double> b = apply_reference(s, exact);
    std::vector<std::vector<double>> solutions;
    for (int threads : {1, 2, 3}) {
      Threading threading;
      threading.threads = threads;
      threading.threshold = 0;
      auto solver = make_multigrid_cg_solver(threading);
      solver->set_system(s);
      std::vector<double> x(s.count(), 0.0);
      const SolveReport report = solver->solve(b, x, 1e-11, 200);
      EXPECT_TRUE(report.converged) << threads << " threads";
      solutions.push_back(x);
    }
    for (std::size_t t = 1; t < solutions.size(); ++t) {
      EXPECT_EQ(std::memcmp(solutions[0].data(), solutions[t].data(), s.count() * sizeof(double)),
                0)
          << "team of " << t + 1 << ", grid " << c.size[0] << "x" << c.size[1] << "x" << c.size[2];
    }
  }
}

}  // namespace
}  // namespace quarry::cfd
