// The one kernel of the CFD-DEM coupling (issue #18 §2): each particle's share of the fluid
// cells, by trilinear (cloud-in-cell) weights of its centre on the cell centres. The same
// weights give the void fraction, deposit the particles' drag on the fluid and interpolate the
// fluid's velocity and pressure gradient to the particles, so that the particle volume and the
// exchanged momentum are the same on both sides (docs/cfd.md "Coupling").
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "cfd/fluid_grid.h"
#include "core/vec3.h"

namespace quarry::cfdem {

// One particle's weights on (at most) eight cells; the weights are ≥ 0 and sum to 1 (to
// round-off). A corner that falls outside the grid across a non-periodic face is folded onto
// the nearest cell inside (so a particle next to a wall keeps all its volume inside), across a
// periodic face it wraps. Cells may repeat after folding; every entry is used as it stands.
struct CellWeights {
  std::array<std::uint32_t, 8> cell{};  // flat FluidGrid::cell_index
  std::array<double, 8> weight{};       // 1
};

// Which axes wrap (both faces periodic).
using PeriodicAxes = std::array<bool, 3>;

// The weights of a particle at `position` (m). The trilinear hat spans one cell size on each
// side of the centre: the weights and everything made from them are continuous in the
// position (so ∂ε/∂t stays finite as a particle crosses cell faces). Positions outside the grid
// are clamped to it (periodic axes: wrapped). Cost: O(1).
CellWeights cell_weights(const cfd::FluidGrid& grid, const PeriodicAxes& periodic,
                         const Vec3& position);

// ε per cell: 1 − Σ_p w_pc V_p / V_cell, V_p = 4/3 π R_p³. `void_fraction` is resized to the
// cell count. Σ_c (1 − ε_c) V_cell = Σ_p V_p to round-off. Returns the smallest ε (may be ≤ 0
// when particles crowd a cell; the caller checks it). Cost: O(cells + particles); the particles
// are summed in index order (bit-identical for any thread count).
double void_fraction(const cfd::FluidGrid& grid, std::span<const CellWeights> weights,
                     std::span<const double> radius, std::vector<double>& void_fraction);

// Adds each particle's value times its weight, divided by the cell volume, to `density`
// (per-cell, already sized): Σ_c density_c V_cell grows by Σ_p value_p exactly (to round-off).
// Used for β (kg/(m³·s)) from β_p (kg/s) and for force densities (N/m³) from forces (N).
void deposit(const cfd::FluidGrid& grid, std::span<const CellWeights> weights,
             std::span<const double> value, std::span<double> density);
void deposit(const cfd::FluidGrid& grid, std::span<const CellWeights> weights,
             std::span<const Vec3> value, std::span<Vec3> density);

// Σ_c w_pc field_c: the field at the particle with the same weights.
double interpolate(const CellWeights& weights, std::span<const double> field);
Vec3 interpolate(const CellWeights& weights, std::span<const Vec3> field);

}  // namespace quarry::cfdem
