// Ghost layers of the fluid solver: the boundary conditions of each box face written into the
// padded fields (periodic wrap, wall and inlet reflection, outlet extrapolation and the outlet's
// hydrostatic pressure p = p_ref + ρ g·(x − x_ref), as the AcuSolve outlet of seed 001).
#include "cfd/fluid_solver.h"

namespace quarry::cfd {

namespace {

// Calls f(I, J, K) for every padded index whose coordinate along `axis` is `layer`.
template <class F>
void for_layer(const std::array<int, 3>& padded_size, int axis, int layer, F&& f) {
  const int b = (axis + 1) % 3, c = (axis + 2) % 3;
  std::array<int, 3> at{};
  at[axis] = layer;
  for (int v = 0; v < padded_size[c]; ++v) {
    for (int u = 0; u < padded_size[b]; ++u) {
      at[b] = u;
      at[c] = v;
      f(at[0], at[1], at[2]);
    }
  }
}

}  // namespace

// Cell fields: periodic wrap, otherwise a copy of the nearest fluid cell (∂/∂n = 0).
void FluidSolver::fill_cell_ghosts(std::vector<double>& field) const {
  for (int a = 0; a < 3; ++a) {
    const int n = grid_.cells[a];
    const bool periodic = boundaries_.face(a, 0).kind == BoundaryKind::periodic;
    const std::ptrdiff_t s = stride_[a];
    for (int g = 0; g < kGhost; ++g) {
      const int low = g, high = n + kGhost + g;
      for_layer(padded_size_, a, low, [&](int i, int j, int k) {
        const std::size_t p = padded(i, j, k);
        field[p] = periodic ? field[p + n * s] : field[p + (kGhost - g) * s];
      });
      for_layer(padded_size_, a, high, [&](int i, int j, int k) {
        const std::size_t p = padded(i, j, k);
        field[p] = periodic ? field[p - n * s] : field[p - (g + 1) * s];
      });
    }
  }
}

double FluidSolver::boundary_pressure(int axis, int side, int i, int j, int k) const {
  const FaceBoundary& face = boundaries_.face(axis, side);
  Vec3 x = grid_.cell_centre(i - kGhost, j - kGhost, k - kGhost);
  x[axis] = grid_.origin[axis] + (side == 0 ? 0.0 : grid_.cells[axis] * grid_.cell_size[axis]);
  // p = p_ref + ρ g·(x − x_ref): the outlet's hydrostatic pressure.
  return face.reference_pressure +
         properties_.density * dot(options_.gravity, x - face.reference_point);
}

// Ghosts of a cell field at outlet faces (after the periodic wrap and the zero-gradient copy of
// fill_cell_ghosts): ghost = ghost_value(inside value, axis, side, i, j, k) for every ghost layer.
template <class GhostValue>
void FluidSolver::fill_outlet_ghosts(std::vector<double>& field, GhostValue ghost_value) {
  fill_cell_ghosts(field);
  for (int a = 0; a < 3; ++a) {
    const int n = grid_.cells[a];
    const std::ptrdiff_t s = stride_[a];
    for (int side = 0; side < 2; ++side) {
      if (boundaries_.face(a, side).kind != BoundaryKind::pressure_outlet) continue;
      const int inside = side == 0 ? kGhost : n + kGhost - 1;
      for_layer(padded_size_, a, inside, [&](int i, int j, int k) {
        const std::size_t p = padded(i, j, k);
        const double ghost = ghost_value(field[p], a, side, i, j, k);
        for (int g = 1; g <= kGhost; ++g) field[side == 0 ? p - g * s : p + g * s] = ghost;
      });
    }
  }
}

// Pressure: periodic wrap; outlets hold p on the face (ghost = 2 p_face − p_inside);
// walls and inlets ∂p/∂n = 0.
void FluidSolver::fill_pressure_ghosts() {
  fill_outlet_ghosts(pressure_, [this](double inside, int a, int side, int i, int j, int k) {
    return 2.0 * boundary_pressure(a, side, i, j, k) - inside;
  });
}

// φ: as the pressure, with φ = 0 on outlet faces.
void FluidSolver::fill_correction_ghosts() {
  fill_outlet_ghosts(correction_, [](double inside, int, int, int, int, int) { return -inside; });
}

// Velocity component `axis`. Along its own axis: the boundary faces of walls and inlets hold
// the prescribed normal velocity (0 where the cell inside is blocked), periodic faces wrap, outlets extrapolate (∂u/∂n = 0). Along
// the other axes the ghost faces mirror the boundary value: u_ghost = 2 u_b − u_inside for
// walls and inlets (second order at the face), a copy for outlets, a wrap for periodic.
void FluidSolver::fill_velocity_ghosts(int axis) {
  std::vector<double>& u = velocity_[axis];
  for (int a = 0; a < 3; ++a) {
    const int n = grid_.cells[a];
    const std::ptrdiff_t s = stride_[a];
    const bool periodic = boundaries_.face(a, 0).kind == BoundaryKind::periodic;
    for (int side = 0; side < 2; ++side) {
      const FaceBoundary& face = boundaries_.face(a, side);
      const double prescribed = face.kind == BoundaryKind::wall
                                    ? (a == axis ? 0.0 : face.velocity[axis])
                                    : face.velocity[axis];
      if (a == axis) {
        // Boundary face at padded kGhost (low) or n + kGhost (high); ghosts beyond it.
        const int boundary = side == 0 ? kGhost : n + kGhost;
        for_layer(padded_size_, a, boundary, [&](int i, int j, int k) {
          const std::size_t p = padded(i, j, k);
          if (periodic) {
            if (side == 1) u[p] = u[p - n * s];
          } else if (face.kind != BoundaryKind::pressure_outlet) {
            // An inlet face of a blocked cell feeds nothing: no fluid behind it. An inlet's
            // velocity is superficial (the volume flux per area, as a distributor is rated):
            // the face carries the interstitial U/ε of the cell inside, so the flux ε u A is
            // U A whatever particle volume that cell holds.
            const std::size_t inside = side == 0 ? p : p - s;
            if (blocked_[inside] > 0.0) u[p] = 0.0;
            else if (face.kind == BoundaryKind::velocity_inlet) u[p] = prescribed / void_fraction_new_[inside];
            else u[p] = prescribed;
          }
          for (int g = 1; g <= kGhost; ++g) {
            const std::size_t ghost = side == 0 ? p - g * s : p + g * s;
            if (side == 1 && g == kGhost) continue;  // beyond the padded array
            u[ghost] = periodic ? (side == 0 ? u[ghost + n * s] : u[ghost - n * s]) : u[p];
          }
        });
        continue;
      }
      const int inside = side == 0 ? kGhost : n + kGhost - 1;
      for_layer(padded_size_, a, inside, [&](int i, int j, int k) {
        const std::size_t p = padded(i, j, k);
        for (int g = 1; g <= kGhost; ++g) {
          const std::size_t ghost = side == 0 ? p - g * s : p + g * s;
          const std::size_t mirror = side == 0 ? p + (g - 1) * s : p - (g - 1) * s;
          if (periodic) {
            u[ghost] = side == 0 ? u[ghost + n * s] : u[ghost - n * s];
          } else if (face.kind == BoundaryKind::pressure_outlet) {
            u[ghost] = u[p];
          } else {
            u[ghost] = 2.0 * prescribed - u[mirror];
          }
        }
      });
    }
  }
}

// After the blocked mask changed (the padded copy and its ghosts are current): every face of a
// blocked cell at rest — a periodic axis' high boundary face is its first face again — then the
// ghost layers from the new face values.
void FluidSolver::apply_blocked_faces() {
  for (int a = 0; a < 3; ++a) {
    std::vector<double>& u = velocity_[a];
    const std::ptrdiff_t s = stride_[a];
    const int n = grid_.cells[a];
    const bool periodic = boundaries_.face(a, 0).kind == BoundaryKind::periodic;
    for (int k = 0; k < grid_.cells[2]; ++k) {
      for (int j = 0; j < grid_.cells[1]; ++j) {
        for (int i = 0; i < grid_.cells[0]; ++i) {
          const std::size_t p = padded(i + kGhost, j + kGhost, k + kGhost);
          if (blocked_[p] == 0.0) continue;
          u[p] = 0.0;
          u[p + s] = 0.0;
          const int along = a == 0 ? i : (a == 1 ? j : k);
          if (periodic && along == n - 1) u[p + s - n * s] = 0.0;
          if (periodic && along == 0) u[p + n * s] = 0.0;
        }
      }
    }
  }
  for (int a = 0; a < 3; ++a) fill_velocity_ghosts(a);
}

}  // namespace quarry::cfd
