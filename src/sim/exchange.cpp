// Changes from outside between steps (exchange.h): particles added and removed, external
// loads, the type order and id index of the coupling interface.
#include "sim/exchange.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <unordered_set>

namespace quarry::sim {

namespace {

bool finite(const Vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

std::string show(const Vec3& v) { return fmt::format("({:.6g}, {:.6g}, {:.6g})", v.x, v.y, v.z); }

// The particle indices changed: the lists are rebuilt before the next force stage. The surface
// candidates name indices and go now; the pair list stays (its history follows the ids).
void mark_lists_stale(World& world) {
  world.lists_stale = true;
  world.candidates = SurfaceCandidates{};
  world.candidates.offsets.assign(1, 0);
}

}  // namespace

std::vector<ParticleId> add_particles(World& world, std::span<const NewParticle> particles) {
  const Aabb& domain = world.spec.simulation.domain.value;
  for (std::size_t k = 0; k < particles.size(); ++k) {
    const NewParticle& q = particles[k];
    const auto fail = [k](const std::string& what) {
      throw std::invalid_argument(fmt::format("particle {} of the list: {}", k, what));
    };
    if (q.type >= world.types.size())
      fail(fmt::format("type index {} does not exist ({} types)", q.type, world.types.size()));
    if (!finite(q.position) || !finite(q.velocity) || !finite(q.angular_velocity) || !std::isfinite(q.radius))
      fail("a position, velocity, angular velocity or radius is not a finite number");
    if (q.radius > world.max_radius)
      fail(fmt::format("radius {:.6g} m is larger than the largest the world was sized for ({:.6g} m, "
                       "from the particle types' size distributions)", q.radius, world.max_radius));
    if (!domain.empty() && !domain.contains(q.position))
      fail(fmt::format("position {} m is outside the domain", show(q.position)));
  }
  if (std::any_of(particles.begin(), particles.end(), [](const NewParticle& q) { return q.id != 0; })) {
    std::unordered_set<ParticleId> taken(world.particles.id.begin(), world.particles.id.end());
    for (std::size_t k = 0; k < particles.size(); ++k)
      if (particles[k].id != 0 && !taken.insert(particles[k].id).second)
        throw std::invalid_argument(fmt::format("particle {} of the list: id {} is taken", k, particles[k].id));
  }
  ParticleStore& p = world.particles;
  const Vec3 gravity = world.spec.simulation.gravity.value;  // m/s²
  std::vector<ParticleId> ids;
  ids.reserve(particles.size());
  for (const NewParticle& q : particles) {
    const ParticleTypeInfo& type = world.types[q.type];
    const double radius = q.radius > 0.0 ? q.radius : world.size_samplers[q.type].sample(world.size_random);  // m
    const ParticleId id = q.id != 0 ? q.id : world.next_id;
    const std::size_t i = p.add(id, type.type_index, type.material_index, q.position, q.velocity,
                                radius, type.density, world.time);
    p.angular_velocity[i] = q.angular_velocity;
    p.force[i] = gravity / p.inv_mass[i];  // its body force, as set_body_forces would give
    if (type.fixed) {
      p.make_fixed(i);
      p.force[i] = Vec3{};
    }
    world.next_id = std::max(world.next_id, id + 1);
    ids.push_back(id);
  }
  if (!particles.empty()) mark_lists_stale(world);
  return ids;
}

void remove_particles(World& world, std::span<const ParticleId> ids) {
  if (ids.empty()) return;
  IdIndex index;
  update_id_index(world, index);
  std::vector<char> remove(world.particles.size(), 0);
  for (const ParticleId id : ids) {
    const auto found = index.index.find(id);
    if (found == index.index.end())
      throw std::invalid_argument(fmt::format("particle id {} does not exist", id));
    if (remove[found->second]) throw std::invalid_argument(fmt::format("particle id {} is given twice", id));
    remove[found->second] = 1;
  }
  drop_wall_contacts_of_removed(world, remove);
  world.particles.remove_flagged(remove);
  mark_lists_stale(world);
}

void set_external_loads(World& world, std::span<const std::uint32_t> indices, std::span<const double> forces,
                        std::span<const double> torques, LoadMode mode, LoadHold hold) {
  ParticleStore& p = world.particles;
  const std::size_t n = p.size();
  const std::size_t entries = indices.empty() ? n : indices.size();
  if ((!forces.empty() && forces.size() != 3 * entries) || (!torques.empty() && torques.size() != 3 * entries))
    throw std::invalid_argument(fmt::format("{} entries expected (3 values each), got {} force and {} torque values",
                                            entries, forces.size(), torques.size()));
  const int team = world.threading.team(entries);
  // Checked in one branch-free pass (x·0 is 0 only for a finite x); the entry at fault is
  // looked for only when there is one.
  double zero = 0.0;
  std::uint32_t largest_index = 0;
#pragma omp parallel for schedule(static) num_threads(team) reduction(+ : zero) reduction(max : largest_index)
  for (std::size_t k = 0; k < entries; ++k) {
    for (int c = 0; c < 3; ++c) {
      if (!forces.empty()) zero += forces[3 * k + c] * 0.0;
      if (!torques.empty()) zero += torques[3 * k + c] * 0.0;
    }
    if (!indices.empty()) largest_index = std::max(largest_index, indices[k]);
  }
  if (!(zero == 0.0))
    for (std::size_t k = 0; k < entries; ++k)
      for (int c = 0; c < 3; ++c)
        if ((!forces.empty() && !std::isfinite(forces[3 * k + c])) || (!torques.empty() && !std::isfinite(torques[3 * k + c])))
          throw std::invalid_argument(fmt::format("entry {}: a force or torque is not a finite number", k));
  if (!indices.empty()) {
    if (largest_index >= n)
      throw std::invalid_argument(fmt::format("particle index {} does not exist ({} particles)", largest_index, n));
    // Each particle once: the entries are then applied in parallel.
    std::vector<char> seen(n, 0);
    for (std::size_t k = 0; k < entries; ++k) {
      if (seen[indices[k]]) throw std::invalid_argument(fmt::format("entry {}: particle id {} is given twice", k, p.id[indices[k]]));
      seen[indices[k]] = 1;
    }
  }
  p.enable_external_loads();
  Vec3* const load = (hold == LoadHold::until_changed ? p.external_force : p.external_force_once).data();
  Vec3* const load_torque = (hold == LoadHold::until_changed ? p.external_torque : p.external_torque_once).data();
  const bool add = mode == LoadMode::add;
  // Loads inside the stored forces (held ones, and one-step ones once something read the forces)
  // change them with the load (F + new − old), so that the next opening kick sees it at once;
  // one-step loads kept apart are added by the kicks themselves.
  const bool inside = hold == LoadHold::until_changed || p.once_in_forces;
  const auto apply = [add, inside](Vec3& held, Vec3& total, const double* value) {
    const Vec3 given{value[0], value[1], value[2]};
    const Vec3 next = add ? held + given : given;
    if (inside) total += next - held;
    held = next;
  };
#pragma omp parallel for schedule(static) num_threads(team)
  for (std::size_t k = 0; k < entries; ++k) {
    const std::size_t i = indices.empty() ? k : indices[k];
    if (!forces.empty()) apply(load[i], p.force[i], &forces[3 * k]);
    if (!torques.empty()) apply(load_torque[i], p.torque[i], &torques[3 * k]);
  }
  const std::uint8_t given = (forces.empty() ? 0 : ParticleStore::kForceLoads) | (torques.empty() ? 0 : ParticleStore::kTorqueLoads);
  (hold == LoadHold::next_step ? p.once_loads : p.held_loads) |= given;
}

namespace {

// force/torque ± the one-step loads of the fields in p.once_loads (sign +1 or −1), on the world's
// threads.
void shift_by_once_loads(World& world, double sign) {
  ParticleStore& p = world.particles;
  const bool force = p.once_loads & ParticleStore::kForceLoads, torque = p.once_loads & ParticleStore::kTorqueLoads;
  const std::size_t n = p.size();
#pragma omp parallel for schedule(static) num_threads(world.threading.team(n))
  for (std::size_t i = 0; i < n; ++i) {
    if (force) p.force[i] += sign * p.external_force_once[i];
    if (torque) p.torque[i] += sign * p.external_torque_once[i];
  }
}

}  // namespace

void open_once_loads(World& world, std::uint8_t field) {
  ParticleStore& p = world.particles;
  p.enable_external_loads();
  unsettle_once_loads(world);
  p.once_loads |= field;
}

void settle_once_loads(World& world) {
  ParticleStore& p = world.particles;
  if (!p.has_external_loads() || p.once_in_forces || p.once_loads == 0) return;
  shift_by_once_loads(world, 1.0);
  p.once_in_forces = true;
}

void unsettle_once_loads(World& world) {
  ParticleStore& p = world.particles;
  if (!p.once_in_forces) return;
  shift_by_once_loads(world, -1.0);
  p.once_in_forces = false;
}

void update_type_order(const World& world, TypeOrder& order) {
  const ParticleStore& p = world.particles;
  const std::size_t n = p.size();
  if (order.epoch == p.layout_epoch && order.particles == n) return;
  const std::size_t types = world.types.size();
  order.type_start.assign(types + 1, 0);
  for (std::size_t i = 0; i < n; ++i) order.type_start[p.type[i] + 1] += 1;
  for (std::size_t t = 0; t < types; ++t) order.type_start[t + 1] += order.type_start[t];
  std::vector<std::uint64_t> next(order.type_start.begin(), order.type_start.end() - 1);
  order.order.resize(n);
  order.identity = true;
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint64_t k = next[p.type[i]]++;
    order.order[k] = static_cast<std::uint32_t>(i);
    order.identity &= k == i;
  }
  order.epoch = p.layout_epoch;
  order.particles = n;
}

void update_id_index(const World& world, IdIndex& ids) {
  const ParticleStore& p = world.particles;
  if (ids.epoch == p.layout_epoch && ids.particles == p.size()) return;
  ids.index.clear();
  ids.index.reserve(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) ids.index.emplace(p.id[i], static_cast<std::uint32_t>(i));
  ids.epoch = p.layout_epoch;
  ids.particles = p.size();
}

}  // namespace quarry::sim
