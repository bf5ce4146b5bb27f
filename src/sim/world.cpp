// Builds a World from a SimulationSpec: materials and their pair table, surfaces (STL files or
// primitives) with topology and search grids, factories, and the time step.
#include "sim/world.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "geometry/motion.h"
#include "geometry/primitives.h"
#include "geometry/stl_reader.h"
#include "insert/size_distribution.h"
#include "sim/time_step_choice.h"

namespace quarry {

namespace {

std::size_t material_index(const SimulationSpec& spec, const std::string& name) {
  for (std::size_t k = 0; k < spec.materials.size(); ++k)
    if (spec.materials[k].name.value == name) return k;
  return spec.materials.size();
}

MaterialTable build_material_table(const SimulationSpec& spec) {
  MaterialTable table;
  const std::size_t n = spec.materials.size();
  for (const auto& m : spec.materials) {
    table.names.push_back(m.name.value);
    table.properties.push_back({m.density.value, m.youngs_modulus.value, m.poisson_ratio.value});
  }
  table.pairs.resize(n * n);
  std::vector<char> defined(n * n, 0);
  for (const auto& inter : spec.interactions) {
    const std::size_t a = material_index(spec, inter.material_a.value);
    const std::size_t b = material_index(spec, inter.material_b.value);
    if (a >= n || b >= n) continue;  // the deck parser reports unknown names
    const InteractionParameters p = make_interaction(table.properties[a], table.properties[b], inter);
    table.pairs[a * n + b] = p;
    table.pairs[b * n + a] = p;
    defined[a * n + b] = defined[b * n + a] = 1;
  }
  // Pairs the deck did not define keep neutral defaults (the parser already demanded every pair
  // that can meet; these are pairs that never touch).
  for (std::size_t a = 0; a < n; ++a)
    for (std::size_t b = 0; b < n; ++b)
      if (!defined[a * n + b])
        table.pairs[a * n + b] = make_interaction(table.properties[a], table.properties[b], InteractionSpec{});
  return table;
}

Surface make_surface(const SurfaceSpec& s) {
  switch (s.kind.value) {
    case SurfaceKind::stl: return read_stl(s.file.value, s.scale.value, s.offset.value);
    case SurfaceKind::plane: return make_plane(s.point.value, s.normal.value, s.size.value, 1);
    case SurfaceKind::box: return make_box(s.min.value, s.max.value, 1);
    case SurfaceKind::cylinder:
      return make_cylinder(s.base.value, s.axis.value, s.radius.value, s.length.value,
                           s.resolution.value, s.capped.value, true);
  }
  return {};
}

}  // namespace

std::vector<ParticleTypeInfo> particle_type_infos(const SimulationSpec& spec) {
  std::vector<ParticleTypeInfo> infos;
  for (std::size_t t = 0; t < spec.particle_types.size(); ++t) {
    const auto& type = spec.particle_types[t];
    const std::size_t m = material_index(spec, type.material.value);
    ParticleTypeInfo info;
    info.type_index = static_cast<std::uint16_t>(t);
    info.material_index = static_cast<std::uint16_t>(m);
    info.density = m < spec.materials.size() ? spec.materials[m].density.value : 0.0;
    info.size = type.size;
    infos.push_back(info);
  }
  return infos;
}

bool World::has_moving_surfaces() const {
  return std::any_of(motions.begin(), motions.end(),
                     [](const MotionSpec& m) { return m.kind.value != MotionKind::none; });
}

std::size_t World::pair_contact_count() const {
  // The force stage's own test (contact_law.h): |xi − xj|² < (Ri + Rj)².
  std::size_t count = 0;
  const std::size_t n = pairs.offsets.empty() ? 0 : pairs.offsets.size() - 1;
  for (std::size_t i = 0; i < n && i < particles.size(); ++i)
    for (std::uint32_t k = pairs.offsets[i]; k < pairs.offsets[i + 1]; ++k) {
      const std::uint32_t j = pairs.partner[k];
      const double touch = particles.radius[i] + particles.radius[j];  // m
      count += norm2(particles.position[i] - particles.position[j]) < touch * touch;
    }
  return count;
}

std::size_t World::wall_contact_count() const { return wall_contacts.size(); }

void reindex_wall_contacts(World& world, const std::vector<std::size_t>& order) {
  std::vector<std::uint32_t> new_index(order.size());
  for (std::size_t k = 0; k < order.size(); ++k) new_index[order[k]] = static_cast<std::uint32_t>(k);
  for (WallContact& c : world.wall_contacts) c.particle = new_index[c.particle];
  std::stable_sort(world.wall_contacts.begin(), world.wall_contacts.end(),
                   [](const WallContact& a, const WallContact& b) { return a.particle < b.particle; });
}

void drop_wall_contacts_of_removed(World& world, const std::vector<char>& removed) {
  std::vector<std::uint32_t> new_index(removed.size());
  std::uint32_t kept = 0;
  for (std::size_t i = 0; i < removed.size(); ++i) {
    new_index[i] = kept;
    kept += removed[i] ? 0 : 1;
  }
  std::erase_if(world.wall_contacts, [&](const WallContact& c) { return removed[c.particle] != 0; });
  for (WallContact& c : world.wall_contacts) c.particle = new_index[c.particle];
}

World build_world(const SimulationSpec& spec) {
  World world;
  world.spec = spec;
  world.materials = build_material_table(spec);
  // Rolling-torque history exists only for the EPSD model (contact_law.h).
  world.pairs.keep_rolling_history =
      std::any_of(world.materials.pairs.begin(), world.materials.pairs.end(),
                  [](const InteractionParameters& p) { return p.rolling_model == RollingModel::epsd; });
  world.types = particle_type_infos(spec);
  for (const auto& t : spec.particle_types) world.type_names.push_back(t.name.value);

  // Time step (throws with the deck location if the contact time is under-resolved).
  const TimeStepChoice choice = choose_time_step(spec);
  Diagnostics problems;
  for (const auto& d : choice.problems)
    if (d.severity == Severity::error) problems.error(d.where, d.message, d.hint);
  if (problems.has_errors()) throw UserError(problems);
  for (const auto& d : choice.problems)
    if (d.severity == Severity::warning) world.warnings.push_back(d.message);
  world.dt = choice.dt;

  // Largest and smallest radius any particle can have (m): sizes the grids and the skin.
  double min_radius = 1e300;
  for (const auto& t : spec.particle_types) {
    SizeSampler sampler(t.size);
    world.max_radius = std::max(world.max_radius, sampler.max_radius());
    min_radius = std::min(min_radius, sampler.min_radius());
  }
  if (world.max_radius <= 0.0) world.max_radius = 1e-3;
  if (min_radius > 1e299) min_radius = world.max_radius;
  // Verlet skin: 10 % of the smallest diameter unless the deck says otherwise.
  world.skin = spec.simulation.skin.value >= 0.0 ? spec.simulation.skin.value : 0.2 * min_radius;

  for (const auto& s : spec.surfaces) {
    Surface surface = make_surface(s);
    surface.name = s.name.value;
    surface.material = static_cast<std::uint16_t>(material_index(spec, s.material.value));
    surface.conveyor_velocity = s.conveyor_velocity.value;
    surface.export_loads = s.export_loads.value;
    surface.reset_loads();
    world.motions.push_back(s.motion);
    if (s.motion.kind.value != MotionKind::none) apply_motion(s.motion, 0.0, surface);
    world.topologies.push_back(build_topology(surface));
    world.surfaces.push_back(std::move(surface));
  }
  // Surface search grids: cells about one particle diameter plus skin (static surfaces keep
  // theirs for the whole run; moving ones are rebuilt with the lists).
  world.grids.resize(world.surfaces.size());
  world.candidates.vertices_at_build.resize(world.surfaces.size());
  for (std::size_t s = 0; s < world.surfaces.size(); ++s) {
    world.grids[s].build(world.surfaces[s], 2.0 * world.max_radius + world.skin);
    world.candidates.vertices_at_build[s] = world.surfaces[s].vertices;
  }

  for (std::size_t f = 0; f < spec.factories.size(); ++f) {
    const auto& fs = spec.factories[f];
    std::size_t type = 0;
    while (type < spec.particle_types.size() && spec.particle_types[type].name.value != fs.particle_type.value) ++type;
    if (type >= world.types.size()) continue;
    // Each factory gets its own random stream derived from the deck seed.
    world.factories.emplace_back(fs, world.types[type], spec.simulation.seed + 0x9E3779B97F4A7C15ull * (f + 1));
  }
  // Factories are polled every 2 ms of simulated time (or every step if dt is larger).
  world.insertion_interval_steps = std::max(1, static_cast<int>(std::lround(2e-3 / world.dt)));
  return world;
}

}  // namespace quarry
