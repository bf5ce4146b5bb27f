// Blocked fluid cells from the deck's geometry (issue #18 §1; docs/deck.md "fluid", `blocked:`):
// boxes, half-spaces and closed surfaces of the deck's `surfaces:` made into the solver's mask,
// and the checks that the fluid they leave can be solved for. Built once with the run.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "cfd/fluid_grid.h"
#include "sim/world.h"

namespace quarry::cfdem {

// The mask (1 = blocked, per cell in FluidGrid::cell_index order) of world.spec.fluid->blocked on
// `grid`; empty when the deck blocks nothing. A cell is blocked when its centre lies
//   box:        in [min, max] (faces included),
//   half_space: on the solid side of the plane, (x − point)·normal ≤ 0 (the plane included),
//   surface:    inside the named surface at its reference (initial) position, by
//               geometry/closed_mesh.h (rays with exact predicates; non-zero winding rule for a
//               consistently oriented mesh, even-odd otherwise).
// Throws UserError at the entry's key: an unknown surface name, a surface that moves (prescribed
// or coupled), one that is not closed (how many open edges, where the first is, a hint), and an
// entry that blocks no cell (outside the grid, or between the cell centres). Pre: world.spec.fluid.
// Cost: O(cells · entries + Σ surface triangles · rows crossed).
std::vector<std::uint8_t> blocked_cells_from_spec(const World& world, const cfd::FluidGrid& grid);

// A region of face-connected fluid cells (periodic faces wrap) that the solver cannot solve for.
struct CutOffFluid {
  std::size_t cells = 0;                   // in the region
  std::array<int, 3> low{}, high{};        // the cell range it spans (inclusive)
  bool touches_inlet = false;              // a velocity inlet feeds it
  std::size_t main_region_cells = 0;       // without an outlet: the largest region's size
};

// With a pressure outlet on the grid: the first region (by its lowest cell index) that touches no
// outlet face — its pressure has no reference and what an inlet feeds it cannot leave. Without an
// outlet: the first region other than the largest (each closed region's pressure would need a
// reference of its own). nullopt when every fluid cell is connected as it must be. Cost: O(cells).
std::optional<CutOffFluid> find_cut_off_fluid(const cfd::FluidGrid& grid, const cfd::FluidBoundaries& boundaries,
                                              std::span<const std::uint8_t> blocked);

// The checks of a mask made from the deck, as UserError at fluid.blocked: every cell blocked, or
// fluid cut off (find_cut_off_fluid; the message gives the region's size and extent in m, the hint
// how to block it or open it). Nothing when `blocked` is empty.
void check_blocked_cells(const FluidSpec& spec, const cfd::FluidGrid& grid, const cfd::FluidBoundaries& boundaries,
                         std::span<const std::uint8_t> blocked);

}  // namespace quarry::cfdem
