// Vertex welding by a hash of cells twice the tolerance wide: a point's tolerance ball then
// touches at most 2 cells per axis, so each corner costs at most 8 hash look-ups
// (one when it coincides exactly with an earlier corner, the common case).
#include "geometry/vertex_welder.h"

#include <cmath>
#include <stdexcept>
#include <unordered_map>

namespace quarry {

namespace {

struct CellKey {
  std::int64_t i, j, k;
  bool operator==(const CellKey&) const = default;
};

struct CellKeyHash {
  std::size_t operator()(const CellKey& key) const {
    // Large odd multipliers spread neighbouring cells over the table (Teschner et al. 2003).
    const std::uint64_t h = static_cast<std::uint64_t>(key.i) * 73856093ULL ^
                            static_cast<std::uint64_t>(key.j) * 19349663ULL ^
                            static_cast<std::uint64_t>(key.k) * 83492791ULL;
    return static_cast<std::size_t>(h ^ (h >> 29));
  }
};

constexpr std::uint32_t end_of_list = 0xFFFFFFFFu;

}  // namespace

double default_weld_tolerance(std::span<const Vec3> points) {
  Aabb box;
  for (const Vec3& p : points) box.expand(p);
  if (box.empty()) return 0.0;
  return 1e-9 * norm(box.hi - box.lo);
}

WeldedMesh weld_triangle_soup(std::span<const Vec3> corners, double tolerance) {
  if (corners.size() % 3 != 0)
    throw std::invalid_argument("weld_triangle_soup: corner count is not a multiple of 3");
  WeldedMesh mesh;
  mesh.triangles.resize(corners.size() / 3);
  if (corners.empty()) return mesh;

  Aabb box;
  for (const Vec3& p : corners) box.expand(p);
  tolerance = std::max(tolerance, 0.0);
  // Cells are measured from the box corner so that cell indices stay small (≤ diagonal/cell).
  const double cell_size = tolerance > 0.0 ? 2.0 * tolerance : 1.0;
  const double tolerance2 = tolerance * tolerance;
  auto cell_index = [&](double coordinate, double origin) {
    return static_cast<std::int64_t>(std::floor((coordinate - origin) / cell_size));
  };

  std::unordered_map<CellKey, std::uint32_t, CellKeyHash> cell_head;  // cell → first vertex
  cell_head.reserve(corners.size());
  std::vector<std::uint32_t> next_in_cell;  // per welded vertex: next vertex in its cell
  mesh.vertices.reserve(corners.size() / 2);
  next_in_cell.reserve(corners.size() / 2);

  for (std::size_t c = 0; c < corners.size(); ++c) {
    const Vec3& p = corners[c];
    const CellKey own{cell_index(p.x, box.lo.x), cell_index(p.y, box.lo.y), cell_index(p.z, box.lo.z)};
    auto search_cell = [&](const CellKey& cell) {
      auto it = cell_head.find(cell);
      if (it == cell_head.end()) return end_of_list;
      for (std::uint32_t v = it->second; v != end_of_list; v = next_in_cell[v])
        if (norm2(mesh.vertices[v] - p) <= tolerance2) return v;
      return end_of_list;
    };
    // The point's own cell first: shared corners are usually bit-identical, so one look-up.
    std::uint32_t found = search_cell(own);
    const std::int64_t i0 = cell_index(p.x - tolerance, box.lo.x), i1 = cell_index(p.x + tolerance, box.lo.x);
    const std::int64_t j0 = cell_index(p.y - tolerance, box.lo.y), j1 = cell_index(p.y + tolerance, box.lo.y);
    const std::int64_t k0 = cell_index(p.z - tolerance, box.lo.z), k1 = cell_index(p.z + tolerance, box.lo.z);
    for (std::int64_t i = i0; i <= i1 && found == end_of_list; ++i)
      for (std::int64_t j = j0; j <= j1 && found == end_of_list; ++j)
        for (std::int64_t k = k0; k <= k1 && found == end_of_list; ++k)
          if (CellKey{i, j, k} != own) found = search_cell({i, j, k});
    if (found == end_of_list) {
      found = static_cast<std::uint32_t>(mesh.vertices.size());
      mesh.vertices.push_back(p);
      auto [it, inserted] = cell_head.try_emplace(own, found);
      next_in_cell.push_back(inserted ? end_of_list : it->second);
      it->second = found;
    }
    mesh.triangles[c / 3][c % 3] = found;
  }
  return mesh;
}

Surface surface_from_triangle_soup(std::span<const Vec3> corners, std::string name,
                                   double weld_tolerance) {
  const double tolerance = weld_tolerance >= 0.0 ? weld_tolerance : default_weld_tolerance(corners);
  WeldedMesh mesh = weld_triangle_soup(corners, tolerance);
  Surface surface;
  surface.name = std::move(name);
  surface.vertices = std::move(mesh.vertices);
  surface.triangles = std::move(mesh.triangles);
  surface.reference_vertices = surface.vertices;
  surface.vertex_velocities.assign(surface.vertices.size(), Vec3{});
  surface.update_normals_and_areas();
  surface.reset_loads();
  return surface;
}

}  // namespace quarry
