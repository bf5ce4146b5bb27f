// Plain data of the fluid solver: the uniform Cartesian grid, the fluid's properties and the
// boundary condition of each box face (docs/cfd.md "Fluid solver").
#pragma once

#include <array>
#include <cstddef>

#include "core/vec3.h"

namespace quarry::cfd {

// A box of cells; cell (i, j, k), 0 ≤ i < cells[0] …, spans origin + (i, j, k)·cell_size to
// origin + (i + 1, j + 1, k + 1)·cell_size. Pressure, void fraction and drag live at cell
// centres; each velocity component at the centres of the cell faces normal to it (MAC grid,
// Harlow & Welch 1965).
struct FluidGrid {
  Vec3 origin;                        // m
  Vec3 cell_size{1.0, 1.0, 1.0};      // Δx, Δy, Δz (m), > 0
  std::array<int, 3> cells{1, 1, 1};  // ≥ 1 along each axis

  std::size_t cell_count() const {
    return static_cast<std::size_t>(cells[0]) * static_cast<std::size_t>(cells[1]) *
           static_cast<std::size_t>(cells[2]);
  }
  // Index of cell (i, j, k) in the flat arrays the solver takes and returns (x fastest).
  std::size_t cell_index(int i, int j, int k) const {
    return static_cast<std::size_t>(i) +
           static_cast<std::size_t>(cells[0]) *
               (static_cast<std::size_t>(j) +
                static_cast<std::size_t>(cells[1]) * static_cast<std::size_t>(k));
  }
  Vec3 cell_centre(int i, int j, int k) const {
    return {origin.x + (i + 0.5) * cell_size.x, origin.y + (j + 0.5) * cell_size.y,
            origin.z + (k + 0.5) * cell_size.z};
  }
  double cell_volume() const { return cell_size.x * cell_size.y * cell_size.z; }
};

struct FluidProperties {
  double density = 1000.0;  // ρ (kg/m³), > 0
  double viscosity = 1e-3;  // μ, dynamic (Pa·s), > 0
};

enum class BoundaryKind {
  wall,             // no slip: u = wall velocity (its tangential part; the normal part is 0)
  velocity_inlet,   // u = inlet velocity (all components)
  pressure_outlet,  // p = p_ref + ρ g·(x − x_ref) on the face; ∂u/∂n = 0
  periodic,         // paired with the opposite face
};

struct FaceBoundary {
  BoundaryKind kind = BoundaryKind::wall;
  Vec3 velocity;  // wall: its velocity (tangential part used); inlet: the velocity (m/s)
  double reference_pressure = 0.0;  // outlet: p_ref (Pa)
  Vec3 reference_point;             // outlet: x_ref (m), where p = p_ref
};

// The six box faces in the order x−, x+, y−, y+, z−, z+ (face 2a + side, side 0 low, 1 high).
struct FluidBoundaries {
  std::array<FaceBoundary, 6> faces;

  FaceBoundary& face(int axis, int side) {
    return faces[static_cast<std::size_t>(2 * axis + side)];
  }
  const FaceBoundary& face(int axis, int side) const {
    return faces[static_cast<std::size_t>(2 * axis + side)];
  }
  // Both faces of `axis` periodic.
  void set_periodic(int axis) {
    face(axis, 0).kind = BoundaryKind::periodic;
    face(axis, 1).kind = BoundaryKind::periodic;
  }
};

}  // namespace quarry::cfd
