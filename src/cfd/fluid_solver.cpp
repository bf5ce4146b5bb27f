// The fluid solver's step: momentum predictor (implicit viscosity and drag, explicit central
// advection), pressure solve for the increment φ, velocity correction, boundary update
// (incremental pressure-correction projection; Goda 1979, van Kan 1986, on the MAC grid of
// Harlow & Welch 1965). Equations in fluid_solver.h and docs/cfd.md.
#include "cfd/fluid_solver.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>

#include "core/diagnostics.h"

namespace quarry::cfd {

namespace {

bool is_periodic(const FluidBoundaries& boundaries, int axis) {
  return boundaries.face(axis, 0).kind == BoundaryKind::periodic;
}

void check_construction(const FluidGrid& grid, const FluidProperties& properties,
                        const FluidBoundaries& boundaries, const FluidSolverOptions& options) {
  for (int a = 0; a < 3; ++a) {
    if (grid.cells[a] < 1) {
      throw std::invalid_argument(
          fmt::format("fluid grid: cells[{}] must be ≥ 1, got {}", a, grid.cells[a]));
    }
    if (!(grid.cell_size[a] > 0.0) || !std::isfinite(grid.cell_size[a])) {
      throw std::invalid_argument(
          fmt::format("fluid grid: cell_size[{}] must be > 0 (m), got {}", a, grid.cell_size[a]));
    }
    const bool low = boundaries.face(a, 0).kind == BoundaryKind::periodic;
    const bool high = boundaries.face(a, 1).kind == BoundaryKind::periodic;
    if (low != high) {
      throw std::invalid_argument(fmt::format(
          "fluid boundaries: axis {} is periodic on one face only; both or neither", a));
    }
  }
  if (!(properties.density > 0.0) || !std::isfinite(properties.density)) {
    throw std::invalid_argument(
        fmt::format("fluid: density must be > 0 (kg/m³), got {}", properties.density));
  }
  if (!(properties.viscosity > 0.0) || !std::isfinite(properties.viscosity)) {
    throw std::invalid_argument(
        fmt::format("fluid: viscosity must be > 0 (Pa·s), got {}", properties.viscosity));
  }
  if (!(options.pressure_tolerance > 0.0) || !(options.velocity_tolerance > 0.0) ||
      options.max_iterations < 1) {
    throw std::invalid_argument("fluid solver: tolerances must be > 0 and max_iterations ≥ 1");
  }
}

}  // namespace

FluidSolver::FluidSolver(const FluidGrid& grid, const FluidProperties& properties,
                         const FluidBoundaries& boundaries, const FluidSolverOptions& options,
                         std::unique_ptr<PressureSolver> pressure_solver)
    : grid_(grid),
      properties_(properties),
      boundaries_(boundaries),
      options_(options),
      pressure_solver_(std::move(pressure_solver)) {
  check_construction(grid, properties, boundaries, options);
  if (!pressure_solver_) pressure_solver_ = make_multigrid_cg_solver(options_.threading);
  for (auto& solver : momentum_solver_) solver = make_multigrid_cg_solver(options_.threading);
  for (int a = 0; a < 3; ++a) padded_size_[a] = grid_.cells[a] + 2 * kGhost;
  stride_ = {1, padded_size_[0], std::ptrdiff_t{padded_size_[0]} * padded_size_[1]};
  const std::size_t padded_count = static_cast<std::size_t>(padded_size_[0]) *
                                   static_cast<std::size_t>(padded_size_[1]) *
                                   static_cast<std::size_t>(padded_size_[2]);
  const std::size_t cells = grid_.cell_count();
  drag_input_.assign(cells, 0.0);
  force_input_.assign(cells, Vec3{});
  blocked_input_.assign(cells, 0);
  void_fraction_old_.assign(padded_count, 1.0);
  void_fraction_new_.assign(padded_count, 1.0);
  drag_.assign(padded_count, 0.0);
  blocked_.assign(padded_count, 0.0);
  pressure_.assign(padded_count, 0.0);
  correction_.assign(padded_count, 0.0);
  for (int a = 0; a < 3; ++a) {
    force_[a].assign(padded_count, 0.0);
    velocity_[a].assign(padded_count, 0.0);
    predicted_[a].assign(padded_count, 0.0);
  }
  for (const FaceBoundary& face : boundaries_.faces) {
    if (face.kind != BoundaryKind::pressure_outlet) continue;
    // Hydrostatic start: p = p_ref + ρ g·(x − x_ref) from the first outlet.
    set_pressure([&](const Vec3& x) {
      return face.reference_pressure +
             properties_.density * dot(options_.gravity, x - face.reference_point);
    });
    break;
  }
  update_boundaries();
}

// ---------------------------------------------------------------------------------------------
// One step: the stages in order.

void FluidSolver::step(double dt) {
  if (!(dt > 0.0) || !std::isfinite(dt)) {
    throw std::invalid_argument(fmt::format("fluid solver: dt must be > 0 (s), got {}", dt));
  }
  // Inputs of this step: β, f and the blocked mask into the padded fields, with ghosts.
  bool blocked_changed = false;
  const int team = options_.threading.team(grid_.cell_count());
#pragma omp parallel for schedule(static) num_threads(team) reduction(|| : blocked_changed)
  for (int k = 0; k < grid_.cells[2]; ++k) {
    for (int j = 0; j < grid_.cells[1]; ++j) {
      for (int i = 0; i < grid_.cells[0]; ++i) {
        const std::size_t c = grid_.cell_index(i, j, k);
        const std::size_t p = padded(i + kGhost, j + kGhost, k + kGhost);
        drag_[p] = drag_input_[c];
        const double blocked = blocked_input_[c] ? 1.0 : 0.0;
        blocked_changed |= blocked_[p] != blocked;
        blocked_[p] = blocked;
        for (int a = 0; a < 3; ++a) force_[a][p] = force_input_[c][a];
      }
    }
  }
  fill_cell_ghosts(drag_);
  fill_cell_ghosts(blocked_);
  if (blocked_changed) apply_blocked_faces();  // u = 0 on newly blocked faces from this step on
  for (auto& component : force_) fill_cell_ghosts(component);
  fill_cell_ghosts(void_fraction_new_);
  fill_cell_ghosts(void_fraction_old_);
  // Inlet faces hold U/ε^{n+1} (superficial inlets): set with this step's void fraction.
  for (int a = 0; a < 3; ++a)
    if (boundaries_.face(a, 0).kind == BoundaryKind::velocity_inlet ||
        boundaries_.face(a, 1).kind == BoundaryKind::velocity_inlet)
      fill_velocity_ghosts(a);

  ++step_count_;
  predict_momentum(dt);           // u*: momentum with p^n, implicit viscosity and drag
  solve_pressure_correction(dt);  // φ: ∇·(ε a ∇φ) = ∇·(εu*) + ∂ε/∂t
  correct_velocity(dt);           // u^{n+1} = u* − a ∇φ, p^{n+1} = p^n + φ
  update_boundaries();            // ghost layers of u and p for the next step
  measure_divergence(dt);
  check_step_health(dt);

  void_fraction_old_ = void_fraction_new_;
  void_fraction_started_ = true;
}

void FluidSolver::set_threading(const Threading& threading) {
  options_.threading = threading;
  pressure_solver_->set_threading(threading);
  for (auto& solver : momentum_solver_) solver->set_threading(threading);
}

// Unknown faces of component `axis` along its own axis (padded indices, inclusive): the
// boundary faces of walls and inlets are known; an outlet's is an unknown; a periodic axis
// has n faces (the one at the high boundary repeats the first).
void FluidSolver::momentum_unknown_range(int axis, int& first, int& last) const {
  const BoundaryKind low = boundaries_.face(axis, 0).kind;
  const BoundaryKind high = boundaries_.face(axis, 1).kind;
  const int n = grid_.cells[axis];
  first =
      (low == BoundaryKind::pressure_outlet || low == BoundaryKind::periodic) ? kGhost : kGhost + 1;
  last = high == BoundaryKind::pressure_outlet ? n + kGhost : n + kGhost - 1;
}

// Momentum predictor, per component a at its faces, volume-integrated (V = ΔxΔyΔz):
// [ρ ε^{n+1}/dt + β] u* − ∇·(ε^{n+1} μ ∇u*) = ρ ε^n u^n/dt − ρ ∇·(ε^n u^n u^n)
//                                              − (ε^{n+1} | 1) ∂p^n/∂x_a + f_a + ε^{n+1} ρ g_a
// (model A | B). Advection: central (second order) or hybrid (options_.advection), flux form,
// the mass flux εu averaged to the momentum cell's faces. Viscous fluxes: ε at the cell centre
// (normal) or the edge average of four cells (tangential); walls and inlets as Dirichlet values
// at the face.
void FluidSolver::predict_momentum(double dt) {
  const double rho = properties_.density;
  const double mu = properties_.viscosity;
  const double volume = grid_.cell_volume();
  const Vec3& h = grid_.cell_size;
  const bool model_a = options_.model == VolumeAveragedModel::a;
  const double nu = mu / rho;  // m²/s
  const bool hybrid = options_.advection == Advection::hybrid;
  // Hybrid advection takes (|εu|/2 − νε/Δx)⁺ (high − low) (m²/s²) off the central momentum
  // flux through a face of mass flux εu (m/s) between the values `low` and `high` (m/s)
  // (`conductance` = νε/Δx, m/s): where the face's Péclet number exceeds 2 the face then
  // diffuses |εu|Δx/2 in all, the physical viscosity included (implicit below), and carries
  // the upwind value; elsewhere it takes 0, central's bits. Central advection does not compute
  // the conductances at all (they are 12 more reads of ε per face).
  const auto upwinding = [](double mass_flux, double low, double high, double conductance) {
    const double excess = 0.5 * std::abs(mass_flux) - conductance;
    return excess > 0.0 ? excess * (high - low) : 0.0;
  };
  const std::vector<double>& eps_old = void_fraction_old_;
  const std::vector<double>& eps = void_fraction_new_;
  auto face_eps_old = [&](int b, std::size_t face) {
    return 0.5 * (eps_old[face - stride_[b]] + eps_old[face]);
  };
  // ε^n u^n at every face, once: the advective fluxes below read each one twelve times. (The
  // same products as the fluxes formed them; the lowest stride of indices has no low cell and
  // is never read.) The team is the cells' as in the other loops, not the padded field's: a
  // 4 x 4 x 40 bed's 2,816 padded values passed the threshold, and its second thread, woken
  // three times a fluid step for a microsecond of products, spun on its core in between.
  const int flux_team = options_.threading.team(grid_.cell_count());
  for (int b = 0; b < 3; ++b) {
    std::vector<double>& flux = mass_flux_old_[b];
    const std::vector<double>& v = velocity_[b];
    flux.resize(eps_old.size());
    const auto first = static_cast<std::ptrdiff_t>(stride_[b]);
    const auto end = static_cast<std::ptrdiff_t>(flux.size());
#pragma omp parallel for schedule(static) num_threads(flux_team)
    for (std::ptrdiff_t face = first; face < end; ++face)
      flux[face] = face_eps_old(b, static_cast<std::size_t>(face)) * v[face];
  }

  for (int a = 0; a < 3; ++a) {
    const std::vector<double>& u = velocity_[a];
    const std::ptrdiff_t sa = stride_[a];
    int first = 0, last = 0;
    momentum_unknown_range(a, first, last);
    std::array<int, 3> size = grid_.cells;
    size[a] = last - first + 1;
    StencilSystem& system = momentum_system_[a];
    system.reset(size, {is_periodic(boundaries_, 0), is_periodic(boundaries_, 1),
                        is_periodic(boundaries_, 2)});
    rhs_.assign(system.count(), 0.0);
    unknowns_.assign(system.count(), 0.0);
    predicted_[a] = velocity_[a];
    if (size[a] <= 0) continue;
    const int rows = size[1] * size[2];
    const int team = options_.threading.team(system.count());
#pragma omp parallel for schedule(static) num_threads(team)
    for (int row = 0; row < rows; ++row) {
      const std::array<int, 3> row_at{0, row % size[1], row / size[1]};
      for (int bi = 0; bi < size[0]; ++bi) {
        const std::array<int, 3> box{bi, row_at[1], row_at[2]};
        std::array<int, 3> pad{box[0] + kGhost, box[1] + kGhost, box[2] + kGhost};
        pad[a] = box[a] + first;
        const std::size_t q = system.index(box[0], box[1], box[2]);
        const std::size_t face = padded(pad[0], pad[1], pad[2]);
        const std::size_t cell_high = face, cell_low = face - sa;
        if (blocked_[cell_low] > 0.0 || blocked_[cell_high] > 0.0) {
          system.active[q] = 0;
          continue;
        }
        const double eps_face = 0.5 * (eps[cell_low] + eps[cell_high]);
        const double beta_face = 0.5 * (drag_[cell_low] + drag_[cell_high]);
        const double force_face = 0.5 * (force_[a][cell_low] + force_[a][cell_high]);

        // −∇·(ε^n u u) at this face (per unit volume): central, or hybrid with the diffusion
        // beyond the physical one, (|εu|/2 − νε/Δx)⁺ (u_high − u_low), that makes it upwind.
        double advection = 0.0;
        for (int b = 0; b < 3; ++b) {
          const std::ptrdiff_t sb = stride_[b];
          double flux_high = 0.0, flux_low = 0.0;
          const std::vector<double>& m = mass_flux_old_[b];
          if (b == a) {
            const double m_high = 0.5 * (m[face] + m[face + sa]), m_low = 0.5 * (m[face - sa] + m[face]);
            flux_high = m_high * 0.5 * (u[face] + u[face + sa]);
            flux_low = m_low * 0.5 * (u[face - sa] + u[face]);
            if (hybrid) {
              flux_high -= upwinding(m_high, u[face], u[face + sa], nu * eps[cell_high] / h[b]);
              flux_low -= upwinding(m_low, u[face - sa], u[face], nu * eps[cell_low] / h[b]);
            }
          } else {
            const std::size_t low_up = cell_low + sb, high_up = cell_high + sb;
            const double m_high = 0.5 * (m[low_up] + m[high_up]), m_low = 0.5 * (m[cell_low] + m[cell_high]);
            flux_high = m_high * 0.5 * (u[face] + u[face + sb]);
            flux_low = m_low * 0.5 * (u[face - sb] + u[face]);
            if (hybrid) {
              const double edge_high = 0.25 * (eps[cell_low] + eps[cell_high] + eps[low_up] + eps[high_up]);
              const double edge_low =
                  0.25 * (eps[cell_low] + eps[cell_high] + eps[cell_low - sb] + eps[cell_high - sb]);
              flux_high -= upwinding(m_high, u[face], u[face + sb], nu * edge_high / h[b]);
              flux_low -= upwinding(m_low, u[face - sb], u[face], nu * edge_low / h[b]);
            }
          }
          advection += (flux_high - flux_low) / h[b];
        }
        const double pressure_gradient = (pressure_[cell_high] - pressure_[cell_low]) / h[a];
        const double pressure_factor = model_a ? eps_face : 1.0;
        double rhs = (rho * face_eps_old(a, face) * u[face] / dt - rho * advection -
                      pressure_factor * pressure_gradient + force_face +
                      eps_face * rho * options_.gravity[a]) *
                     volume;
        system.mass[q] = (rho * eps_face / dt + beta_face) * volume;

        // Viscous couplings, μ ε A/h = μ ε V/h².
        for (int e = 0; e < 3; ++e) {
          const std::ptrdiff_t se = stride_[e];
          const bool periodic = is_periodic(boundaries_, e);
          const double coefficient = mu * volume / (h[e] * h[e]);
          if (e == a) {
            const double low = coefficient * eps[cell_low];
            if (box[a] > 0 || periodic) {
              system.conductance[a][q] = low;
            } else if (first == kGhost + 1) {  // the boundary face below is a known value
              system.boundary[a][q] += low;
              rhs += low * u[face - sa];
            }
            if (box[a] == size[a] - 1 && !periodic &&
                boundaries_.face(a, 1).kind != BoundaryKind::pressure_outlet) {
              const double high = coefficient * eps[cell_high];
              system.boundary[a][q] += high;
              rhs += high * u[face + sa];
            }
            continue;
          }
          const double low =
              coefficient * 0.25 *
              (eps[cell_low] + eps[cell_high] + eps[cell_low - se] + eps[cell_high - se]);
          if (box[e] > 0 || periodic) {
            system.conductance[e][q] = low;
          } else {
            const FaceBoundary& wall = boundaries_.face(e, 0);
            if (wall.kind != BoundaryKind::pressure_outlet) {
              system.boundary[e][q] += 2.0 * low;
              rhs += 2.0 * low * wall.velocity[a];
            }
          }
          if (box[e] == size[e] - 1 && !periodic) {
            const FaceBoundary& wall = boundaries_.face(e, 1);
            if (wall.kind != BoundaryKind::pressure_outlet) {
              const double high =
                  coefficient * 0.25 *
                  (eps[cell_low] + eps[cell_high] + eps[cell_low + se] + eps[cell_high + se]);
              system.boundary[e][q] += 2.0 * high;
              rhs += 2.0 * high * wall.velocity[a];
            }
          }
        }
        rhs_[q] = rhs;
        unknowns_[q] = u[face];
      }
    }
    momentum_solver_[a]->take_system(system);  // system: its active flags still read below
    report_.momentum[a] = momentum_solver_[a]->solve(rhs_, unknowns_, options_.velocity_tolerance,
                                                     options_.max_iterations);
    std::vector<double>& star = predicted_[a];
#pragma omp parallel for schedule(static) num_threads(team)
    for (int row = 0; row < rows; ++row) {
      const int bj = row % size[1], bk = row / size[1];
      for (int bi = 0; bi < size[0]; ++bi) {
        std::array<int, 3> pad{bi + kGhost, bj + kGhost, bk + kGhost};
        pad[a] = (a == 0 ? bi : (a == 1 ? bj : bk)) + first;
        const std::size_t q = system.index(bi, bj, bk);
        star[padded(pad[0], pad[1], pad[2])] = system.active[q] ? unknowns_[q] : 0.0;
      }
    }
    if (is_periodic(boundaries_, a)) {
      // The face at the high boundary is the first face again: continuity reads both.
      const std::ptrdiff_t period = grid_.cells[a] * stride_[a];
      std::array<int, 3> high{grid_.cells[0] + kGhost, grid_.cells[1] + kGhost,
                              grid_.cells[2] + kGhost};
      high[a] = kGhost + 1;  // the plane of first faces only
      for (int k = kGhost; k < high[2]; ++k) {
        for (int j = kGhost; j < high[1]; ++j) {
          for (int i = kGhost; i < high[0]; ++i) {
            const std::size_t face = padded(i, j, k);
            star[face + static_cast<std::size_t>(period)] = star[face];
          }
        }
      }
    }
  }
}

// Face coefficient a of the correction u = u* − a ∇φ: from [ρ ε/dt + β](u − u*) = −(ε | 1) ∇φ,
// a = ε/(ρ ε/dt + β) (model A) or 1/(ρ ε/dt + β) (model B), at the face between the cells.
double FluidSolver::correction_coefficient(std::size_t low_cell, std::size_t high_cell,
                                           double dt) const {
  const double eps_face = 0.5 * (void_fraction_new_[low_cell] + void_fraction_new_[high_cell]);
  const double beta_face = 0.5 * (drag_[low_cell] + drag_[high_cell]);
  const double denominator = properties_.density * eps_face / dt + beta_face;
  return (options_.model == VolumeAveragedModel::a ? eps_face : 1.0) / denominator;
}

// ∇·(εu) + (ε^{n+1} − ε^n)/dt in one cell (1/s), ε^{n+1} on the faces.
double FluidSolver::continuity_residual(std::size_t cell,
                                        const std::array<std::vector<double>, 3>& velocity,
                                        double dt) const {
  const std::vector<double>& eps = void_fraction_new_;
  double residual = (eps[cell] - void_fraction_old_[cell]) / dt;
  for (int a = 0; a < 3; ++a) {
    const std::ptrdiff_t s = stride_[a];
    const double flux_high = 0.5 * (eps[cell] + eps[cell + s]) * velocity[a][cell + s];
    const double flux_low = 0.5 * (eps[cell - s] + eps[cell]) * velocity[a][cell];
    residual += (flux_high - flux_low) / grid_.cell_size[a];
  }
  return residual;
}

// Pressure increment, volume-integrated: −Σ_faces ε a A ∂φ/∂n = −V (∇·(εu*) + ∂ε/∂t), so that
// the corrected velocity satisfies the continuity equation. Outlets hold φ = 0 on the face;
// walls, inlets and blocked cells give ∂φ/∂n = 0.
void FluidSolver::solve_pressure_correction(double dt) {
  const double volume = grid_.cell_volume();
  const Vec3& h = grid_.cell_size;
  StencilSystem& system = pressure_system_;
  system.reset(grid_.cells, {is_periodic(boundaries_, 0), is_periodic(boundaries_, 1),
                             is_periodic(boundaries_, 2)});
  rhs_.assign(system.count(), 0.0);
  unknowns_.assign(system.count(), 0.0);
  const std::array<int, 3>& n = grid_.cells;
  const int rows = n[1] * n[2];
  const int team = options_.threading.team(system.count());
  std::vector<double> row_max(static_cast<std::size_t>(rows), 0.0);
#pragma omp parallel for schedule(static) num_threads(team)
  for (int row = 0; row < rows; ++row) {
    const int j = row % n[1], k = row / n[1];
    for (int i = 0; i < n[0]; ++i) {
      const std::array<int, 3> at{i, j, k};
      const std::size_t q = system.index(i, j, k);
      const std::size_t cell = padded(i + kGhost, j + kGhost, k + kGhost);
      if (blocked_[cell] > 0.0) {
        system.active[q] = 0;
        continue;
      }
      for (int a = 0; a < 3; ++a) {
        const std::ptrdiff_t s = stride_[a];
        const double area_over_h = volume / (h[a] * h[a]);
        const double eps_low = 0.5 * (void_fraction_new_[cell - s] + void_fraction_new_[cell]);
        const double low = eps_low * correction_coefficient(cell - s, cell, dt) * area_over_h;
        if (at[a] > 0 || is_periodic(boundaries_, a)) {
          if (blocked_[cell - s] == 0.0) system.conductance[a][q] = low;
        } else if (boundaries_.face(a, 0).kind == BoundaryKind::pressure_outlet) {
          system.boundary[a][q] += 2.0 * low;
        }
        if (at[a] == n[a] - 1 && boundaries_.face(a, 1).kind == BoundaryKind::pressure_outlet) {
          const double eps_high = 0.5 * (void_fraction_new_[cell] + void_fraction_new_[cell + s]);
          system.boundary[a][q] +=
              2.0 * eps_high * correction_coefficient(cell, cell + s, dt) * area_over_h;
        }
      }
      const double residual = continuity_residual(cell, predicted_, dt);
      rhs_[q] = -residual * volume;
      row_max[static_cast<std::size_t>(row)] =
          std::max(row_max[static_cast<std::size_t>(row)], std::abs(residual));
    }
  }
  report_.predicted_divergence = *std::max_element(row_max.begin(), row_max.end());
  pressure_solver_->take_system(system);  // system: its active flags still read below
  report_.pressure = pressure_solver_->solve(rhs_, unknowns_, options_.pressure_tolerance,
                                             options_.max_iterations);
  std::fill(correction_.begin(), correction_.end(), 0.0);
#pragma omp parallel for schedule(static) num_threads(team)
  for (int k = 0; k < n[2]; ++k) {
    for (int j = 0; j < n[1]; ++j) {
      for (int i = 0; i < n[0]; ++i) {
        const std::size_t q = system.index(i, j, k);
        correction_[padded(i + kGhost, j + kGhost, k + kGhost)] =
            system.active[q] ? unknowns_[q] : 0.0;
      }
    }
  }
  fill_correction_ghosts();
}

void FluidSolver::correct_velocity(double dt) {
  for (int a = 0; a < 3; ++a) {
    // u = u* everywhere, then corrected in place on the unknown faces (a swap: predict_momentum
    // fills u* from u anew at the next step).
    velocity_[a].swap(predicted_[a]);
    std::vector<double>& u = velocity_[a];
    const std::ptrdiff_t s = stride_[a];
    int first = 0, last = 0;
    momentum_unknown_range(a, first, last);
    std::array<int, 3> low{kGhost, kGhost, kGhost};
    std::array<int, 3> high{grid_.cells[0] + kGhost - 1, grid_.cells[1] + kGhost - 1,
                            grid_.cells[2] + kGhost - 1};
    low[a] = first;
    high[a] = last;
    const int team = options_.threading.team(grid_.cell_count());
#pragma omp parallel for schedule(static) num_threads(team)
    for (int k = low[2]; k <= high[2]; ++k) {
      for (int j = low[1]; j <= high[1]; ++j) {
        for (int i = low[0]; i <= high[0]; ++i) {
          const std::size_t face = padded(i, j, k);
          if (blocked_[face] > 0.0 || blocked_[face - s] > 0.0) continue;
          u[face] = u[face] - correction_coefficient(face - s, face, dt) *
                                     (correction_[face] - correction_[face - s]) /
                                     grid_.cell_size[a];
        }
      }
    }
  }
  const int team = options_.threading.team(grid_.cell_count());
#pragma omp parallel for schedule(static) num_threads(team)
  for (int k = kGhost; k < grid_.cells[2] + kGhost; ++k) {
    for (int j = kGhost; j < grid_.cells[1] + kGhost; ++j) {
      for (int i = kGhost; i < grid_.cells[0] + kGhost; ++i)
        pressure_[padded(i, j, k)] += correction_[padded(i, j, k)];
    }
  }
}

void FluidSolver::update_boundaries() {
  for (int a = 0; a < 3; ++a) fill_velocity_ghosts(a);
  fill_pressure_ghosts();
}

// Physics guard: a linear solve that stopped short, or a velocity that is no longer finite. A
// PhysicsError (exit code 3, PHYSICS through the ABI): the state or the deck's physics went
// wrong, not the program. A residual that is not finite means the system's right-hand side
// already held a NaN or an infinity (a source out of range), not that the solver was too slow.
void FluidSolver::check_step_health(double dt) const {
  constexpr std::array<const char*, 3> kAxes{"x", "y", "z"};
  const auto non_finite = [&](const std::string& solve, double residual) {
    return PhysicsError(fmt::format(
        "fluid solver, step {}: the {} solve met a value that is not finite (relative residual "
        "{}) at dt = {} s; the fluid's sources are out of range: check gravity, the boundary "
        "velocities and the particles' state (a particle that is no longer finite gives a "
        "non-finite drag)",
        step_count_, solve, residual, dt));
  };
  for (int a = 0; a < 3; ++a) {
    const SolveReport& momentum = report_.momentum[a];
    if (momentum.converged) continue;
    const std::string solve = fmt::format("{}-momentum", kAxes[static_cast<std::size_t>(a)]);
    if (!std::isfinite(momentum.relative_residual))
      throw non_finite(solve, momentum.relative_residual);
    throw PhysicsError(fmt::format(
        "fluid solver, step {}: the {} solve did not converge in {} iterations (relative "
        "residual {:.3e}, tolerance {:.1e}) at dt = {} s; raise max_iterations or check β and the "
        "boundary velocities",
        step_count_, solve, momentum.iterations, momentum.relative_residual,
        options_.velocity_tolerance, dt));
  }
  if (!report_.pressure.converged) {
    if (!std::isfinite(report_.pressure.relative_residual))
      throw non_finite("pressure", report_.pressure.relative_residual);
    throw PhysicsError(fmt::format(
        "fluid solver, step {}: the pressure solve did not converge in {} iterations (relative "
        "residual {:.3e}, tolerance {:.1e}) at dt = {} s; raise max_iterations, or check for "
        "fluid regions cut off from every outlet whose volume changes (Σ ∂ε/∂t ≠ 0)",
        step_count_, report_.pressure.iterations, report_.pressure.relative_residual,
        options_.pressure_tolerance, dt));
  }
  if (!std::isfinite(report_.divergence)) {
    throw PhysicsError(fmt::format(
        "fluid solver, step {}: the velocity is no longer finite after a step of dt = {} s; keep "
        "dt at about half of stable_time_step() (CFL, and for central advection 2ν/|u|² where "
        "there is no drag; hybrid advection needs only the CFL limit)",
        step_count_, dt));
  }
}

void FluidSolver::measure_divergence(double dt) {
  const std::array<int, 3>& n = grid_.cells;
  double largest = 0.0;  // a maximum: the same for any team
  const int team = options_.threading.team(grid_.cell_count());
#pragma omp parallel for schedule(static) num_threads(team) reduction(max : largest)
  for (int k = 0; k < n[2]; ++k) {
    for (int j = 0; j < n[1]; ++j) {
      for (int i = 0; i < n[0]; ++i) {
        const std::size_t cell = padded(i + kGhost, j + kGhost, k + kGhost);
        if (blocked_[cell] > 0.0) continue;
        largest = std::max(largest, std::abs(continuity_residual(cell, velocity_, dt)));
      }
    }
  }
  report_.divergence = largest;
}

}  // namespace quarry::cfd
