// Stages that change what exists or where it is: the surfaces' drivers, factories, removal of
// particles that left the domain, spatial re-sorting and list rebuilds.
#include <fmt/format.h>
#include <omp.h>

#include <algorithm>
#include <cmath>

#include "geometry/motion.h"
#include "neighbor/spatial_sort.h"
#include "sim/step.h"

namespace quarry::sim {

namespace {

// Largest displacement (m) of any vertex of a moving surface since the lists were built.
double max_surface_displacement(const World& world) {
  double worst = 0.0;
  for (const WorldSurface& s : world.surfaces) {
    if (!s.moving()) continue;
    const auto& now = s.mesh.vertices;
    if (s.vertices_at_build.size() != now.size()) return 1e300;
    for (std::size_t v = 0; v < now.size(); ++v)
      worst = std::max(worst, norm2(now[v] - s.vertices_at_build[v]));
  }
  return std::sqrt(worst);
}

// Candidate triangles: those whose bounding box comes within (R + skin) of the particle.
// Each thread collects a contiguous range of particles; the ranges are concatenated in order,
// so the result does not depend on the thread count.
void build_surface_candidates(World& world) {
  const ParticleStore& p = world.particles;
  const std::size_t n = p.size();
  SurfaceCandidates& c = world.candidates;
  for (WorldSurface& s : world.surfaces) {
    if (!s.moving()) continue;
    s.vertices_at_build = s.mesh.vertices;
    build_search_grid(world, s);
  }
  c.particles.clear();
  c.offsets.assign(1, 0);
  c.surface.clear();
  c.triangle.clear();
  if (world.surfaces.empty()) return;
  struct Found {
    std::vector<std::uint32_t> particles, counts, triangles;
    std::vector<std::uint16_t> surfaces;
  };
  const int thread_count = world.threading.team(n);
  std::vector<Found> found(static_cast<std::size_t>(thread_count));
#pragma omp parallel num_threads(thread_count)
  {
    const int threads = omp_get_num_threads(), t = omp_get_thread_num();
    Found& mine = found[t];
    std::vector<std::uint32_t> hits;
    for (std::size_t i = n * t / threads; i < n * (t + 1) / threads; ++i) {
      const double reach = p.radius[i] + world.skin;
      Aabb box;
      box.lo = p.position[i] - Vec3{reach, reach, reach};
      box.hi = p.position[i] + Vec3{reach, reach, reach};
      std::uint32_t count = 0;
      for (std::size_t s = 0; s < world.surfaces.size(); ++s) {
        world.surfaces[s].grid.query(box, hits);
        const Surface& surface = world.surfaces[s].mesh;
        for (std::uint32_t tri : hits) {
          // Exact test against the triangle's own box, so the set does not depend on the grid.
          Aabb tb;
          for (int k = 0; k < 3; ++k) tb.expand(surface.vertices[surface.triangles[tri][k]]);
          if (tb.lo.x > box.hi.x || tb.hi.x < box.lo.x || tb.lo.y > box.hi.y ||
              tb.hi.y < box.lo.y || tb.lo.z > box.hi.z || tb.hi.z < box.lo.z)
            continue;
          mine.surfaces.push_back(static_cast<std::uint16_t>(s));
          mine.triangles.push_back(tri);
          ++count;
        }
      }
      if (count > 0) {
        mine.particles.push_back(static_cast<std::uint32_t>(i));
        mine.counts.push_back(count);
      }
    }
  }
  for (const Found& f : found) {
    c.particles.insert(c.particles.end(), f.particles.begin(), f.particles.end());
    for (std::uint32_t count : f.counts) c.offsets.push_back(c.offsets.back() + count);
    c.surface.insert(c.surface.end(), f.surfaces.begin(), f.surfaces.end());
    c.triangle.insert(c.triangle.end(), f.triangles.begin(), f.triangles.end());
  }
}

// The surface candidates of the particles left after removing those flagged (by index),
// renumbered as ParticleStore::remove_flagged renumbers them (keeping the order).
void remove_from_candidates(SurfaceCandidates& c, const std::vector<char>& removed) {
  const std::vector<std::uint32_t> new_index = indices_after_removal(removed);
  // In place, front to back: entries only move to lower positions. The rows before the first
  // removed particle's stay as they are (same index, same place).
  const auto first = static_cast<std::uint32_t>(first_removed(removed));
  std::size_t rows = 0;
  while (rows < c.particles.size() && c.particles[rows] < first) ++rows;
  std::size_t entries = c.offsets[rows];
  for (std::size_t q = rows; q < c.particles.size(); ++q) {
    const std::uint32_t i = c.particles[q], begin = c.offsets[q], end = c.offsets[q + 1];
    if (removed[i]) continue;
    c.offsets[rows] = static_cast<std::uint32_t>(entries);
    c.particles[rows++] = new_index[i];
    for (std::uint32_t e = begin; e < end; ++e, ++entries) {
      c.surface[entries] = c.surface[e];
      c.triangle[entries] = c.triangle[e];
    }
  }
  c.particles.resize(rows);
  c.offsets.resize(rows + 1);
  c.offsets[rows] = static_cast<std::uint32_t>(entries);
  c.surface.resize(entries);
  c.triangle.resize(entries);
}

// Particles flagged (by index) are about to leave the store: the lists drop them instead of
// being rebuilt (what stays listed is what a build at the last build's positions would list,
// and the rebuild criterion goes on from there). Lists already stale stay stale.
void remove_from_lists(World& world, const std::vector<char>& removed) {
  if (world.lists_stale || !world.pairs.built_for(removed.size())) {
    world.lists_stale = true;
    return;
  }
  remove_from_pair_list(world.pairs, removed);
  remove_from_candidates(world.candidates, removed);
}

}  // namespace

void drive_surfaces(World& world, double time) {
  for (WorldSurface& s : world.surfaces) {
    SurfaceDriver& driver = s.driver;
    switch (driver.kind) {
      case SurfaceDriverKind::fixed:
        break;
      case SurfaceDriverKind::prescribed:
        apply_motion(driver.motion, time, s.mesh);
        break;
      case SurfaceDriverKind::coupled: {
        if (driver.set_positions.empty()) break;      // nothing set yet: the surface rests
        const double since = time - driver.set_time;  // s
        for (std::size_t v = 0; v < s.mesh.vertices.size(); ++v) {
          s.mesh.vertices[v] = driver.set_positions[v] + driver.set_velocities[v] * since;
          s.mesh.vertex_velocities[v] = driver.set_velocities[v];
        }
        s.mesh.update_normals_and_areas();
        break;
      }
    }
  }
}

void set_surface_vertices(World& world, std::size_t surface, std::span<const Vec3> positions,
                          std::span<const Vec3> velocities) {
  WorldSurface& s = world.surfaces.at(surface);
  const std::size_t n = s.mesh.vertex_count();
  if (s.driver.kind != SurfaceDriverKind::coupled)
    throw std::logic_error("surface '" + s.mesh.name +
                           "' is not coupled; its vertices are moved by its own driver");
  if (positions.size() != n || (!velocities.empty() && velocities.size() != n))
    throw std::invalid_argument("surface '" + s.mesh.name + "' has " + std::to_string(n) +
                                " vertices");
  s.driver.set_positions.assign(positions.begin(), positions.end());
  if (velocities.empty())
    s.driver.set_velocities.assign(n, Vec3{});
  else
    s.driver.set_velocities.assign(velocities.begin(), velocities.end());
  s.driver.set_time = world.time;
  // The surface is where the partner says now: the state between steps is complete.
  s.mesh.vertices = s.driver.set_positions;
  s.mesh.vertex_velocities = s.driver.set_velocities;
  s.mesh.update_normals_and_areas();
}

void insert_and_remove(World& world) {
  const ParticleStore& p = world.particles;
  const Aabb domain = world.pairs.periodic.removal_bounds(world.spec.simulation.domain.value);
  // One parallel pass to see whether anything left (almost never).
  const std::size_t n = p.size();
  bool any = false;
  if (!domain.empty()) {
#pragma omp parallel for schedule(static) num_threads(world.threading.team(n)) reduction(|| : any)
    for (std::size_t i = 0; i < n; ++i) any = any || !domain.contains(p.position[i]);
  }
  DriftScan scan;
  scan.particles = n;
  scan.first_non_finite = n;
  scan.any_outside = any;
  insert_and_remove(world, scan);
}

void insert_and_remove(World& world, const DriftScan& scan) {
  ParticleStore& p = world.particles;
  // Particles outside the domain are removed and counted (guard 11): flags only if any left.
  // Not along periodic axes: those particles are wrapped at the list build (rebuild_lists).
  const Aabb domain = world.pairs.periodic.removal_bounds(world.spec.simulation.domain.value);
  if (!domain.empty()) {
    const std::size_t n = p.size();
    if (scan.any_outside) {
      std::vector<char> outside(n, 0);
      for (std::size_t i = 0; i < n; ++i) outside[i] = !domain.contains(p.position[i]);
      world.removed_outside +=
          static_cast<std::uint64_t>(std::count(outside.begin(), outside.end(), 1));
      drop_wall_contacts_of_removed(world, outside);
      remove_from_lists(world, outside);
      p.remove_flagged(outside);
    }
  }
  if (world.factories.empty() || world.step_count % world.insertion_interval_steps != 0) return;
  const auto touches_surface = [&world](const Vec3& centre, double radius) {
    std::vector<std::uint32_t> all;
    std::vector<SurfaceContact> contacts;
    for (const WorldSurface& s : world.surfaces) {
      Aabb box;
      // The grid of a moving surface is from the last rebuild: widen the query by the skin.
      const double reach = radius + world.skin;
      box.lo = centre - Vec3{reach, reach, reach};
      box.hi = centre + Vec3{reach, reach, reach};
      s.grid.query(box, all);
      find_surface_contacts(s.mesh, s.topology, centre, radius, all, contacts);
      if (!contacts.empty()) return true;
    }
    return false;
  };
  const std::atomic<int>* stop = world.stop_request;
  const auto stop_requested = [stop] { return stop && stop->load(std::memory_order_relaxed) != 0; };
  for (auto& factory : world.factories) {
    const InsertionReport report =
        factory.insert_due(world.time, p, world.next_id, touches_surface, stop_requested);
    if (report.inserted > 0) world.lists_stale = true;
  }
}

namespace {

// Periodic axes: every particle that has left [min, max) along one re-enters at the other
// side. Done here, when the lists are rebuilt, and nowhere else: between builds a particle is
// at most skin/2 outside, which the minimum-image separations of the pair stages and the
// unbounded removal test tolerate, and the list's reference positions (the rebuild criterion)
// are the wrapped ones taken just after. A wrapped position is simply the position, so
// checkpoints and thread counts see nothing special. Particles inside are not touched.
void wrap_into_period(World& world) {
  const PeriodicBox& box = world.pairs.periodic;
  if (!box.any()) return;
  ParticleStore& p = world.particles;
  const std::size_t n = p.size();
  Vec3* const position = p.position.data();
#pragma omp parallel for schedule(static) num_threads(world.threading.team(n))
  for (std::size_t i = 0; i < n; ++i) position[i] = box.wrapped(position[i]);
}

// The skin of the lists about to be built unless the deck fixes one (issue 21: a fixed 10 % of
// the smallest diameter made a pour rebuild every 4 steps; 30 % ran the flagship in 0.77 of
// the time). A skin s costs two ways per step: a build every s / (2u)
// steps, u (m) the largest move per step, at c_b per particle; and the listed pairs, whose
// count beyond the contacts grows about as 12 φ s / d per particle (a shell of width s around
// spheres of diameter d at packing φ ≈ 0.6), at c_p each. The sum is least at
// s² = u d c_b / (6 φ c_p); c_b / c_p ≈ 40 (a build ≈ 40 listed pair-steps per particle; from
// the hopper's and the flagship's best measured skins, docs/performance.md) gives
// s = √(11 u d). u is the fastest particle's speed × dt, or half the sum with the fastest
// moving surface's (its triangles are re-listed at d + s > skin). Read from the state alone:
// the same skin for any thread count and after a restart.
double automatic_skin(const World& world) {
  const World::SkinChoice& choice = world.skin_choice;
  const ParticleStore& p = world.particles;
  const std::size_t n = p.size();
  const Vec3* const velocity = p.velocity.data();
  double fastest_squared = 0.0;  // (m/s)²
#pragma omp parallel for schedule(static) num_threads(world.threading.team(n)) reduction(max : fastest_squared)
  for (std::size_t i = 0; i < n; ++i) fastest_squared = std::max(fastest_squared, norm2(velocity[i]));
  double surface_squared = 0.0;  // (m/s)²
  for (const WorldSurface& s : world.surfaces)
    if (s.moving())
      for (const Vec3& v : s.mesh.vertex_velocities) surface_squared = std::max(surface_squared, norm2(v));
  const double particle_move = std::sqrt(fastest_squared) * world.dt;  // m per step
  const double move = std::max(particle_move, 0.5 * (particle_move + std::sqrt(surface_squared) * world.dt));
  const double best = std::sqrt(11.0 * move * choice.smallest_diameter);  // m
  return std::isfinite(best) ? std::clamp(best, choice.floor, choice.ceiling) : choice.floor;
}

}  // namespace

void rebuild_lists(World& world) {
  ParticleStore& p = world.particles;
  wrap_into_period(world);
  if (world.skin_choice.automatic) world.skin = automatic_skin(world);
  const int interval = world.spec.simulation.sort_interval.value;
  if (interval > 0 && world.steps_since_sort >= static_cast<std::uint64_t>(interval)) {
    // Re-sort along a space-filling curve for cache locality; wall contacts follow their particle.
    const std::vector<std::size_t> order = spatial_order(p, 2.0 * world.max_radius + world.skin);
    p.permute(order);
    reindex_wall_contacts(world, order);
    world.steps_since_sort = 0;
  }
  build_pair_list(p, world.skin, world.pairs);
  build_surface_candidates(world);
  world.rebuilds += 1;
  world.lists_stale = false;
}

namespace {

// Counts the step towards the next sort, and rebuilds the lists if they are stale or
// needs_rebuild(surface motion since the build, m) says so.
template <class Decide>
void update_neighbors_by(World& world, Decide&& needs_rebuild) {
  world.steps_since_sort += 1;
  const double surface_motion = world.has_moving_surfaces() ? max_surface_displacement(world) : 0.0;
  if (world.lists_stale || needs_rebuild(surface_motion)) rebuild_lists(world);
}

}  // namespace

void update_neighbors(World& world, bool force_rebuild) {
  update_neighbors_by(world, [&](double surface_motion) {
    return force_rebuild || pair_list_needs_rebuild(world.particles, world.pairs, surface_motion);
  });
}

void update_neighbors(World& world, const DriftScan& scan) {
  // The scan holds for the particles as they are unless something was inserted or removed
  // since (that marks the lists stale) or it could not compare with the list: then a pass.
  const bool scanned = scan.list_compared && scan.particles == world.particles.size();
  update_neighbors_by(world, [&](double surface_motion) {
    return scanned ? pair_list_needs_rebuild(world.pairs, scan.largest_displacement_squared,
                                             scan.ids_changed, surface_motion)
                   : pair_list_needs_rebuild(world.particles, world.pairs, surface_motion);
  });
}

}  // namespace quarry::sim
