// The particles a run starts from (deck `particles:`, issue #20), placed into the built world
// through sim::add_particles, and checked where the deck parser could not: radius within the
// type's sizes (the time step and the grids are sized from them), inside the domain, and no
// overlap with each other or with a surface unless the entry allows it.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <unordered_map>

#include "geometry/surface_contact.h"
#include "insert/size_distribution.h"
#include "neighbor/pair_list.h"
#include "sim/exchange.h"
#include "sim/world.h"

namespace quarry {

namespace {

constexpr int kMaxReported = 10;  // overlaps reported one by one; the rest counted
// Overlaps up to this fraction of the smaller radius are contacts, not mistakes: a bed settled
// by an earlier run rests on them (the Hertz overlap under a bed's weight is ~0.1 % of R for
// E ≥ 1e7 Pa; 1 % is the usual DEM ceiling for an accurate contact). Above it, a wrong unit, a
// repeated row or a misplaced particle is far more likely than a physical contact.
constexpr double kContactOverlapFraction = 0.01;

std::string millimetres(double metres) {
  return fmt::format("{:.4g} mm", metres * 1e3);
}

// Where a particle was given and how to name it in a message.
struct Origin {
  SourceLocation where;
  std::string name;
};

Origin origin_of(const SimulationSpec& spec, const InitialParticle& p, ParticleId id) {
  const ParticleSourceSpec& source = spec.particle_sources.at(p.source);
  if (source.file.value.empty())
    return {source.where, fmt::format("the particle of the entry on line {}", source.where.line)};
  const std::string file = std::filesystem::path(source.file.value).filename().string();
  if (p.line > 0)
    return {{source.file.value, static_cast<int>(p.line), 1},
            fmt::format("the particle on line {} of {}", p.line, file)};
  return {source.file.where, fmt::format("particle id {} of {}", id, file)};
}

const char* const kOverlapHint =
    "overlaps above 1 % of the smaller radius are refused (a settled bed's contacts are far "
    "below): move the "
    "particles apart, or set allow_overlap: true on the particles entry (they then start with "
    "large repulsive forces)";

}  // namespace

void place_initial_particles(World& world) {
  const SimulationSpec& spec = world.spec;
  const std::vector<InitialParticle>& given = spec.initial_particles;
  if (given.empty()) return;
  Diagnostics problems;
  // Radius inside its type's size range, centre inside the domain: the grids, the skin and the
  // time step were chosen for these.
  const Aabb& domain = spec.simulation.domain.value;
  for (const InitialParticle& p : given) {
    if (problems.all().size() >= kMaxReported) break;
    const ParticleTypeSpec& type = spec.particle_types.at(p.type);
    const SizeSampler sizes(type.size);
    const double lowest = sizes.min_radius() * (1.0 - 1e-12),
                 highest = sizes.max_radius() * (1.0 + 1e-12);  // m
    const Origin origin = origin_of(spec, p, p.id);
    if (p.radius > 0.0 && (p.radius < lowest || p.radius > highest))
      problems.error(
          origin.where,
          fmt::format("{}: radius {} is outside the sizes of particle type \"{}\" ({} to {})",
                      origin.name, millimetres(p.radius), type.name.value,
                      millimetres(sizes.min_radius()), millimetres(sizes.max_radius())),
          "the time step and the neighbour grid are sized from the particle types' size "
          "distributions: "
          "widen the type's size (e.g. distribution: uniform, min_radius, max_radius) to cover it");
    if (!domain.empty() && !domain.contains(p.position))
      problems.error(origin.where,
                     fmt::format("{}: centre [{:.6g}, {:.6g}, {:.6g}] m is outside the domain",
                                 origin.name, p.position.x, p.position.y, p.position.z),
                     "enlarge simulation.domain or move the particle into it");
  }
  if (problems.has_errors()) throw UserError(problems);

  // Ids given by files must not repeat across the entries (each file checked its own).
  std::unordered_map<ParticleId, std::size_t> first_with_id;
  for (std::size_t k = 0; k < given.size() && problems.all().size() < kMaxReported; ++k) {
    if (given[k].id == 0) continue;
    const auto [entry, inserted] = first_with_id.emplace(given[k].id, k);
    if (inserted) continue;
    const Origin here = origin_of(spec, given[k], given[k].id),
                 first = origin_of(spec, given[entry->second], given[k].id);
    problems.error(here.where,
                   fmt::format("{} has id {}, as {} has", here.name, given[k].id, first.name),
                   "ids are kept from the files, so two files cannot share one: start from one of "
                   "them, or drop "
                   "the id column of a CSV table (new ids are then given)");
  }
  if (problems.has_errors()) throw UserError(problems);

  const std::size_t first_index = world.particles.size();
  std::vector<sim::NewParticle> added(given.size());
  for (std::size_t k = 0; k < given.size(); ++k) {
    const InitialParticle& p = given[k];
    added[k] = {p.type, p.position, p.velocity, p.angular_velocity, p.radius, p.id};
  }
  sim::add_particles(world, added);

  // Overlaps between the particles: pairs from the neighbour grid with no skin, i.e. those with
  // |xi − xj| < Ri + Rj (neighbor/pair_list.h), O(n).
  const ParticleStore& store = world.particles;
  const auto allows = [&](std::size_t index) {
    return index < first_index ||
           spec.particle_sources[given[index - first_index].source].allow_overlap.value;
  };
  const auto origin_at = [&](std::size_t index) {
    return origin_of(spec, given[index - first_index], store.id[index]);
  };
  std::size_t overlaps = 0;
  PairList pairs;
  pairs.keep_rolling_history = false;
  pairs.periodic = world.pairs.periodic;  // pairs across the periodic faces too
  build_pair_list(store, 0.0, pairs);
  for (std::size_t i = 0; i + 1 < pairs.offsets.size(); ++i)
    for (std::uint32_t k = pairs.offsets[i]; k < pairs.offsets[i + 1]; ++k) {
      const std::size_t j = pairs.partner[k];
      if (allows(i) || allows(j)) continue;
      const double overlap =
          store.radius[i] + store.radius[j] -
          norm(pairs.periodic.minimum_image(store.position[i] - store.position[j]));  // m
      if (!(overlap > kContactOverlapFraction * std::min(store.radius[i], store.radius[j])))
        continue;
      if (++overlaps > kMaxReported) continue;
      const Origin a = origin_at(std::min(i, j)), b = origin_at(std::max(i, j));
      problems.error(a.where,
                     fmt::format("{} and {} overlap by {}", a.name, b.name, millimetres(overlap)),
                     kOverlapHint);
    }
  // Overlaps with the surfaces: each particle's box against the surfaces' search grids.
  std::vector<std::uint32_t> candidates;
  std::vector<SurfaceContact> contacts;
  for (std::size_t i = first_index; i < store.size(); ++i) {
    if (allows(i)) continue;
    const double r = store.radius[i];  // m
    Aabb box;
    box.lo = store.position[i] - Vec3{r, r, r};
    box.hi = store.position[i] + Vec3{r, r, r};
    for (const WorldSurface& surface : world.surfaces) {
      surface.grid.query(box, candidates);
      find_surface_contacts(surface.mesh, surface.topology, store.position[i], r, candidates,
                            contacts);
      if (contacts.empty()) continue;
      const double deepest =
          std::max_element(contacts.begin(), contacts.end(), [](const auto& a, const auto& b) {
            return a.overlap < b.overlap;
          })->overlap;
      if (!(deepest > kContactOverlapFraction * r)) continue;
      if (++overlaps > kMaxReported) break;
      const Origin a = origin_at(i);
      problems.error(a.where,
                     fmt::format("{} overlaps surface \"{}\" by {}", a.name, surface.mesh.name,
                                 millimetres(deepest)),
                     kOverlapHint);
      break;
    }
  }
  if (overlaps > kMaxReported)
    problems.error(
        spec.particle_sources.front().where,
        fmt::format("{} overlaps in all, the first {} reported above", overlaps, kMaxReported),
        kOverlapHint);
  if (problems.has_errors()) throw UserError(problems);
}

}  // namespace quarry
