// fluid.blocked → the solver's blocked-cell mask: boxes and half-spaces by the cell centres, closed
// surfaces by geometry/closed_mesh.h; then the fluid left over is checked: some fluid, and every
// region of it reached by an outlet (a flood fill over the cells' faces).
#include "cfdem/fluid_blocked.h"

#include <fmt/format.h>

#include <algorithm>

#include "core/diagnostics.h"
#include "geometry/closed_mesh.h"

namespace quarry::cfdem {

namespace {

const char* kind_name(FluidBlockedKind kind) {
  switch (kind) {
    case FluidBlockedKind::box: return "box";
    case FluidBlockedKind::half_space: return "half_space";
    case FluidBlockedKind::surface: return "surface";
  }
  return "region";
}

std::string point_text(const Vec3& x) { return fmt::format("[{:.6g}, {:.6g}, {:.6g}]", x.x, x.y, x.z); }

// The surface of `world` named in a surface entry: fixed and closed, else UserError at the name.
const WorldSurface& blocking_surface(const World& world, const FluidBlockedSpec& entry) {
  const auto found = std::find_if(world.surfaces.begin(), world.surfaces.end(),
                                  [&](const WorldSurface& s) { return s.mesh.name == entry.surface.value; });
  if (found == world.surfaces.end()) {
    std::string names;
    for (const WorldSurface& s : world.surfaces) names += (names.empty() ? "" : ", ") + s.mesh.name;
    throw UserError(entry.surface.where, fmt::format("unknown surface \"{}\"", entry.surface.value),
                    names.empty() ? "no surface is defined" : "the surfaces are: " + names);
  }
  if (found->moving())
    throw UserError(entry.surface.where,
                    fmt::format("surface \"{}\" moves, but blocked fluid cells are fixed", entry.surface.value),
                    "block a fixed surface");
  return *found;
}

void mark_surface(const World& world, const FluidBlockedSpec& entry, const cfd::FluidGrid& grid,
                  std::vector<std::uint8_t>& inside) {
  const Surface& mesh = blocking_surface(world, entry).mesh;
  const MeshClosure closure = check_closure(mesh.reference_vertices, mesh.triangles);
  if (!closure.closed())
    throw UserError(
        entry.surface.where,
        fmt::format("surface \"{}\" is not closed, so it has no inside: {} of its edges belong to an odd number "
                    "of triangles (a hole's rim; the first at {} m)",
                    entry.surface.value, closure.open_edges, point_text(closure.first_open_edge_midpoint)),
        "a blocked surface must be watertight (each edge shared by two triangles, corners at the same "
        "coordinates): close the holes in the STL (e.g. MeshLab: Close Holes), or block boxes and "
        "half-spaces instead");
  const CellCentres centres{grid.origin, grid.cell_size, grid.cells};
  inside = mark_centres_inside(centres, mesh.reference_vertices, mesh.triangles, closure);
}

// Where the grid's cell centres lie, for hints.
std::string centre_range(const cfd::FluidGrid& grid) {
  return fmt::format("the cell centres lie from {} to {} m",
                     point_text(grid.cell_centre(0, 0, 0)),
                     point_text(grid.cell_centre(grid.cells[0] - 1, grid.cells[1] - 1, grid.cells[2] - 1)));
}

}  // namespace

std::vector<std::uint8_t> blocked_cells_from_spec(const World& world, const cfd::FluidGrid& grid) {
  const FluidSpec& spec = *world.spec.fluid;
  if (spec.blocked.empty()) return {};
  std::vector<std::uint8_t> mask(grid.cell_count(), 0);
  std::vector<std::uint8_t> inside;
  for (const FluidBlockedSpec& entry : spec.blocked) {
    if (entry.kind.value == FluidBlockedKind::surface) mark_surface(world, entry, grid, inside);
    std::size_t marked = 0;  // cells this entry blocks (some perhaps blocked by others as well)
    for (int k = 0; k < grid.cells[2]; ++k)
      for (int j = 0; j < grid.cells[1]; ++j)
        for (int i = 0; i < grid.cells[0]; ++i) {
          const std::size_t c = grid.cell_index(i, j, k);
          const Vec3 x = grid.cell_centre(i, j, k);
          bool solid = false;
          switch (entry.kind.value) {
            case FluidBlockedKind::box: {
              const Vec3& lo = entry.min.value;
              const Vec3& hi = entry.max.value;
              solid = x.x >= lo.x && x.x <= hi.x && x.y >= lo.y && x.y <= hi.y && x.z >= lo.z && x.z <= hi.z;
              break;
            }
            case FluidBlockedKind::half_space:
              solid = dot(x - entry.point.value, entry.normal.value) <= 0.0;
              break;
            case FluidBlockedKind::surface:
              solid = inside[c] != 0;
              break;
          }
          if (!solid) continue;
          mask[c] = 1;
          ++marked;
        }
    if (marked > 0) continue;
    const char* where = entry.kind.value == FluidBlockedKind::box          ? "in it"
                        : entry.kind.value == FluidBlockedKind::half_space ? "on its solid side, (x − point)·normal ≤ 0"
                                                                           : "inside it";
    throw UserError(entry.where,
                    fmt::format("this blocked {} blocks no fluid cell: no cell centre lies {}", kind_name(entry.kind.value), where),
                    entry.kind.value == FluidBlockedKind::half_space
                        ? fmt::format("the normal points out of the solid, into the fluid; {}", centre_range(grid))
                        : fmt::format("a cell is blocked when its centre is covered; {} (cell size {:.6g} m)",
                                      centre_range(grid), grid.cell_size.x));
  }
  return mask;
}

std::optional<CutOffFluid> find_cut_off_fluid(const cfd::FluidGrid& grid, const cfd::FluidBoundaries& boundaries,
                                              std::span<const std::uint8_t> blocked) {
  const std::size_t cells = grid.cell_count();
  if (blocked.empty()) return std::nullopt;
  constexpr std::uint32_t kNone = ~std::uint32_t{0};
  std::vector<std::uint32_t> region(cells, kNone);
  struct Region {
    CutOffFluid extent;
    bool touches_outlet = false;
  };
  std::vector<Region> regions;
  bool any_outlet = false;
  for (const cfd::FaceBoundary& face : boundaries.faces) any_outlet |= face.kind == cfd::BoundaryKind::pressure_outlet;
  std::vector<std::uint32_t> stack;
  const auto coordinates = [&](std::size_t c) {
    const auto nx = static_cast<std::size_t>(grid.cells[0]), ny = static_cast<std::size_t>(grid.cells[1]);
    return std::array<int, 3>{static_cast<int>(c % nx), static_cast<int>((c / nx) % ny), static_cast<int>(c / (nx * ny))};
  };
  for (std::size_t seed = 0; seed < cells; ++seed) {
    if (blocked[seed] || region[seed] != kNone) continue;
    const auto label = static_cast<std::uint32_t>(regions.size());
    Region r;
    r.extent.low = coordinates(seed);
    r.extent.high = r.extent.low;
    region[seed] = label;
    stack.assign(1, static_cast<std::uint32_t>(seed));
    while (!stack.empty()) {
      const std::size_t c = stack.back();
      stack.pop_back();
      const std::array<int, 3> at = coordinates(c);
      ++r.extent.cells;
      for (int axis = 0; axis < 3; ++axis) {
        const auto a = static_cast<std::size_t>(axis);
        r.extent.low[a] = std::min(r.extent.low[a], at[a]);
        r.extent.high[a] = std::max(r.extent.high[a], at[a]);
        const bool periodic = boundaries.face(axis, 0).kind == cfd::BoundaryKind::periodic;
        for (int side = 0; side < 2; ++side) {
          std::array<int, 3> next = at;
          next[a] += side == 0 ? -1 : 1;
          if (next[a] < 0 || next[a] >= grid.cells[a]) {
            if (!periodic) {  // the grid's face: what kind of boundary the region meets there
              const cfd::BoundaryKind kind = boundaries.face(axis, side).kind;
              r.touches_outlet |= kind == cfd::BoundaryKind::pressure_outlet;
              r.extent.touches_inlet |= kind == cfd::BoundaryKind::velocity_inlet;
              continue;
            }
            next[a] = (next[a] + grid.cells[a]) % grid.cells[a];
          }
          const std::size_t n = grid.cell_index(next[0], next[1], next[2]);
          if (blocked[n] || region[n] != kNone) continue;
          region[n] = label;
          stack.push_back(static_cast<std::uint32_t>(n));
        }
      }
    }
    regions.push_back(r);
  }
  if (any_outlet) {
    for (const Region& r : regions)
      if (!r.touches_outlet) return r.extent;
    return std::nullopt;
  }
  if (regions.size() <= 1) return std::nullopt;
  std::size_t largest = 0;
  for (std::size_t n = 1; n < regions.size(); ++n)
    if (regions[n].extent.cells > regions[largest].extent.cells) largest = n;
  CutOffFluid cut = regions[largest == 0 ? 1 : 0].extent;
  cut.main_region_cells = regions[largest].extent.cells;
  return cut;
}

void check_blocked_cells(const FluidSpec& spec, const cfd::FluidGrid& grid, const cfd::FluidBoundaries& boundaries,
                         std::span<const std::uint8_t> blocked) {
  if (blocked.empty()) return;
  if (std::all_of(blocked.begin(), blocked.end(), [](std::uint8_t b) { return b != 0; }))
    throw UserError(spec.blocked_where,
                    fmt::format("every one of the {} fluid cells is blocked: no fluid is left", grid.cell_count()),
                    "a half_space's normal points out of the solid, into the fluid; check it and the boxes' corners");
  const std::optional<CutOffFluid> cut = find_cut_off_fluid(grid, boundaries, blocked);
  if (!cut) return;
  const Vec3 low{grid.origin.x + cut->low[0] * grid.cell_size.x, grid.origin.y + cut->low[1] * grid.cell_size.y,
                 grid.origin.z + cut->low[2] * grid.cell_size.z};
  const Vec3 high{grid.origin.x + (cut->high[0] + 1) * grid.cell_size.x,
                  grid.origin.y + (cut->high[1] + 1) * grid.cell_size.y,
                  grid.origin.z + (cut->high[2] + 1) * grid.cell_size.z};
  const std::string region = fmt::format("{} fluid cells (cells ({}, {}, {}) to ({}, {}, {}), within {} to {} m)", cut->cells,
                                         cut->low[0], cut->low[1], cut->low[2], cut->high[0], cut->high[1],
                                         cut->high[2], point_text(low), point_text(high));
  const std::string hint = fmt::format("block them too (e.g. - {{type: box, min: {}, max: {}}} if no other fluid lies "
                                       "there), or open a path {}",
                                       point_text(low), point_text(high),
                                       cut->main_region_cells > 0 ? "to the rest of the fluid" : "to an outlet");
  if (cut->main_region_cells > 0)
    throw UserError(spec.blocked_where,
                    fmt::format("{} are cut off by blocked cells from the rest of the fluid ({} cells); without a "
                                "pressure outlet each closed region's pressure would need a reference of its own",
                                region, cut->main_region_cells),
                    hint);
  throw UserError(spec.blocked_where,
                  fmt::format("{} are cut off by blocked cells from every pressure outlet: {}", region,
                              cut->touches_inlet ? "the velocity inlet that feeds them has no way out"
                                                 : "their pressure has no reference"),
                  hint);
}

}  // namespace quarry::cfdem
