// Volume-averaged incompressible Navier-Stokes on a uniform staggered (MAC) grid: incremental
// pressure-correction projection (Goda 1979; van Kan 1986) with implicit viscosity and implicit
// drag, in the form of Zhou, Kuang, Chu & Yu 2010 (J. Fluid Mech. 661:482-510) model A (default)
// or model B. With ε ≡ 1 and β ≡ 0 it is plain Navier-Stokes. docs/cfd.md "Fluid solver".
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <vector>

#include "cfd/fluid_grid.h"
#include "cfd/pressure_solver.h"
#include "cfd/stencil_system.h"
#include "core/threading.h"
#include "core/vec3.h"

namespace quarry::cfd {

// Model A: ρ(∂(εu)/∂t + ∇·(εuu)) = −ε∇p + ∇·(εμ∇u) − β u + f + ερg
// Model B: ρ(∂(εu)/∂t + ∇·(εuu)) = −∇p  + ∇·(εμ∇u) − β u + f + ερg
// with ∂ε/∂t + ∇·(εu) = 0 in both. u is the interstitial fluid velocity, β (kg/(m³·s)) the
// implicit part of the particle-fluid exchange per unit volume, f (N/m³) its explicit part (a
// caller coupling particles puts β v̄_p there, plus any other force density).
enum class VolumeAveragedModel { a, b };

// The explicit advection of the momentum predictor (docs/cfd.md "Discretisation", "Time step").
// central: second order; stable only while the implicit viscosity and drag damp it (cell
// Péclet number |u|Δx/ν ≲ 2, or a strong drag). hybrid (Spalding 1972; Patankar 1980 §5.2.6):
// central where a face's Péclet number is ≤ 2, beyond it first-order upwind with the physical
// viscosity's share taken back, so that the face diffuses max(ν, |u|Δx/2); stable up to the
// CFL limit whatever the viscosity and drag, first order where it upwinds. Identical bits to
// central where every face's Péclet number is ≤ 2.
enum class Advection { central, hybrid };

struct FluidSolverOptions {
  VolumeAveragedModel model = VolumeAveragedModel::a;
  Advection advection = Advection::central;
  Vec3 gravity;                       // g (m/s²)
  double pressure_tolerance = 1e-10;  // relative residual of the pressure solve
  double velocity_tolerance = 1e-10;  // relative residual of the implicit momentum solves
  int max_iterations = 500;           // per linear solve
  Threading threading;
};

// What the last step did; iteration counts and residuals of its linear solves.
struct FluidStepReport {
  SolveReport pressure;
  std::array<SolveReport, 3> momentum;
  double predicted_divergence = 0.0;  // max |∇·(εu*) + ∂ε/∂t| before the projection (1/s)
  double divergence = 0.0;            // the same after it (1/s)
};

// Everything a step reads that earlier steps or calls wrote, beyond what the constructor is
// given: a checkpoint stores it, and after set_state the next step is bit-identical to the one
// the solver it came from would take. Cell arrays are in the solver's own layout (each with two
// ghost layers on every side, ghosts included), the inputs per cell (FluidGrid::cell_index):
// callers keep and give back, they do not interpret. (What a step rebuilds from these — the
// linear systems, the multigrid hierarchies, u* and φ — is not part of it.)
struct FluidSolverState {
  std::array<std::vector<double>, 3> velocity;  // u at faces (m/s), padded
  std::vector<double> pressure;                 // p (Pa), padded
  // ε of the last step (the ∂ε/∂t of the next) and ε set for the next step, padded.
  std::vector<double> void_fraction_old, void_fraction_new;
  std::vector<double> drag_coefficient;         // β input (kg/(m³·s)), per cell
  std::vector<Vec3> force_density;              // f input (N/m³), per cell
  std::vector<std::uint8_t> blocked;            // per cell, 0 or 1
  bool void_fraction_started = false;           // ε was set (else the first set is also the old)
  long long steps = 0;                          // steps taken (messages)
  FluidStepReport last_report;                  // of the last step (divergence_norm, last_report)
};

class FluidSolver {
 public:
  // Checks the grid (cells ≥ 1, sizes > 0), the properties (> 0) and that periodic faces come
  // in pairs: std::invalid_argument otherwise. Starts with u = 0, ε = 1, β = 0, f = 0, no
  // blocked cell, and p hydrostatic from the first pressure outlet (p = 0 without one).
  // `pressure_solver` defaults to make_multigrid_cg_solver.
  FluidSolver(const FluidGrid& grid, const FluidProperties& properties,
              const FluidBoundaries& boundaries, const FluidSolverOptions& options = {},
              std::unique_ptr<PressureSolver> pressure_solver = nullptr);

  // Advances the fluid by dt (s) > 0 with the inputs as they are set now. After it the face
  // velocities satisfy ∇·(εu) + ∂ε/∂t = 0 to the pressure tolerance; the void fraction set for
  // this step becomes the old one of the next. Cost: a few multigrid-CG solves of the cell count.
  // Throws PhysicsError (the state is then that of the failed step) when a linear solve
  // does not converge or the velocity is no longer finite, with the values and a hint.
  void step(double dt);
  // The team of the next steps' loops and linear solves (the run loop's thread governor
  // changes it between steps on a busy machine). Results do not depend on it.
  void set_threading(const Threading& threading);

  // --- inputs, per cell (flat, FluidGrid::cell_index order) ---
  // ε at the end of the next step, in (0, 1]. The first call before any step sets the old
  // value too (no ∂ε/∂t in the first step); set_initial_void_fraction does so at any time.
  void set_void_fraction(std::span<const double> void_fraction);
  void set_initial_void_fraction(std::span<const double> void_fraction);
  std::span<double> drag_coefficient();  // β ≥ 0 (kg/(m³·s))
  std::span<Vec3> force_density();       // f (N/m³)
  // Blocked cells hold no fluid (u = 0 on their faces, inlet faces included; no flux through
  // them); 1 = blocked. A change takes effect from the next step.
  std::span<std::uint8_t> blocked();
  // The inputs as set (read-only).
  std::span<const double> drag_coefficient() const { return drag_input_; }
  std::span<const Vec3> force_density() const { return force_input_; }
  std::span<const std::uint8_t> blocked() const { return blocked_input_; }
  // Initial or imposed state: each face's normal velocity from velocity(x) at its centre;
  // pressure from pressure(x) at cell centres. Boundary values are re-applied afterwards.
  void set_velocity(const std::function<Vec3(const Vec3&)>& velocity);
  void set_pressure(const std::function<double(const Vec3&)>& pressure);

  // --- results ---
  Vec3 cell_velocity(int i, int j, int k) const;  // average of the two faces per axis (m/s)
  double pressure(int i, int j, int k) const;     // Pa
  // Velocity component `axis` on the face at the low side of cell (i, j, k) along it;
  // i (for axis 0) may be cells[0] for the high boundary face.
  double face_velocity(int axis, int i, int j, int k) const;
  // max over fluid cells of |∇·(εu) + ∂ε/∂t| of the last step (1/s).
  double divergence_norm() const { return report_.divergence; }
  // Largest dt for the explicit advection (forward Euler): the CFL limit 1/Σ_a(max|u_a|/Δx_a);
  // for central advection also, in every fluid cell, the step up to which the implicit
  // viscosity and drag damp every Fourier mode (without drag 2ν/Σ_a u_a², ν = μ/ρ; with
  // β/(ρε) ≫ |u|/Δx no limit; docs/cfd.md "Time step"). Hybrid advection needs only the CFL
  // limit. +∞ at rest. Callers use a fraction of it (0.5 recommended). Cost: O(cells).
  double stable_time_step() const;
  const FluidStepReport& last_report() const { return report_; }
  const FluidGrid& grid() const { return grid_; }

  // --- checkpoints ---
  // The state between steps (a copy). Cost: O(cells).
  FluidSolverState state() const;
  // Takes a state from state() of a solver built with the same grid, properties, boundaries and
  // options. Throws std::invalid_argument naming the field, the solver unchanged, for an array
  // whose size is not this grid's, a value that is not finite, ε outside (0, 1], β < 0, a
  // blocked flag other than 0 or 1, or a negative step count. Cost: O(cells).
  void set_state(FluidSolverState state);

 private:
  // The stages of step(), in order.
  void predict_momentum(double dt);
  void solve_pressure_correction(double dt);
  void correct_velocity(double dt);
  void update_boundaries();
  void measure_divergence(double dt);
  void check_step_health(double dt) const;

  // Helpers (fluid_solver_boundaries.cpp).
  void fill_cell_ghosts(std::vector<double>& field) const;
  template <class GhostValue>
  void fill_outlet_ghosts(std::vector<double>& field, GhostValue ghost_value);
  void fill_pressure_ghosts();
  void fill_correction_ghosts();
  void fill_velocity_ghosts(int axis);
  void apply_blocked_faces();  // u = 0 on every face of a blocked cell, then the velocity ghosts
  double boundary_pressure(int axis, int side, int i, int j, int k) const;
  double correction_coefficient(std::size_t face_low_cell, std::size_t face_high_cell,
                                double dt) const;
  double continuity_residual(std::size_t cell, const std::array<std::vector<double>, 3>& velocity,
                             double dt) const;
  void momentum_unknown_range(int axis, int& first, int& last) const;

  // Padded storage: kGhost layers of ghost cells on every side; cell (i, j, k) of the grid is
  // padded (i + kGhost, …). The face array of axis a holds at padded (I, J, K) the face at
  // the low side of padded cell (I, J, K) along a.
  static constexpr int kGhost = 2;
  std::size_t padded(int pi, int pj, int pk) const {
    return static_cast<std::size_t>(pi) +
           static_cast<std::size_t>(padded_size_[0]) *
               (static_cast<std::size_t>(pj) +
                static_cast<std::size_t>(padded_size_[1]) * static_cast<std::size_t>(pk));
  }

  FluidGrid grid_;
  FluidProperties properties_;
  FluidBoundaries boundaries_;
  FluidSolverOptions options_;
  std::unique_ptr<PressureSolver> pressure_solver_;
  std::array<int, 3> padded_size_{};
  std::array<std::ptrdiff_t, 3> stride_{};
  bool void_fraction_started_ = false;
  long long step_count_ = 0;  // steps taken, for messages

  // Inputs (flat, unpadded) and their padded copies.
  std::vector<double> drag_input_;
  std::vector<Vec3> force_input_;
  std::vector<std::uint8_t> blocked_input_;
  std::vector<double> void_fraction_old_, void_fraction_new_, drag_;
  std::array<std::vector<double>, 3> force_;
  std::vector<double> blocked_;  // 1.0 where blocked (padded copy of blocked_input_)

  // State (padded).
  std::array<std::vector<double>, 3> velocity_;   // u at faces (m/s)
  std::array<std::vector<double>, 3> predicted_;  // u* at faces
  // ε^n u^n at faces (m/s), ε^n the mean of the two cells: the advective mass fluxes of the
  // momentum predictor, each read by twelve faces' fluxes (scratch of predict_momentum).
  std::array<std::vector<double>, 3> mass_flux_old_;
  std::vector<double> pressure_;                  // p at cells (Pa)
  std::vector<double> correction_;                // φ = p^{n+1} − p^n (Pa)

  // Linear systems and their solvers (one per momentum component: each keeps its hierarchy).
  StencilSystem pressure_system_;
  std::array<StencilSystem, 3> momentum_system_;
  std::array<std::unique_ptr<PressureSolver>, 3> momentum_solver_;
  std::vector<double> rhs_, unknowns_;
  FluidStepReport report_;
};

}  // namespace quarry::cfd
