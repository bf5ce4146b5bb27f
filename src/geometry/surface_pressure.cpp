// Nodal and coarse-grained surface pressure (surface_pressure.h). Coarse graining after
// Weinhart, Thornton, Luding & Bokhove, "From discrete particles to continuum fields near a
// boundary", Granular Matter 14 (2012) 289–294: a contact force spread by a Gaussian of width
// ~ a particle gives a smooth stress field whose mean is the load per area.
#include "geometry/surface_pressure.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <unordered_map>

#include "core/hashed_cell.h"

namespace quarry {

namespace {

void require(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument(what);
}

// Cell key of a point for a grid of cell size `cell` (m); 21 bits per axis (wraps far away,
// which only merges distant cells: the distance test below stays exact).
std::uint64_t cell_key(long long ix, long long iy, long long iz) {
  constexpr std::uint64_t mask = (1u << 21) - 1;
  return (static_cast<std::uint64_t>(ix) & mask) | ((static_cast<std::uint64_t>(iy) & mask) << 21) |
         ((static_cast<std::uint64_t>(iz) & mask) << 42);
}

}  // namespace

std::vector<Vec3> vertex_normals(const Surface& surface) {
  std::vector<Vec3> normals(surface.vertex_count());
  for (std::size_t t = 0; t < surface.triangle_count(); ++t)
    for (const std::uint32_t v : surface.triangles[t])
      normals[v] += surface.triangle_normals[t] * surface.triangle_areas[t];
  for (Vec3& n : normals) {
    const double length = norm(n);
    n = length > 0.0 ? n / length : Vec3{};
  }
  return normals;
}

std::vector<double> tributary_areas(const Surface& surface) {
  std::vector<double> areas(surface.vertex_count(), 0.0);  // m²
  for (std::size_t t = 0; t < surface.triangle_count(); ++t)
    for (const std::uint32_t v : surface.triangles[t]) areas[v] += surface.triangle_areas[t] / 3.0;
  return areas;
}

std::vector<double> nodal_pressure(const Surface& surface, std::span<const Vec3> nodal_force) {
  require(nodal_force.size() == surface.vertex_count(),
          "nodal_pressure: surface '" + surface.name + "' has another number of vertices");
  const std::vector<Vec3> normals = vertex_normals(surface);
  const std::vector<double> areas = tributary_areas(surface);
  std::vector<double> pressure(surface.vertex_count(), 0.0);  // Pa
  for (std::size_t v = 0; v < pressure.size(); ++v)
    if (areas[v] > 0.0) pressure[v] = -dot(nodal_force[v], normals[v]) / areas[v];
  return pressure;
}

bool PressureSmoother::made_for(const Surface& surface, double width) const {
  return width == width_ && surface.vertices.size() == vertices_.size() &&
         surface.triangle_count() == triangles_ &&
         std::equal(vertices_.begin(), vertices_.end(), surface.vertices.begin(),
                    [](const Vec3& a, const Vec3& b) {
                      return a.x == b.x && a.y == b.y && a.z == b.z;
                    });
}

void PressureSmoother::make(const Surface& surface, double width) {
  require(width > 0.0 && std::isfinite(width), "coarse_grained_pressure: the width must be > 0");
  const double cutoff = 3.0 * width;  // m
  const double min_cosine = 0.5;      // cos 60°
  const auto axis_cell = [cutoff](double coordinate) { return hashed_cell(coordinate / cutoff); };
  const auto cell_of = [&axis_cell](const Vec3& x) {
    return cell_key(axis_cell(x.x), axis_cell(x.y), axis_cell(x.z));
  };
  std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> cells;  // vertices per cell
  for (std::size_t v = 0; v < surface.vertex_count(); ++v)
    cells[cell_of(surface.vertices[v])].push_back(static_cast<std::uint32_t>(v));
  const std::vector<Vec3> normals = vertex_normals(surface);
  areas_ = tributary_areas(surface);
  offsets_.assign(1, 0);
  neighbours_.clear();
  weights_.clear();
  weighted_areas_.assign(surface.vertex_count(), 0.0);
  for (std::size_t u = 0; u < surface.vertex_count(); ++u) {
    const Vec3& x = surface.vertices[u];
    const std::int64_t cx = axis_cell(x.x), cy = axis_cell(x.y), cz = axis_cell(x.z);
    double weighted_area = 0.0;  // m² (times the kernel)
    for (std::int64_t dx = -1; dx <= 1; ++dx)
      for (std::int64_t dy = -1; dy <= 1; ++dy)
        for (std::int64_t dz = -1; dz <= 1; ++dz) {
          const auto cell = cells.find(cell_key(cx + dx, cy + dy, cz + dz));
          if (cell == cells.end()) continue;
          for (const std::uint32_t v : cell->second) {
            const double r2 = norm2(surface.vertices[v] - x);  // m²
            if (r2 >= cutoff * cutoff || dot(normals[v], normals[u]) < min_cosine) continue;
            const double weight = std::exp(-0.5 * r2 / (width * width));
            neighbours_.push_back(v);
            weights_.push_back(weight);
            weighted_area += weight * areas_[v];
          }
        }
    weighted_areas_[u] = weighted_area;
    offsets_.push_back(neighbours_.size());
  }
  vertices_ = surface.vertices;
  triangles_ = surface.triangle_count();
  width_ = width;
}

std::vector<double> PressureSmoother::smooth(const Surface& surface,
                                             std::span<const double> nodal_pressure, double width) {
  require(nodal_pressure.size() == surface.vertex_count(),
          "coarse_grained_pressure: surface '" + surface.name + "' has another number of vertices");
  if (!made_for(surface, width)) make(surface, width);
  std::vector<double> pressure(surface.vertex_count(), 0.0);  // Pa
  for (std::size_t u = 0; u < pressure.size(); ++u) {
    double weighted_force = 0.0;  // N (times the kernel)
    for (std::size_t k = offsets_[u]; k < offsets_[u + 1]; ++k) {
      const std::uint32_t v = neighbours_[k];
      weighted_force += weights_[k] * nodal_pressure[v] * areas_[v];
    }
    if (weighted_areas_[u] > 0.0) pressure[u] = weighted_force / weighted_areas_[u];
  }
  return pressure;
}

std::vector<double> coarse_grained_pressure(const Surface& surface,
                                            std::span<const double> nodal_pressure, double width) {
  return PressureSmoother().smooth(surface, nodal_pressure, width);
}

}  // namespace quarry
