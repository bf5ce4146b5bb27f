// The pressure solve of the projection method behind a small interface, and Quarry's own
// backend: conjugate gradients preconditioned by one geometric multigrid V-cycle on the
// uniform grid (deterministic for any thread count, no MPI; docs/cfd.md "Pressure solver").
#pragma once

#include <memory>
#include <span>
#include <string_view>

#include "cfd/stencil_system.h"
#include "core/threading.h"

namespace quarry::cfd {

struct SolveReport {
  int iterations = 0;              // Krylov iterations (0: b was zero)
  double relative_residual = 0.0;  // ‖b − A x‖₂ / ‖b‖₂ at return (0 when b = 0)
  bool converged = false;
  // Singular systems only: the mean of b over active unknowns that was removed before solving
  // (a discrete compatibility defect; 0 for a consistent right-hand side up to round-off).
  double removed_mean = 0.0;
};

class PressureSolver {
 public:
  virtual ~PressureSolver() = default;
  virtual std::string_view name() const = 0;
  // Takes the operator; call again whenever a coefficient changes. Cost O(unknowns) (the
  // multigrid backend keeps its hierarchy when the operator equals the previous one).
  virtual void set_system(const StencilSystem& system) = 0;
  // set_system without the copy: the coefficient arrays may be swapped with the solver's own,
  // so that `system` comes back with the sizes, periodicity and active flags it had and
  // coefficients of no use (reset it before filling it again).
  virtual void take_system(StencilSystem& system) { set_system(system); }
  // The team of the following calls (results do not depend on it).
  virtual void set_threading(const Threading& threading) = 0;
  // Solves A x = b to ‖b − A x‖₂ ≤ relative_tolerance ‖b‖₂, starting from x as given. b and x
  // have system.count() entries; inactive entries of x are set to b. For a singular system the
  // mean of b over active unknowns is removed first and x is returned with zero mean.
  // Does not throw on non-convergence: the report says so and the caller decides.
  virtual SolveReport solve(std::span<const double> rhs, std::span<double> solution,
                            double relative_tolerance, int max_iterations) = 0;
};

// Conjugate gradients with a symmetric multigrid V-cycle preconditioner: cell-centred
// aggregation (2 per axis along the strongly coupled axes: semi-coarsening as in PFMG, so
// anisotropic cells keep few iterations), coarse conductances the sum of the fine ones
// through a coarse face divided by the coarsening ratio along the axis, symmetric red-black
// Gauss-Seidel (2 sweeps before, 2 after), a dense Cholesky solve on the coarsest level.
// Reductions are summed per grid row and the rows in order: the same bits for any team.
std::unique_ptr<PressureSolver> make_multigrid_cg_solver(const Threading& threading);

}  // namespace quarry::cfd
