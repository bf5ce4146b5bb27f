#include "sim/memory_estimate.h"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "geometry/primitives.h"
#include "insert/size_distribution.h"
#include "sim/world.h"

namespace quarry::sim {
namespace {

// Triangles of an STL file from its size, without reading it: a binary file whose size is
// 84 + 50 n for the count n in its header has n; otherwise it is text, and the shortest facet
// ("facet normal 0 0 0 outer loop vertex 0 0 0 …endfacet") takes about 85 bytes, so size / 85
// bounds the count from above. A file that cannot be read counts 0 (the reader reports it).
double stl_triangles(const std::string& path) {
  std::error_code error;
  const auto size = std::filesystem::file_size(path, error);
  if (error) return 0.0;
  std::ifstream in(path, std::ios::binary);
  char header[84] = {};
  if (size >= 84 && in.read(header, 84)) {
    std::uint32_t count = 0;
    std::memcpy(&count, header + 80, 4);
    if (size == 84 + 50 * static_cast<std::uint64_t>(count)) return count;
  }
  return static_cast<double>(size) / 85.0;
}

double surface_triangles(const SurfaceSpec& s) {
  switch (s.kind.value) {
    case SurfaceKind::stl:
      return stl_triangles(s.file.value);
    case SurfaceKind::mesh:
      return static_cast<double>(s.mesh_triangles.size() + 2 * s.mesh_quads.size());
    case SurfaceKind::plane:
      return 2.0;
    case SurfaceKind::box:
      return 12.0;
    case SurfaceKind::cylinder:
      return static_cast<double>(cylinder_triangle_count(s.radius.value, s.length.value,
                                                         s.resolution.value, s.capped.value));
  }
  return 0.0;
}

// Particles a factory makes: its count, or its mass over the mean particle mass of its type.
double factory_particles(const SimulationSpec& spec, const FactorySpec& f) {
  if (f.target_count) return static_cast<double>(f.target_count->value);
  if (!f.target_mass) return 0.0;
  for (const ParticleTypeInfo& t : particle_type_infos(spec)) {
    if (spec.particle_types[t.type_index].name.value != f.particle_type.value) continue;
    const double mass = SizeSampler(t.size).mean_particle_mass(t.density);  // kg
    return mass > 0.0 ? f.target_mass->value / mass : 0.0;
  }
  return 0.0;
}

}  // namespace

std::string format_bytes(double bytes) {
  if (bytes < 1e9) return fmt::format("{:.0f} MB", bytes / 1e6);
  if (bytes < 1e12) return fmt::format("{:.3g} GB", bytes / 1e9);
  return fmt::format("{:.3g} TB", bytes / 1e12);
}

MemoryEstimate estimate_memory(const SimulationSpec& spec) {
  MemoryEstimate e;
  const auto consider = [&e](double bytes, std::string what, SourceLocation where) {
    if (bytes > e.largest_bytes)
      e.largest_bytes = bytes, e.largest = std::move(what), e.largest_where = where;
  };
  for (const FactorySpec& f : spec.factories) {
    const double n = factory_particles(spec, f);
    e.particles += n;
    consider(n * kBytesPerParticle, fmt::format("factory '{}' ({:.3g} particles)", f.name.value, n),
             f.target_count  ? f.target_count->where
             : f.target_mass ? f.target_mass->where
                             : f.name.where);
  }
  for (const SurfaceSpec& s : spec.surfaces) {
    const double n = surface_triangles(s);
    e.triangles += n;
    consider(n * kBytesPerTriangle, fmt::format("surface '{}' ({:.3g} triangles)", s.name.value, n),
             s.kind.value == SurfaceKind::cylinder ? s.resolution.where
             : s.kind.value == SurfaceKind::stl    ? s.file.where
                                                   : s.name.where);
  }
  e.bytes = kBaseBytes + e.particles * kBytesPerParticle + e.triangles * kBytesPerTriangle;
  return e;
}

std::uint64_t machine_memory_bytes() {
  const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGESIZE);
  std::uint64_t bytes = pages > 0 && page > 0
                            ? static_cast<std::uint64_t>(pages) * static_cast<std::uint64_t>(page)
                            : std::uint64_t{0};
  // A container's limit (cgroup v2 memory.max, or v1 limit_in_bytes): "max" or a number.
  for (const char* path :
       {"/sys/fs/cgroup/memory.max", "/sys/fs/cgroup/memory/memory.limit_in_bytes"}) {
    std::ifstream in(path);
    std::uint64_t limit = 0;
    if (in >> limit && limit > 0 && (bytes == 0 || limit < bytes)) bytes = limit;
  }
  return bytes;
}

MemoryEstimate refuse_if_it_cannot_fit(const SimulationSpec& spec, std::uint64_t available) {
  const MemoryEstimate e = estimate_memory(spec);
  if (available == 0 || e.bytes <= static_cast<double>(available)) return e;
  throw UserError(
      e.largest_where,
      fmt::format(
          "this deck needs about {} of memory ({:.3g} particles at {:.0f} B, {:.3g} triangles at "
          "{:.0f} B), more than this machine's {}; the largest part is {}",
          format_bytes(e.bytes), e.particles, kBytesPerParticle, e.triangles, kBytesPerTriangle,
          format_bytes(static_cast<double>(available)), e.largest),
      "fewer or larger particles, a coarser mesh (resolution, fewer STL facets), or a machine with "
      "more "
      "memory (docs/errors.md, \"Memory\")");
}

}  // namespace quarry::sim
