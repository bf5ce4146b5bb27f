// The one kernel of the CFD-DEM coupling (issue #18 §2): each particle's share of the fluid
// cells, by trilinear (cloud-in-cell) weights of its centre on the cell centres. The same
// weights give the void fraction, deposit the particles' drag on the fluid and interpolate the
// fluid's velocity and pressure gradient to the particles, so that the particle volume and the
// exchanged momentum are the same on both sides (docs/cfd.md "Coupling"). Blocked cells (no fluid)
// get no weight: a particle's share of them goes to its fluid cells.
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

// Blocked cells (no fluid) as the kernel needs them: the mask, and for every cell the nearest
// fluid cell (itself when it is one), by the distance between cell centres within the grid
// (periodic faces are not crossed by this search).
struct BlockedCells {
  std::vector<std::uint8_t> mask;            // per cell, 1 = blocked; empty when none is
  std::vector<std::uint32_t> nearest_fluid;  // per cell (flat index); empty when none is blocked
  std::size_t count = 0;                     // blocked cells

  bool blocked(std::size_t cell) const { return count > 0 && mask[cell] != 0; }
};

// From a per-cell mask (1 = blocked) of grid.cell_count() values. Throws std::invalid_argument
// when the size is wrong or every cell is blocked. The nearest fluid cells come from the exact
// Euclidean distance transform of Felzenszwalb & Huttenlocher (2012, Theory of Computing 8:415-428:
// lower envelopes of parabolas, one axis after the other), carrying the nearest cell along; ties
// are broken the same way every time. Cost: O(cells).
BlockedCells make_blocked_cells(const cfd::FluidGrid& grid, std::span<const std::uint8_t> mask);

// The weights of a particle at `position` kept off blocked cells: the trilinear weights of its
// blocked cells are dropped and the rest divided by their sum, so they still sum to 1 (to
// round-off), the particle's volume and forces stay whole on fluid cells, and nothing it
// interpolates reads a blocked cell (a dropped entry points at one of its fluid cells, with weight
// 0). A particle none of whose weight falls on a fluid cell (its centre among blocked cell centres)
// goes whole onto the fluid cell nearest the cell holding its centre, and *moved_to_nearest (if
// given) is set to true. Equal to the plain cell_weights when no cell is blocked. Continuous in
// the position wherever some weight is on fluid cells. Cost: O(1).
CellWeights cell_weights(const cfd::FluidGrid& grid, const PeriodicAxes& periodic,
                         const BlockedCells& blocked, const Vec3& position,
                         bool* moved_to_nearest = nullptr);

// The particles grouped so that several threads deposit them with the bits of one ("owner
// computes"). The cells are cut into ranges of the flat index, each holding about as many
// particles (counted at their lowest cell); a range lists, in index order, the particles whose
// lowest-to-highest cells overlap it. A thread deposits a range's particles into that range's
// cells only, so every cell sums its particles in index order, as one thread does, however the
// cells are cut. A particle whose cells straddle a cut is read by both ranges: about one layer of
// cells' particles per cut (across a periodic z face a particle's cells span the whole flat
// index, and every range reads it, writing only its own cells).
struct DepositOrder {
  int threads = 1;                                    // the team that deposits with it
  std::vector<std::size_t> first_cell;                // per range and one more: range r is [first_cell[r], first_cell[r + 1])
  std::vector<std::vector<std::uint32_t>> particles;  // per range, ascending
  std::vector<std::uint32_t> lowest, highest;         // per particle, its lowest and highest cell (scratch)
  std::vector<std::uint32_t> per_cell;                // particles whose lowest cell it is (scratch)
};

// Makes `order` for these weights: `threads` ranges, deposited by as many threads. Cost:
// O(particles + cells), the particles on the threads.
void order_deposits(const cfd::FluidGrid& grid, std::span<const CellWeights> weights, int threads,
                    DepositOrder& order);

// ε per cell: 1 − Σ_p w_pc V_p / V_cell, V_p = 4/3 π R_p³. `void_fraction` is resized to the
// cell count. Σ_c (1 − ε_c) V_cell = Σ_p V_p to round-off. Returns the smallest ε (may be ≤ 0
// when particles crowd a cell; the caller checks it). Cost: O(cells + particles); each cell sums
// its particles in index order, on one thread, or on order->threads with an order made for these
// weights (order_deposits): the same bits.
double void_fraction(const cfd::FluidGrid& grid, std::span<const CellWeights> weights,
                     std::span<const double> radius, std::vector<double>& void_fraction,
                     const DepositOrder* order = nullptr);

// Adds each particle's value times its weight, divided by the cell volume, to `density`
// (per-cell, already sized): Σ_c density_c V_cell grows by Σ_p value_p exactly (to round-off).
// Used for β (kg/(m³·s)) from β_p (kg/s) and for force densities (N/m³) from forces (N). Threads
// and bits as void_fraction's.
void deposit(const cfd::FluidGrid& grid, std::span<const CellWeights> weights,
             std::span<const double> value, std::span<double> density,
             const DepositOrder* order = nullptr);
void deposit(const cfd::FluidGrid& grid, std::span<const CellWeights> weights,
             std::span<const Vec3> value, std::span<Vec3> density, const DepositOrder* order = nullptr);

// The drag's two deposits in one pass over the weights: β_p into `beta` and β_p v_p into `force`,
// the same bits as deposit(…, coefficient, beta) and deposit(…, v_p β_p, force).
void deposit_drag(const cfd::FluidGrid& grid, std::span<const CellWeights> weights,
                  std::span<const double> coefficient, std::span<const Vec3> velocity, std::span<double> beta,
                  std::span<Vec3> force, const DepositOrder* order = nullptr);

// Σ_c w_pc field_c: the field at the particle with the same weights.
double interpolate(const CellWeights& weights, std::span<const double> field);
Vec3 interpolate(const CellWeights& weights, std::span<const Vec3> field);

}  // namespace quarry::cfdem
