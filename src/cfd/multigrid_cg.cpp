// Quarry's pressure-solver backend: conjugate gradients (Hestenes & Stiefel 1952) preconditioned
// by one symmetric geometric multigrid V-cycle on the box of unknowns (cell-centred aggregation
// multigrid; Wesseling 1992, "An Introduction to Multigrid Methods", ch. 5 and 7). Deterministic:
// every reduction sums per grid row, then the rows in order.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <span>
#include <vector>

#include "cfd/pressure_solver.h"

namespace quarry::cfd {
namespace {

// The coarsest level is solved directly (dense Cholesky) when it has at most this many unknowns;
// coarsening stops below kCoarsestTarget unknowns.
constexpr std::size_t kDirectSolveLimit = 256;
constexpr std::size_t kCoarsestTarget = 64;
// Red-black Gauss-Seidel sweep pairs before and after the coarse correction, and the sweep
// pairs that stand in for the direct solve when the coarsest level is too large for it.
constexpr int kSmoothingSweeps = 2;
constexpr int kCoarsestSweeps = 40;
// An axis is coarsened when its mean coupling is at least this fraction of the strongest axis'.
constexpr double kStrongCoupling = 0.25;
// A system whose every row couples to its neighbours with at most this fraction of its diagonal
// is preconditioned by the diagonal alone: the Jacobi-scaled matrix I − N has ‖N‖ ≤ 1/4, so
// its condition number is at most (1 + 1/4)/(1 − 1/4) = 5/3 and CG gains a factor of at least
// (√κ − 1)/(√κ + 1) = 0.13 per iteration (Saad 2003, Iterative Methods for Sparse Linear
// Systems, §6.11.3) with no hierarchy to build. The momentum equations of a coupled step are
// such systems (mass ρε/dt far above the viscous couplings μ/Δx²).
constexpr double kDiagonalDominance = 0.25;

struct Level {
  StencilSystem system;
  std::vector<double> diagonal;
  // link[a][P]: the conductance of P with its low neighbour along a where both are active
  // unknowns, 0 otherwise (no neighbour, or either held). P's high neighbour Q is reached
  // through link[a][Q]: the stencil is read from the grid's strides, not from index lists.
  std::array<std::vector<double>, 3> link;
  std::vector<double> solution, rhs;  // work vectors of this level
  std::array<int, 3> ratio{1, 1, 1};  // coarsening ratio towards the next level
  bool colours_independent = true;    // a red-black half sweep may run on a team
  // Coarsest level only: dense Cholesky factor (row-major, lower) over the active unknowns.
  std::vector<double> cholesky;
  std::vector<std::size_t> dense_to_cell;
  bool direct = false;
};

// Neighbour of P = (i, j, k) along axis a on side -1/+1, or -1 when there is none.
inline std::ptrdiff_t neighbour(const StencilSystem& s, const std::array<int, 3>& at, int a,
                                int side, std::size_t p) {
  const int n = s.size[a];
  if (n == 1) return -1;
  const std::ptrdiff_t stride =
      a == 0 ? 1 : (a == 1 ? s.size[0] : std::ptrdiff_t{s.size[0]} * s.size[1]);
  const auto pi = static_cast<std::ptrdiff_t>(p);
  if (side < 0) {
    if (at[a] > 0) return pi - stride;
    return s.periodic[a] ? pi + (n - 1) * stride : -1;
  }
  if (at[a] < n - 1) return pi + stride;
  return s.periodic[a] ? pi - (n - 1) * stride : -1;
}

// Conductance of the coupling of P with its neighbour q on `side` along a.
inline double coupling(const StencilSystem& s, int a, int side, std::size_t p, std::ptrdiff_t q) {
  return side < 0 ? s.conductance[a][p] : s.conductance[a][static_cast<std::size_t>(q)];
}

// The rows beside grid row (j, k) along y and z as `neighbour` finds them (an axis of one
// unknown has none; periodic axes wrap), and whether the row wraps along x.
struct NeighbourRows {
  std::size_t start = 0;                     // index of (0, j, k)
  std::array<std::size_t, 2> low{}, high{};  // starts of the rows at j∓1 (y), k∓1 (z)
  std::array<bool, 2> has_low{}, has_high{};
  int length = 0;
  bool wrap = false;  // periodic along x with more than one unknown
};

inline NeighbourRows neighbour_rows(const StencilSystem& s, int j, int k) {
  NeighbourRows r;
  r.length = s.size[0];
  r.wrap = s.periodic[0] && s.size[0] > 1;
  r.start = s.index(0, j, k);
  const std::array<int, 2> at{j, k};
  for (int b = 0; b < 2; ++b) {
    const int a = b + 1, n = s.size[a];
    if (n == 1) continue;
    const std::size_t stride = a == 1 ? static_cast<std::size_t>(s.size[0])
                                      : static_cast<std::size_t>(s.size[0]) * s.size[1];
    const auto span = static_cast<std::size_t>(n - 1) * stride;
    r.has_low[b] = at[b] > 0 || s.periodic[a];
    r.low[b] = at[b] > 0 ? r.start - stride : r.start + span;
    r.has_high[b] = at[b] < n - 1 || s.periodic[a];
    r.high[b] = at[b] < n - 1 ? r.start + stride : r.start - span;
  }
  return r;
}

// One grid row (j, k) of a level: where its neighbour rows along y and z start, and the links
// to read. A missing neighbour row (a non-periodic border, or an axis of one unknown) points at
// the row itself with links of 0, so every unknown sums the same six terms.
struct RowStencil {
  std::size_t start = 0;                    // index of (0, j, k)
  std::array<std::size_t, 2> low{}, high{};  // starts of the rows at j∓1 (y), k∓1 (z)
  const double* x_links = nullptr;          // link[0] from (0, j, k)
  std::array<const double*, 2> low_links{}, high_links{};
  int length = 0;     // unknowns along x
  bool wrap = false;  // periodic along x with more than one unknown
};

RowStencil row_stencil(const Level& level, int j, int k, const double* zeros) {
  const NeighbourRows n = neighbour_rows(level.system, j, k);
  RowStencil r;
  r.length = n.length;
  r.wrap = n.wrap;
  r.start = n.start;
  r.x_links = level.link[0].data() + r.start;
  for (int b = 0; b < 2; ++b) {
    const std::vector<double>& links = level.link[static_cast<std::size_t>(b) + 1];
    r.low[b] = n.has_low[b] ? n.low[b] : r.start;
    r.low_links[b] = links.data() + r.start;  // 0 where there is no low neighbour
    r.high[b] = n.has_high[b] ? n.high[b] : r.start;
    r.high_links[b] = n.has_high[b] ? links.data() + r.high[b] : zeros;
  }
  return r;
}

// The link of unknown i of the row with its high neighbour along x (0 at a non-periodic end).
inline double x_high_link(const RowStencil& r, int i) {
  return i < r.length - 1 ? r.x_links[i + 1] : (r.wrap ? r.x_links[0] : 0.0);
}

// Σ over active neighbours N of g_PN x_N for P = (i, j, k) of the row, in the order x−, x+,
// y−, y+, z−, z+ (a missing or held neighbour adds 0 · x_P).
inline double neighbour_sum(const RowStencil& r, const double* x, int i) {
  const double* row = x + r.start;
  double x_low = 0.0, x_high = 0.0, g_high = 0.0;
  if (i > 0 && i < r.length - 1) {
    x_low = row[i - 1];
    x_high = row[i + 1];
    g_high = r.x_links[i + 1];
  } else {
    x_low = i > 0 ? row[i - 1] : (r.wrap ? row[r.length - 1] : row[i]);
    x_high = i < r.length - 1 ? row[i + 1] : (r.wrap ? row[0] : row[i]);
    g_high = x_high_link(r, i);
  }
  return r.x_links[i] * x_low + g_high * x_high + r.low_links[0][i] * x[r.low[0] + i] +
         r.high_links[0][i] * x[r.high[0] + i] + r.low_links[1][i] * x[r.low[1] + i] +
         r.high_links[1][i] * x[r.high[1] + i];
}

// log2 of a coarsening ratio per axis (1 or 2): the coarse index of fine i is i >> shift, not
// an integer division per unknown (the transfers cost 8 % of the fluid step with them).
inline std::array<int, 3> ratio_shifts(const std::array<int, 3>& ratio) {
  return {ratio[0] == 2 ? 1 : 0, ratio[1] == 2 ? 1 : 0, ratio[2] == 2 ? 1 : 0};
}

class MultigridCgSolver final : public PressureSolver {
 public:
  explicit MultigridCgSolver(const Threading& threading) : threading_(threading) {}

  std::string_view name() const override { return "multigrid-cg"; }

  void set_threading(const Threading& threading) override { threading_ = threading; }

  void set_system(const StencilSystem& system) override {
    // A fluid step often repeats the previous operator (same dt, ε and β): keep the hierarchy.
    if (!levels_.empty() && fine_is_input_ && same_system(system, levels_[0].system)) return;
    // The levels are rebuilt in place: their arrays keep their storage from step to step.
    if (levels_.empty()) levels_.emplace_back();
    levels_[0].system = system;
    build_hierarchy();
  }

  void take_system(StencilSystem& system) override {
    if (!levels_.empty() && fine_is_input_ && same_system(system, levels_[0].system)) return;
    if (levels_.empty()) levels_.emplace_back();
    // The coefficients by swapping (the caller gets the previous operator's storage back); the
    // active flags by copy, as prepare_level may hold more unknowns than the caller gave.
    StencilSystem& fine = levels_[0].system;
    fine.size = system.size;
    fine.periodic = system.periodic;
    fine.conductance.swap(system.conductance);
    fine.boundary.swap(system.boundary);
    fine.mass.swap(system.mass);
    fine.active = system.active;
    build_hierarchy();
  }

  SolveReport solve(std::span<const double> rhs_in, std::span<double> x_out, double tolerance,
                    int max_iterations) override {
    Level& fine = levels_[0];
    const StencilSystem& s = fine.system;
    const std::size_t n = s.count();
    SolveReport report;
    // Work vectors kept from call to call (their storage is reused, not faulted in again).
    std::vector<double>& b = work_[0];
    std::vector<double>& x = work_[1];
    b.assign(rhs_in.begin(), rhs_in.end());
    x.assign(x_out.begin(), x_out.end());
    for (std::size_t p = 0; p < n; ++p) {
      if (!s.active[p]) x[p] = b[p];
    }
    if (singular_) {
      report.removed_mean = active_mean(b);
      subtract_on_active(b, report.removed_mean);
    }
    const double b_norm = std::sqrt(dot(b, b));
    if (b_norm == 0.0) {
      for (std::size_t p = 0; p < n; ++p) x[p] = s.active[p] ? 0.0 : b[p];
      std::copy(x.begin(), x.end(), x_out.begin());
      report.converged = true;
      return report;
    }
    std::vector<double>& r = work_[2];
    std::vector<double>& z = work_[3];
    std::vector<double>& direction = work_[4];
    std::vector<double>& q = work_[5];
    for (std::size_t w = 2; w < work_.size(); ++w) work_[w].resize(n);
    (void)apply_dot(fine, x, q);
    for_each(n, [&](std::size_t p) { r[p] = s.active[p] ? b[p] - q[p] : 0.0; });
    double r_norm = std::sqrt(dot(r, r));
    if (r_norm > tolerance * b_norm) {
      precondition(r, z);
      direction = z;
      double rz = dot(r, z);
      while (report.iterations < max_iterations) {
        ++report.iterations;
        const double alpha = rz / apply_dot(fine, direction, q);
        // x += α d and r −= α q, with ‖r‖² summed in the same pass.
        const double r_squared = row_sum(s, [&](std::size_t p) {
          x[p] += alpha * direction[p];
          r[p] -= alpha * q[p];
          return r[p] * r[p];
        });
        r_norm = std::sqrt(r_squared);
        if (r_norm <= tolerance * b_norm) break;
        precondition(r, z);
        const double rz_next = dot(r, z);
        const double beta = rz_next / rz;
        rz = rz_next;
        for_each(n, [&](std::size_t p) { direction[p] = z[p] + beta * direction[p]; });
      }
    }
    report.relative_residual = r_norm / b_norm;
    report.converged = r_norm <= tolerance * b_norm;
    if (singular_) subtract_on_active(x, active_mean(x));
    std::copy(x.begin(), x.end(), x_out.begin());
    return report;
  }

 private:
  // set_system's work once levels_[0].system holds the operator given.
  void build_hierarchy() {
    const StencilSystem& system = levels_[0].system;
    zeros_.assign(static_cast<std::size_t>(system.size[0]), 0.0);
    fine_is_input_ = !prepare_level(levels_[0]);
    singular_ = !has_fixed_part(levels_[0]);
    diagonal_only_ = !singular_ && !couples_beyond(levels_[0], kDiagonalDominance);
    if (diagonal_only_) {
      levels_.resize(1);
      return;
    }
    std::size_t count = 1;
    while (levels_[count - 1].system.count() > kCoarsestTarget) {
      if (levels_.size() == count) levels_.emplace_back();
      if (!coarsen(levels_[count - 1], levels_[count])) break;
      (void)prepare_level(levels_[count]);
      ++count;
    }
    levels_.resize(count);
    factor_coarsest(levels_.back());
  }

  template <class F>
  void for_each(std::size_t n, F&& f) const {
    const int team = threading_.team(n);
#pragma omp parallel for schedule(static) num_threads(team)
    for (std::size_t p = 0; p < n; ++p) f(p);
  }

  // Σ over the grid rows of row_total(row), each row's total computed on the team and the
  // rows added in order: identical bits for any team.
  template <class F>
  double sum_over_rows(const StencilSystem& s, F&& row_total) const {
    const int rows = s.size[1] * s.size[2];
    std::vector<double>& partial = partial_;
    partial.assign(static_cast<std::size_t>(rows), 0.0);
    const int team = threading_.team(s.count());
#pragma omp parallel for schedule(static) num_threads(team)
    for (int row = 0; row < rows; ++row) partial[static_cast<std::size_t>(row)] = row_total(row);
    double total = 0.0;
    for (double value : partial) total += value;
    return total;
  }

  // Σ_rows (Σ_i in row f(p)), the rows summed in order: identical bits for any team.
  template <class F>
  double row_sum(const StencilSystem& s, F&& f) const {
    const std::size_t row_length = static_cast<std::size_t>(s.size[0]);
    return sum_over_rows(s, [&](int row) {
      const std::size_t first = static_cast<std::size_t>(row) * row_length;
      double sum = 0.0;
      for (std::size_t i = 0; i < row_length; ++i) sum += f(first + i);
      return sum;
    });
  }

  double dot(const std::vector<double>& u, const std::vector<double>& v) const {
    return row_sum(levels_[0].system, [&](std::size_t p) { return u[p] * v[p]; });
  }

  double active_mean(const std::vector<double>& v) const {
    const StencilSystem& s = levels_[0].system;
    const double sum = row_sum(s, [&](std::size_t p) { return s.active[p] ? v[p] : 0.0; });
    const double count = row_sum(s, [&](std::size_t p) { return s.active[p] ? 1.0 : 0.0; });
    return count > 0.0 ? sum / count : 0.0;
  }

  void subtract_on_active(std::vector<double>& v, double value) const {
    const StencilSystem& s = levels_[0].system;
    for_each(s.count(), [&](std::size_t p) {
      if (s.active[p]) v[p] -= value;
    });
  }

  // Returns whether it held an unknown the system had active (its level then differs from it).
  bool prepare_level(Level& level) const {
    StencilSystem& s = level.system;
    const std::size_t n = s.count();
    level.diagonal.resize(n);
    for (auto& links : level.link) links.resize(n);
    level.solution.assign(n, 0.0);
    level.rhs.assign(n, 0.0);
    const int rows = s.size[1] * s.size[2];
    const int team = threading_.team(n);
    // Diagonal: mass, boundary terms and every coupling to an existing neighbour (held or
    // not), in the order x−, x+, y−, y+, z−, z+. An unknown coupled to nothing (enclosed by
    // held unknowns) is held as well. Row by row: the neighbours of a row's unknowns along y
    // and z are those of the rows beside it (neighbour_rows), along x the row's own.
    bool held = false;
#pragma omp parallel for schedule(static) num_threads(team) reduction(|| : held)
    for (int row = 0; row < rows; ++row) {
      const NeighbourRows r = neighbour_rows(s, row % s.size[1], row / s.size[1]);
      for (int i = 0; i < s.size[0]; ++i) {
        const std::size_t p = r.start + static_cast<std::size_t>(i);
        double diagonal = s.mass[p] + s.boundary[0][p] + s.boundary[1][p] + s.boundary[2][p];
        if (i > 0 || r.wrap) diagonal += s.conductance[0][p];
        if (i < r.length - 1) {
          diagonal += s.conductance[0][p + 1];
        } else if (r.wrap) {
          diagonal += s.conductance[0][r.start];
        }
        for (int b = 0; b < 2; ++b) {
          if (r.has_low[b]) diagonal += s.conductance[b + 1][p];
          if (r.has_high[b]) diagonal += s.conductance[b + 1][r.high[b] + static_cast<std::size_t>(i)];
        }
        if (diagonal <= 0.0 && s.active[p]) {
          s.active[p] = 0;
          held = true;
        }
        level.diagonal[p] = diagonal;
      }
    }
    // Links once every unknown's state is known.
#pragma omp parallel for schedule(static) num_threads(team)
    for (int row = 0; row < rows; ++row) {
      const NeighbourRows r = neighbour_rows(s, row % s.size[1], row / s.size[1]);
      for (int i = 0; i < s.size[0]; ++i) {
        const std::size_t p = r.start + static_cast<std::size_t>(i);
        const bool x_low = i > 0 || r.wrap;
        const std::size_t q_x = i > 0 ? p - 1 : r.start + static_cast<std::size_t>(r.length - 1);
        level.link[0][p] = x_low && s.active[p] && s.active[q_x] ? s.conductance[0][p] : 0.0;
        for (int b = 0; b < 2; ++b) {
          const bool coupled = r.has_low[b] && s.active[p] && s.active[r.low[b] + static_cast<std::size_t>(i)];
          level.link[b + 1][p] = coupled ? s.conductance[b + 1][p] : 0.0;
        }
      }
    }
    level.colours_independent = true;
    for (int a = 0; a < 3; ++a) {
      if (s.periodic[a] && s.size[a] % 2 == 1 && s.size[a] > 1) level.colours_independent = false;
    }
    return held;
  }

  // Whether some active row has Σ_N g_PN / diagonal(P) > fraction (couplings to active
  // neighbours, summed in neighbour_sum's order). Each thread stops at its first such row: a
  // pressure system, never diagonally dominant, is answered by its first rows, not a pass.
  bool couples_beyond(const Level& level, double fraction) const {
    const StencilSystem& s = level.system;
    const int rows = s.size[1] * s.size[2];
    bool found = false;  // an "any": the same for any team
#pragma omp parallel for schedule(static) num_threads(threading_.team(s.count())) reduction(|| : found)
    for (int row = 0; row < rows; ++row) {
      if (found) continue;  // this thread has its answer
      const RowStencil r = row_stencil(level, row % s.size[1], row / s.size[1], zeros_.data());
      for (int i = 0; i < s.size[0] && !found; ++i) {
        const std::size_t p = r.start + static_cast<std::size_t>(i);
        if (!s.active[p]) continue;
        const double sum = r.x_links[i] + x_high_link(r, i) + r.low_links[0][i] + r.high_links[0][i] +
                           r.low_links[1][i] + r.high_links[1][i];
        found = sum / level.diagonal[p] > fraction;
      }
    }
    return found;
  }

  // Whether some row holds its unknown to a value (mass, a boundary term, or a coupling to a
  // held neighbour); without one the system is singular (constant null space).
  static bool has_fixed_part(const Level& level) {
    const StencilSystem& s = level.system;
    for (int k = 0; k < s.size[2]; ++k) {
      for (int j = 0; j < s.size[1]; ++j) {
        for (int i = 0; i < s.size[0]; ++i) {
          const std::size_t p = s.index(i, j, k);
          if (!s.active[p]) continue;
          if (s.mass[p] > 0.0 || s.boundary[0][p] > 0.0 || s.boundary[1][p] > 0.0 ||
              s.boundary[2][p] > 0.0) {
            return true;
          }
          const std::array<int, 3> at{i, j, k};
          for (int a = 0; a < 3; ++a) {
            for (int side = -1; side <= 1; side += 2) {
              const std::ptrdiff_t q = neighbour(s, at, a, side, p);
              if (q >= 0 && !s.active[static_cast<std::size_t>(q)] &&
                  coupling(s, a, side, p, q) > 0.0) {
                return true;
              }
            }
          }
        }
      }
    }
    return false;
  }

  // Aggregates 2 cells per axis where the axis allows (≥ 2 unknowns, even when periodic).
  bool coarsen(Level& fine_level, Level& coarse_level) const {
    const StencilSystem& fine = fine_level.system;
    std::array<int, 3> ratio{1, 1, 1};
    std::array<int, 3> size = fine.size;
    // Semi-coarsening (as PFMG, Ashby & Falgout 1996): only the axes whose mean coupling is at
    // least kStrongCoupling of the strongest are coarsened, so that a point smoother still
    // smooths the error along the others (anisotropic cells).
    std::array<double, 3> strength{0.0, 0.0, 0.0};
    double strongest = 0.0;
    for (int a = 0; a < 3; ++a) {
      const int n = fine.size[a];
      if (n < 2 || (fine.periodic[a] && n % 2 != 0)) continue;
      const double sum = row_sum(fine, [&](std::size_t p) { return fine.conductance[a][p]; });
      strength[a] = sum / static_cast<double>(fine.count()) + std::numeric_limits<double>::min();
      strongest = std::max(strongest, strength[a]);
    }
    if (strongest == 0.0) return false;
    for (int a = 0; a < 3; ++a) {
      if (strength[a] > 0.0 && strength[a] >= kStrongCoupling * strongest) {
        ratio[a] = 2;
        size[a] = (fine.size[a] + 1) / 2;
      }
    }
    StencilSystem& coarse = coarse_level.system;
    coarse.reset(size, fine.periodic);
    // Each coarse row sums its aggregates' fine cells in grid order (k, j, i): the same bits
    // for any team.
    const int coarse_rows = size[1] * size[2];
    const int team = threading_.team(fine.count());
#pragma omp parallel for schedule(static) num_threads(team)
    for (int coarse_row = 0; coarse_row < coarse_rows; ++coarse_row) {
      const int cj = coarse_row % size[1], ck = coarse_row / size[1];
      for (int ci = 0; ci < size[0]; ++ci) coarse.active[coarse.index(ci, cj, ck)] = 0;
      for (int k = ck * ratio[2]; k < std::min((ck + 1) * ratio[2], fine.size[2]); ++k) {
        for (int j = cj * ratio[1]; j < std::min((cj + 1) * ratio[1], fine.size[1]); ++j) {
          for (int i = 0; i < fine.size[0]; ++i) {
            const std::size_t p = fine.index(i, j, k);
            const std::array<int, 3> at{i, j, k};
            const std::size_t c = coarse.index(i / ratio[0], cj, ck);
            coarse.mass[c] += fine.mass[p];
            if (fine.active[p]) coarse.active[c] = 1;
            for (int a = 0; a < 3; ++a) {
              // A conductance through A_c/h_c = (Σ A_f)/(r h_f): the sum of the fine ones over r.
              const double scale = 1.0 / ratio[a];
              coarse.boundary[a][c] += scale * fine.boundary[a][p];
              if (at[a] % ratio[a] == 0) coarse.conductance[a][c] += scale * fine.conductance[a][p];
            }
          }
        }
      }
    }
    fine_level.ratio = ratio;
    return true;
  }

  void factor_coarsest(Level& level) const {
    const StencilSystem& s = level.system;
    level.direct = false;
    level.dense_to_cell.clear();
    for (std::size_t p = 0; p < s.count(); ++p) {
      if (s.active[p]) level.dense_to_cell.push_back(p);
    }
    const std::size_t m = level.dense_to_cell.size();
    if (m == 0 || m > kDirectSolveLimit) return;
    std::vector<std::ptrdiff_t> cell_to_dense(s.count(), -1);
    for (std::size_t d = 0; d < m; ++d)
      cell_to_dense[level.dense_to_cell[d]] = static_cast<std::ptrdiff_t>(d);
    std::vector<double> a(m * m, 0.0);
    for (int k = 0; k < s.size[2]; ++k) {
      for (int j = 0; j < s.size[1]; ++j) {
        for (int i = 0; i < s.size[0]; ++i) {
          const std::size_t p = s.index(i, j, k);
          const std::ptrdiff_t row = cell_to_dense[p];
          if (row < 0) continue;
          const std::array<int, 3> at{i, j, k};
          a[static_cast<std::size_t>(row) * m + static_cast<std::size_t>(row)] += level.diagonal[p];
          for (int axis = 0; axis < 3; ++axis) {
            for (int side = -1; side <= 1; side += 2) {
              const std::ptrdiff_t q = neighbour(s, at, axis, side, p);
              if (q < 0) continue;
              const std::ptrdiff_t column = cell_to_dense[static_cast<std::size_t>(q)];
              if (column < 0) continue;
              a[static_cast<std::size_t>(row) * m + static_cast<std::size_t>(column)] -=
                  coupling(s, axis, side, p, q);
            }
          }
        }
      }
    }
    if (singular_) {
      // Pin the first unknown: the constant null space is removed by the caller.
      for (std::size_t d = 0; d < m; ++d) a[d] = a[d * m] = 0.0;
      a[0] = 1.0;
    }
    // In-place Cholesky, A = L Lᵀ (lower triangle kept).
    for (std::size_t c = 0; c < m; ++c) {
      double pivot = a[c * m + c];
      for (std::size_t t = 0; t < c; ++t) pivot -= a[c * m + t] * a[c * m + t];
      if (!(pivot > 1e-14 * std::abs(a[c * m + c]) && pivot > 0.0)) return;  // fall back to sweeps
      pivot = std::sqrt(pivot);
      a[c * m + c] = pivot;
      for (std::size_t r = c + 1; r < m; ++r) {
        double value = a[r * m + c];
        for (std::size_t t = 0; t < c; ++t) value -= a[r * m + t] * a[c * m + t];
        a[r * m + c] = value / pivot;
      }
    }
    level.cholesky = std::move(a);
    level.direct = true;
  }

  // y = A x on the active unknowns (0 on the held ones); returns Σ x·y summed per row and the
  // rows in order (as row_sum).
  double apply_dot(const Level& level, const std::vector<double>& x, std::vector<double>& y) const {
    const StencilSystem& s = level.system;
    return sum_over_rows(s, [&](int row) {
      const RowStencil r = row_stencil(level, row % s.size[1], row / s.size[1], zeros_.data());
      double sum = 0.0;
      for (int i = 0; i < s.size[0]; ++i) {
        const std::size_t p = r.start + static_cast<std::size_t>(i);
        y[p] = s.active[p] ? level.diagonal[p] * x[p] - neighbour_sum(r, x.data(), i) : 0.0;
        sum += x[p] * y[p];
      }
      return sum;
    });
  }

  // One grid row (j, k) of a Gauss-Seidel half sweep over the unknowns of colour
  // (i + j + k) mod 2.
  void smooth_row(Level& level, int j, int k, int colour) const {
    const StencilSystem& s = level.system;
    const RowStencil r = row_stencil(level, j, k, zeros_.data());
    double* x = level.solution.data();
    for (int i = (j + k + colour) % 2; i < s.size[0]; i += 2) {
      const std::size_t p = r.start + static_cast<std::size_t>(i);
      if (!s.active[p]) continue;
      x[p] = (level.rhs[p] + neighbour_sum(r, x, i)) / level.diagonal[p];
    }
  }

  // One Gauss-Seidel half sweep over the unknowns of colour (i + j + k) mod 2.
  void smooth_colour(Level& level, int colour) const {
    const StencilSystem& s = level.system;
    const int ny = s.size[1], rows = ny * s.size[2];
    const int team = level.colours_independent ? threading_.team(s.count()) : 1;
#pragma omp parallel for schedule(static) num_threads(team)
    for (int row = 0; row < rows; ++row) smooth_row(level, row % ny, row / ny, colour);
  }

  // `stages` Gauss-Seidel half sweeps of alternating colours, the first of colour `first`.
  void smooth_sweeps(Level& level, int first, int stages) const {
    for (int stage = 0; stage < stages; ++stage) smooth_colour(level, (first + stage) % 2);
  }

  void solve_coarsest(Level& level) const {
    std::fill(level.solution.begin(), level.solution.end(), 0.0);
    if (!level.direct) {
      smooth_sweeps(level, 0, 2 * kCoarsestSweeps);
      smooth_sweeps(level, 1, 2 * kCoarsestSweeps);
      return;
    }
    const std::size_t m = level.dense_to_cell.size();
    std::vector<double> y(m);
    for (std::size_t d = 0; d < m; ++d) y[d] = level.rhs[level.dense_to_cell[d]];
    if (singular_) y[0] = 0.0;
    const std::vector<double>& l = level.cholesky;
    for (std::size_t r = 0; r < m; ++r) {
      double value = y[r];
      for (std::size_t t = 0; t < r; ++t) value -= l[r * m + t] * y[t];
      y[r] = value / l[r * m + r];
    }
    for (std::size_t r = m; r-- > 0;) {
      double value = y[r];
      for (std::size_t t = r + 1; t < m; ++t) value -= l[t * m + r] * y[t];
      y[r] = value / l[r * m + r];
    }
    for (std::size_t d = 0; d < m; ++d) level.solution[level.dense_to_cell[d]] = y[d];
  }

  // x_l = V-cycle(b_l) from x_l = 0: symmetric (pre-smoothing red, black; post-smoothing black,
  // red; restriction the transpose of the piecewise-constant prolongation).
  void v_cycle(std::size_t l) {
    Level& level = levels_[l];
    if (l + 1 == levels_.size()) {
      solve_coarsest(level);
      return;
    }
    std::fill(level.solution.begin(), level.solution.end(), 0.0);
    smooth_sweeps(level, 0, 2 * kSmoothingSweeps);  // red, black, ...
    restrict_residual(level, levels_[l + 1]);
    v_cycle(l + 1);
    const StencilSystem& s = level.system;
    const Level& coarse = levels_[l + 1];
    const StencilSystem& cs = coarse.system;
    const int nx = s.size[0], ny = s.size[1], nz = s.size[2];
    const int rows = ny * nz;
    const int team = threading_.team(s.count());
    const std::array<int, 3> shift = ratio_shifts(level.ratio);
    double* x = level.solution.data();
    const double* correction = coarse.solution.data();
#pragma omp parallel for schedule(static) num_threads(team)
    for (int row = 0; row < rows; ++row) {
      const int j = row % ny, k = row / ny;
      const std::size_t start = s.index(0, j, k);
      const double* coarse_row = correction + cs.index(0, j >> shift[1], k >> shift[2]);
      for (int i = 0; i < nx; ++i) {
        if (s.active[start + static_cast<std::size_t>(i)])
          x[start + static_cast<std::size_t>(i)] += coarse_row[i >> shift[0]];
      }
    }
    smooth_sweeps(level, 1, 2 * kSmoothingSweeps);  // black, red, ...: symmetric
  }

  // The coarse right-hand side: the fine residual b − A x summed over each aggregate, the
  // aggregate's fine unknowns in grid order (k, j, i) — the order the serial sum had.
  void restrict_residual(const Level& level, Level& coarse) const {
    const StencilSystem& s = level.system;
    const StencilSystem& cs = coarse.system;
    const std::array<int, 3>& ratio = level.ratio;
    const int shift = ratio_shifts(ratio)[0];
    const int coarse_rows = cs.size[1] * cs.size[2];
    const double* x = level.solution.data();
    const int team = threading_.team(s.count());
#pragma omp parallel for schedule(static) num_threads(team)
    for (int coarse_row = 0; coarse_row < coarse_rows; ++coarse_row) {
      const int cj = coarse_row % cs.size[1], ck = coarse_row / cs.size[1];
      double* sums = coarse.rhs.data() + cs.index(0, cj, ck);
      std::fill(sums, sums + cs.size[0], 0.0);
      for (int k = ck * ratio[2]; k < std::min((ck + 1) * ratio[2], s.size[2]); ++k) {
        for (int j = cj * ratio[1]; j < std::min((cj + 1) * ratio[1], s.size[1]); ++j) {
          const RowStencil r = row_stencil(level, j, k, zeros_.data());
          for (int i = 0; i < s.size[0]; ++i) {
            const std::size_t p = r.start + static_cast<std::size_t>(i);
            if (!s.active[p]) continue;
            const double a_x = level.diagonal[p] * x[p] - neighbour_sum(r, x, i);
            sums[i >> shift] += level.rhs[p] - a_x;
          }
        }
      }
    }
  }

  void precondition(std::vector<double>& r, std::vector<double>& z) {
    Level& fine = levels_[0];
    if (diagonal_only_) {
      const StencilSystem& s = fine.system;
      for_each(s.count(), [&](std::size_t p) { z[p] = s.active[p] ? r[p] / fine.diagonal[p] : 0.0; });
      return;
    }
    // The fine level works on r and leaves z in its solution: swapped in and out, not copied.
    // Held unknowns keep the 0 the cycle starts from (no sweep or correction touches them).
    std::swap(fine.rhs, r);
    v_cycle(0);
    std::swap(fine.rhs, r);
    std::swap(fine.solution, z);
    if (singular_) subtract_on_active(z, active_mean(z));
  }

  static bool same_system(const StencilSystem& a, const StencilSystem& b) {
    return a.size == b.size && a.periodic == b.periodic && a.conductance == b.conductance &&
           a.boundary == b.boundary && a.mass == b.mass && a.active == b.active;
  }

  Threading threading_;
  // Whether levels_[0].system is the operator as last given to set_system (prepare_level held
  // none of its unknowns): then an equal operator keeps the hierarchy.
  bool fine_is_input_ = false;
  std::vector<Level> levels_;
  bool singular_ = false;
  std::array<std::vector<double>, 6> work_;  // solve(): b, x, r, z, direction, q
  std::vector<double> zeros_;                // a row of zero links (missing neighbour rows)
  mutable std::vector<double> partial_;      // per-row partial sums of a reduction
  bool diagonal_only_ = false;  // Jacobi preconditioning (kDiagonalDominance), no hierarchy
};

}  // namespace

std::unique_ptr<PressureSolver> make_multigrid_cg_solver(const Threading& threading) {
  return std::make_unique<MultigridCgSolver>(threading);
}

}  // namespace quarry::cfd
