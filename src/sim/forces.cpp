// Force stage (DESIGN §2 step 3): particle–particle contacts computed once per pair and stored,
// then gathered per particle in a fixed order (no atomics: bit-identical for any thread count);
// particle–surface contacts per particle, their reactions gathered onto triangles and vertices
// in particle order; then gravity and the external (coupling) forces.
#include <algorithm>
#include <cmath>

#include "sim/step.h"

namespace quarry::sim {

namespace {

void pair_forces(World& world) {
  ParticleStore& p = world.particles;
  PairList& list = world.pairs;
  const std::size_t n = p.size();
  const std::size_t pairs = list.size();
  world.pair_force.resize(pairs);
  world.pair_torque_i.resize(pairs);
  world.pair_torque_j.resize(pairs);
  world.pair_overlap.resize(pairs);
  const double dt = world.dt;
  const double overlap_limit = world.spec.simulation.max_overlap_fraction.value;  // of min radius
  int excessive = 0;  // set if some overlap passed the guard's limit (check_overlaps reports it)
  // Raw arrays: the stores below are Vec3 like the particle arrays, so through the vectors the
  // compiler would have to reload particle i's data after every store (possible aliasing).
  const Vec3* position = p.position.data();
  const Vec3* velocity = p.velocity.data();
  const Vec3* angular_velocity = p.angular_velocity.data();
  const double* radius = p.radius.data();
  const double* inv_mass = p.inv_mass.data();
  const std::uint16_t* material = p.material.data();
  const std::uint32_t* offsets = list.offsets.data();
  const std::uint32_t* partner = list.partner.data();
  Vec3* tangential = list.tangential_displacement.data();
  Vec3* rolling = list.rolling_torque.data();
  Vec3* pair_force = world.pair_force.data();
  Vec3* pair_torque_i = world.pair_torque_i.data();
  Vec3* pair_torque_j = world.pair_torque_j.data();
  double* pair_overlap = world.pair_overlap.data();
  const MaterialTable& materials = world.materials;
#pragma omp parallel for schedule(dynamic, 512) if (n > parallel_threshold) reduction(| : excessive)
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3 position_i = position[i];
    const double radius_i = radius[i];
    const double mass_i = 1.0 / inv_mass[i];  // kg
    const Vec3 velocity_i = velocity[i];
    const Vec3 angular_velocity_i = angular_velocity[i];
    const InteractionParameters* row = &materials.between(material[i], 0);
    for (std::uint32_t k = offsets[i]; k < offsets[i + 1]; ++k) {
      const std::uint32_t j = partner[k];
      const Vec3 d = position_i - position[j];
      const double touch = radius_i + radius[j];
      const double distance2 = norm2(d);
      if (distance2 >= touch * touch) {
        // Not touching: no force, and the tangential history of a broken contact is reset.
        pair_force[k] = {};
        pair_torque_i[k] = {};
        pair_torque_j[k] = {};
        pair_overlap[k] = 0.0;
        tangential[k] = {};
        rolling[k] = {};
        continue;
      }
      const double distance = std::sqrt(distance2);
      ContactKinematics kin;
      kin.normal = d / distance;
      kin.overlap = touch - distance;
      kin.radius_i = radius_i;
      kin.radius_j = radius[j];
      kin.mass_i = mass_i;
      kin.mass_j = 1.0 / inv_mass[j];
      kin.velocity_i = velocity_i;
      kin.velocity_j = velocity[j];
      kin.angular_velocity_i = angular_velocity_i;
      kin.angular_velocity_j = angular_velocity[j];
      ContactHistory history{tangential[k], rolling[k]};
      const ContactResult r = evaluate_contact(row[material[j]], kin, history, dt);
      tangential[k] = history.tangential_displacement;
      rolling[k] = history.rolling_torque;
      pair_force[k] = r.force_i;
      pair_torque_i[k] = r.torque_i;
      pair_torque_j[k] = r.torque_j;
      pair_overlap[k] = kin.overlap;
      excessive |= kin.overlap > overlap_limit * std::min(kin.radius_i, kin.radius_j);
    }
  }
  world.excessive_overlap = excessive != 0;
}

// Sums the stored pair forces onto the particles: first the pairs where the particle is i,
// then those where it is the partner, each in ascending pair order.
void gather_pair_forces(World& world) {
  ParticleStore& p = world.particles;
  const PairList& list = world.pairs;
  const std::size_t n = p.size();
#pragma omp parallel for schedule(static) if (n > parallel_threshold)
  for (std::size_t i = 0; i < n; ++i) {
    Vec3 force, torque;
    for (std::uint32_t k = list.offsets[i]; k < list.offsets[i + 1]; ++k) {
      force += world.pair_force[k];
      torque += world.pair_torque_i[k];
    }
    for (std::uint32_t r = list.reverse_offsets[i]; r < list.reverse_offsets[i + 1]; ++r) {
      const std::uint32_t k = list.reverse_pairs[r];
      force -= world.pair_force[k];
      torque += world.pair_torque_j[k];
    }
    p.force[i] = force;
    p.torque[i] = torque;
  }
}

// Velocity of the surface material at a contact point: the vertices' velocities interpolated
// with the barycentric weights, plus the conveyor velocity's tangential part (m/s).
Vec3 surface_velocity(const Surface& surface, const SurfaceContact& c) {
  const auto& tri = surface.triangles[c.triangle];
  Vec3 v = surface.vertex_velocities[tri[0]] * c.weights[0] +
           surface.vertex_velocities[tri[1]] * c.weights[1] +
           surface.vertex_velocities[tri[2]] * c.weights[2];
  const Vec3& belt = surface.conveyor_velocity;
  return v + belt - c.normal * dot(belt, c.normal);
}

void wall_forces(World& world) {
  ParticleStore& p = world.particles;
  const std::size_t n = p.size();
  const SurfaceCandidates& cand = world.candidates;
  const double dt = world.dt;
  const double overlap_limit = world.spec.simulation.max_overlap_fraction.value;  // of radius
  int excessive = 0;
#pragma omp parallel if (n > parallel_threshold) reduction(| : excessive)
  {
    std::vector<SurfaceContact> found;
    std::vector<std::pair<std::uint16_t, SurfaceContact>> contacts;
#pragma omp for schedule(dynamic, 256)
    for (std::size_t i = 0; i < n; ++i) {
      WallSlot* slots = &world.wall_slots[i * kWallSlots];
      const std::uint32_t begin = cand.offsets[i], end = cand.offsets[i + 1];
      if (begin == end) {
        // No surface within reach (most particles): slots are filled front to back, so one
        // look at the first tells whether anything must be cleared.
        if (slots[0].surface >= 0)
          for (int s = 0; s < kWallSlots; ++s) slots[s].surface = -1;
        continue;
      }
      // Candidates are grouped by surface: detect contacts one surface at a time.
      contacts.clear();
      for (std::uint32_t a = begin; a < end;) {
        std::uint32_t b = a;
        while (b < end && cand.surface[b] == cand.surface[a]) ++b;
        const std::uint16_t s = cand.surface[a];
        find_surface_contacts(world.surfaces[s], world.topologies[s], p.position[i], p.radius[i],
                              std::span<const std::uint32_t>(cand.triangle.data() + a, b - a), found);
        for (const auto& c : found) contacts.emplace_back(s, c);
        a = b;
      }
      // Keep tangential history for contacts that continue: same surface, similar normal.
      WallSlot previous[kWallSlots];
      int previous_count = 0;  // slots are filled front to back: copy only the used ones
      while (previous_count < kWallSlots && slots[previous_count].surface >= 0) {
        previous[previous_count] = slots[previous_count];
        ++previous_count;
      }
      bool used[kWallSlots] = {};
      Vec3 force, torque;
      int filled = 0;
      for (const auto& [s, c] : contacts) {
        if (filled == kWallSlots) break;
        WallSlot slot;
        int best = -1;
        double best_alignment = 0.5;  // cos 60°
        for (int q = 0; q < previous_count; ++q) {
          if (used[q] || previous[q].surface != s) continue;
          const double alignment = dot(previous[q].normal, c.normal);
          if (alignment > best_alignment) best_alignment = alignment, best = q;
        }
        if (best >= 0) {
          used[best] = true;
          slot.history = previous[best].history;
        }
        const Surface& surface = world.surfaces[s];
        ContactKinematics kin;
        kin.normal = c.normal;
        kin.overlap = c.overlap;
        kin.radius_i = p.radius[i];
        kin.radius_j = 0.0;  // a wall
        kin.mass_i = 1.0 / p.inv_mass[i];
        kin.mass_j = 0.0;
        kin.velocity_i = p.velocity[i];
        kin.velocity_j = surface_velocity(surface, c);
        kin.angular_velocity_i = p.angular_velocity[i];
        const ContactResult r = evaluate_contact(
            world.materials.between(p.material[i], surface.material), kin, slot.history, dt);
        slot.surface = s;
        slot.normal = c.normal;
        slot.triangle = c.triangle;
        slot.weights = c.weights;
        slot.point = c.point;
        slot.force_on_particle = r.force_i;
        excessive |= c.overlap > overlap_limit * p.radius[i];
        force += r.force_i;
        torque += r.torque_i;
        slots[filled++] = slot;
      }
      for (int q = filled; q < std::max(filled, previous_count); ++q) slots[q].surface = -1;
      p.force[i] += force;
      p.torque[i] += torque;
    }
  }
  world.excessive_overlap = world.excessive_overlap || excessive != 0;
  // Reactions on the surfaces, gathered in particle order (deterministic).
  for (auto& surface : world.surfaces) surface.clear_step_loads();
  for (std::size_t i = 0; i < n; ++i) {
    for (int q = 0; q < kWallSlots; ++q) {
      const WallSlot& slot = world.wall_slots[i * kWallSlots + q];
      if (slot.surface < 0) break;
      Surface& surface = world.surfaces[slot.surface];
      const Vec3 reaction = -slot.force_on_particle;
      surface.triangle_force[slot.triangle] += reaction;
      const auto& tri = surface.triangles[slot.triangle];
      for (int k = 0; k < 3; ++k) surface.vertex_force[tri[k]] += reaction * slot.weights[k];
      surface.total_force += reaction;
      surface.total_torque += cross(slot.point, reaction);
    }
  }
}

void body_forces(World& world) {
  ParticleStore& p = world.particles;
  const Vec3 gravity = world.spec.simulation.gravity.value;
  const std::size_t n = p.size();
#pragma omp parallel for schedule(static) if (n > parallel_threshold)
  for (std::size_t i = 0; i < n; ++i) {
    p.force[i] += gravity / p.inv_mass[i] + p.external_force[i];
    p.torque[i] += p.external_torque[i];
  }
}

}  // namespace

void compute_forces(World& world) {
  {
    ScopedStage timer(world.timers, world.timers.stage("pair forces"));
    pair_forces(world);
  }
  {
    ScopedStage timer(world.timers, world.timers.stage("gather"));
    gather_pair_forces(world);
  }
  {
    ScopedStage timer(world.timers, world.timers.stage("surface forces"));
    wall_forces(world);
  }
  body_forces(world);
}

}  // namespace quarry::sim
