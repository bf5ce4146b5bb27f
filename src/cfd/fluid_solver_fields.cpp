// The fluid solver's inputs (void fraction, drag coefficient, force density, blocked cells, an
// imposed velocity or pressure) and results (cell and face velocities, pressure, the stable
// time step), between the flat per-cell arrays of the caller and the padded fields.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

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
  double convective = 0.0, kinetic = 0.0;
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
    kinetic += largest * largest;
  }
  if (convective == 0.0) return std::numeric_limits<double>::infinity();
  const double nu = properties_.viscosity / properties_.density;
  return std::min(1.0 / convective, 2.0 * nu / kinetic);
}

}  // namespace quarry::cfd
