// The fluid solver's inputs (void fraction, drag coefficient, force density, blocked cells, an
// imposed velocity or pressure) and results (cell and face velocities, pressure, the stable
// time step), between the flat per-cell arrays of the caller and the padded fields; the state
// between steps for checkpoints (state, set_state).
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>

#include "cfd/fluid_solver.h"

namespace quarry::cfd {

namespace {
void check_void_fraction(std::span<const double> values, std::size_t expected) {
  if (values.size() != expected) {
    throw std::invalid_argument(fmt::format(
        "fluid solver: void fraction has {} values, the grid {} cells", values.size(), expected));
  }
  for (std::size_t c = 0; c < values.size(); ++c) {
    if (!(values[c] > 0.0 && values[c] <= 1.0)) {
      throw std::invalid_argument(fmt::format(
          "fluid solver: void fraction of cell {} must be in (0, 1], got {}", c, values[c]));
    }
  }
}
}  // namespace

void FluidSolver::set_void_fraction(std::span<const double> void_fraction) {
  check_void_fraction(void_fraction, grid_.cell_count());
  for (int k = 0; k < grid_.cells[2]; ++k) {
    for (int j = 0; j < grid_.cells[1]; ++j) {
      for (int i = 0; i < grid_.cells[0]; ++i) {
        void_fraction_new_[padded(i + kGhost, j + kGhost, k + kGhost)] =
            void_fraction[grid_.cell_index(i, j, k)];
      }
    }
  }
  fill_cell_ghosts(void_fraction_new_);
  if (!void_fraction_started_) {
    void_fraction_old_ = void_fraction_new_;
    void_fraction_started_ = true;
  }
}

void FluidSolver::set_initial_void_fraction(std::span<const double> void_fraction) {
  void_fraction_started_ = false;
  set_void_fraction(void_fraction);
}

std::span<double> FluidSolver::drag_coefficient() {
  return drag_input_;
}
std::span<Vec3> FluidSolver::force_density() {
  return force_input_;
}
std::span<std::uint8_t> FluidSolver::blocked() {
  return blocked_input_;
}

void FluidSolver::set_velocity(const std::function<Vec3(const Vec3&)>& velocity) {
  for (int a = 0; a < 3; ++a) {
    for (int k = kGhost; k < grid_.cells[2] + kGhost + (a == 2 ? 1 : 0); ++k) {
      for (int j = kGhost; j < grid_.cells[1] + kGhost + (a == 1 ? 1 : 0); ++j) {
        for (int i = kGhost; i < grid_.cells[0] + kGhost + (a == 0 ? 1 : 0); ++i) {
          Vec3 x = grid_.cell_centre(i - kGhost, j - kGhost, k - kGhost);
          x[a] -= 0.5 * grid_.cell_size[a];
          velocity_[a][padded(i, j, k)] = velocity(x)[a];
        }
      }
    }
  }
  update_boundaries();
}

void FluidSolver::set_pressure(const std::function<double(const Vec3&)>& pressure) {
  for (int k = 0; k < grid_.cells[2]; ++k) {
    for (int j = 0; j < grid_.cells[1]; ++j) {
      for (int i = 0; i < grid_.cells[0]; ++i) {
        pressure_[padded(i + kGhost, j + kGhost, k + kGhost)] =
            pressure(grid_.cell_centre(i, j, k));
      }
    }
  }
  fill_pressure_ghosts();
}

Vec3 FluidSolver::cell_velocity(int i, int j, int k) const {
  const std::size_t cell = padded(i + kGhost, j + kGhost, k + kGhost);
  Vec3 result;
  for (int a = 0; a < 3; ++a)
    result[a] = 0.5 * (velocity_[a][cell] + velocity_[a][cell + stride_[a]]);
  return result;
}

double FluidSolver::pressure(int i, int j, int k) const {
  return pressure_[padded(i + kGhost, j + kGhost, k + kGhost)];
}

double FluidSolver::face_velocity(int axis, int i, int j, int k) const {
  return velocity_[axis][padded(i + kGhost, j + kGhost, k + kGhost)];
}

double FluidSolver::stable_time_step() const {
  // CFL: 1/Σ_a(max|u_a|/Δx_a) over all faces.
  double convective = 0.0;
  for (int a = 0; a < 3; ++a) {
    double largest = 0.0;
    for (int k = kGhost; k < grid_.cells[2] + kGhost + (a == 2 ? 1 : 0); ++k) {
      for (int j = kGhost; j < grid_.cells[1] + kGhost + (a == 1 ? 1 : 0); ++j) {
        for (int i = kGhost; i < grid_.cells[0] + kGhost + (a == 0 ? 1 : 0); ++i) {
          largest = std::max(largest, std::abs(velocity_[a][padded(i, j, k)]));
        }
      }
    }
    convective += largest / grid_.cell_size[a];
  }
  if (convective == 0.0) return std::numeric_limits<double>::infinity();
  // Hybrid advection: the step multiplies a mode by g = N/(1 + d + Σ 2 r_a (1 − cos θ_a)) with
  // N = (1 − Σc_a) + Σ_up [c_a e^{−iθ_a} + 2 r_a (1 − cos θ_a)] + Σ_central c_a (1 − i sin θ_a),
  // c_a ≤ 2 r_a on the central faces. While Σc_a ≤ 1 (CFL) the triangle inequality gives
  // |N| ≤ 1 + Σ_up 2 r_a (1 − cos θ_a) + Σ_central c_a sin²θ_a/2 ≤ the denominator: no other limit.
  if (options_.advection == Advection::hybrid) return 1.0 / convective;
  // Forward-Euler central advection damped by the implicit viscosity and drag, cell by cell
  // (frozen coefficients; docs/cfd.md "Time step"). A Fourier mode is multiplied per step by
  // g = (1 − i Σ c_a sin θ_a)/(1 + d + Σ 2 r_a (1 − cos θ_a)), c_a = |u_a| dt/Δx_a,
  // r_a = ν dt/Δx_a², d = β dt/(ρ ε). |g| ≤ 1 for every θ if either
  //   (i)  dt (Σu_a² Σ1/Δx_a² − D²) ≤ 2 (D + ν Σ1/Δx_a²)   (Cauchy–Schwarz on Σ c_a sin θ_a), or
  //   (ii) dt ((Σ|u_a|/Δx_a)² − D²) ≤ 2 D                 (|Σ c_a sin θ_a| ≤ Σ c_a),
  // D = β/(ρ ε) (1/s). Without drag (i) is dt ≤ 2ν/Σu_a², the classical limit.
  const double nu = properties_.viscosity / properties_.density;  // m²/s
  double inverse_h2 = 0.0;                                         // 1/m²
  for (int a = 0; a < 3; ++a) inverse_h2 += 1.0 / (grid_.cell_size[a] * grid_.cell_size[a]);
  const auto limit = [](double numerator, double denominator) {
    return denominator > 0.0 ? numerator / denominator : std::numeric_limits<double>::infinity();
  };
  double damped = std::numeric_limits<double>::infinity();  // a minimum: the same for any team
  const int team = options_.threading.team(grid_.cell_count());
#pragma omp parallel for schedule(static) num_threads(team) reduction(min : damped)
  for (int k = 0; k < grid_.cells[2]; ++k) {
    for (int j = 0; j < grid_.cells[1]; ++j) {
      for (int i = 0; i < grid_.cells[0]; ++i) {
        const std::size_t c = grid_.cell_index(i, j, k);
        if (blocked_input_[c]) continue;
        const std::size_t cell = padded(i + kGhost, j + kGhost, k + kGhost);
        double speed2 = 0.0, rate = 0.0;  // Σ u_a² (m²/s²), Σ |u_a|/Δx_a (1/s): the faces' larger
        for (int a = 0; a < 3; ++a) {
          const double u = std::max(std::abs(velocity_[a][cell]), std::abs(velocity_[a][cell + stride_[a]]));
          speed2 += u * u;
          rate += u / grid_.cell_size[a];
        }
        const double d = drag_input_[c] / (properties_.density * void_fraction_new_[cell]);  // 1/s
        const double by_viscosity = limit(2.0 * (d + nu * inverse_h2), speed2 * inverse_h2 - d * d);
        const double by_drag = limit(2.0 * d, rate * rate - d * d);
        damped = std::min(damped, std::max(by_viscosity, by_drag));
      }
    }
  }
  return std::min(1.0 / convective, damped);
}

FluidSolverState FluidSolver::state() const {
  FluidSolverState state;
  state.velocity = velocity_;
  state.pressure = pressure_;
  state.void_fraction_old = void_fraction_old_;
  state.void_fraction_new = void_fraction_new_;
  state.drag_coefficient = drag_input_;
  state.force_density = force_input_;
  state.blocked = blocked_input_;
  state.void_fraction_started = void_fraction_started_;
  state.steps = step_count_;
  state.last_report = report_;
  return state;
}

namespace {

template <class T>
void check_state_size(const std::vector<T>& values, std::size_t expected, const char* what) {
  if (values.size() != expected) {
    throw std::invalid_argument(fmt::format("the fluid's {} has {} values, the grid {}", what,
                                            values.size(), expected));
  }
}

void check_state_finite(std::span<const double> values, const char* what) {
  for (std::size_t k = 0; k < values.size(); ++k) {
    if (!std::isfinite(values[k])) {
      throw std::invalid_argument(
          fmt::format("the fluid's {} value {} is not a finite number", what, k));
    }
  }
}

}  // namespace

void FluidSolver::set_state(FluidSolverState state) {
  const std::size_t padded_count = pressure_.size(), cells = grid_.cell_count();
  constexpr std::array<const char*, 3> kVelocity{"x-velocity", "y-velocity", "z-velocity"};
  for (std::size_t a = 0; a < 3; ++a) {
    check_state_size(state.velocity[a], padded_count, kVelocity[a]);
    check_state_finite(state.velocity[a], kVelocity[a]);
  }
  check_state_size(state.pressure, padded_count, "pressure");
  check_state_finite(state.pressure, "pressure");
  for (const auto& [field, what] : {std::pair{&state.void_fraction_old, "previous void fraction"},
                                    std::pair{&state.void_fraction_new, "void fraction"}}) {
    check_state_size(*field, padded_count, what);
    for (std::size_t k = 0; k < field->size(); ++k) {
      if (!((*field)[k] > 0.0 && (*field)[k] <= 1.0)) {
        throw std::invalid_argument(
            fmt::format("the fluid's {} value {} is {}, not in (0, 1]", what, k, (*field)[k]));
      }
    }
  }
  check_state_size(state.drag_coefficient, cells, "drag coefficient");
  for (std::size_t c = 0; c < cells; ++c) {
    if (!(state.drag_coefficient[c] >= 0.0) || !std::isfinite(state.drag_coefficient[c])) {
      throw std::invalid_argument(fmt::format("the fluid's drag coefficient of cell {} is {}", c,
                                              state.drag_coefficient[c]));
    }
  }
  check_state_size(state.force_density, cells, "force density");
  for (std::size_t c = 0; c < cells; ++c) {
    const Vec3& f = state.force_density[c];
    if (!std::isfinite(f.x) || !std::isfinite(f.y) || !std::isfinite(f.z)) {
      throw std::invalid_argument(
          fmt::format("the fluid's force density of cell {} is not finite", c));
    }
  }
  check_state_size(state.blocked, cells, "blocked-cell flags");
  for (std::size_t c = 0; c < cells; ++c) {
    if (state.blocked[c] > 1) {
      throw std::invalid_argument(
          fmt::format("the fluid's blocked flag of cell {} is {}, not 0 or 1", c, state.blocked[c]));
    }
  }
  if (state.steps < 0) {
    throw std::invalid_argument(fmt::format("the fluid's step count {} is negative", state.steps));
  }
  velocity_ = std::move(state.velocity);
  pressure_ = std::move(state.pressure);
  void_fraction_old_ = std::move(state.void_fraction_old);
  void_fraction_new_ = std::move(state.void_fraction_new);
  drag_input_ = std::move(state.drag_coefficient);
  force_input_ = std::move(state.force_density);
  blocked_input_ = std::move(state.blocked);
  void_fraction_started_ = state.void_fraction_started;
  step_count_ = state.steps;
  report_ = state.last_report;
}

}  // namespace quarry::cfd
