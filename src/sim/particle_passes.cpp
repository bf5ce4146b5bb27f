// The step's plain per-particle passes besides the opening one (guards.cpp): the body forces,
// the velocity leads and the closing kick. Each takes four particles at a time
// (sim/particle_lanes.h) and the rest of its range one by one, with the same operations in the
// same order lane by lane, so the bits do not depend on the thread split (docs/performance.md,
// "The other per-particle passes too").
#include <omp.h>

#include "integrate/integrator.h"
#include "sim/particle_lanes.h"
#include "sim/step.h"

namespace quarry::sim {

namespace {

// Each component of p where `keep` (one value per particle, spread) is set, else 0.
[[gnu::always_inline]] inline Packed kept(const Packed& p, const Packed& keep) {
  const Lanes zero{};
  return {keep.a != zero ? p.a : zero, keep.b != zero ? p.b : zero, keep.c != zero ? p.c : zero};
}

[[gnu::always_inline]] inline Packed operator/(const Packed& p, const Packed& q) {
  return {p.a / q.a, p.b / q.b, p.c / q.c};
}

// Particle i's body force and torque, one at a time (see set_body_forces).
template <bool kForce, bool kTorque>
[[gnu::always_inline]] inline void body_force_particle(ParticleStore& p, std::size_t i, const Vec3& gravity) {
  // A fixed particle (inv_mass 0) has no weight to carry: m g would be inf (and 0/0 = NaN).
  Vec3 force = p.inv_mass[i] > 0.0 ? gravity / p.inv_mass[i] : Vec3{};  // N, the weight
  Vec3 torque;                                                            // N·m
  if constexpr (kForce) force += p.external_force[i];
  if constexpr (kTorque) torque += p.external_torque[i];
  p.force[i] = force;
  p.torque[i] = torque;
}

template <bool kForce, bool kTorque>
void body_forces_range(ParticleStore& p, std::size_t first, std::size_t end, const Vec3& gravity) {
  const Packed g = packed_corner(gravity);  // m/s²
  const Lanes one{1.0, 1.0, 1.0, 1.0};
  std::size_t i = first;
  for (; i + 4 <= end; i += 4) {
    const Lanes inv_mass = load_lanes(p.inv_mass.data() + i);  // 1/kg
    const Mask heavy = inv_mass > 0.0;
    // g / (1/m) where 1/m > 0; the other lanes divide by 1 and are dropped.
    Packed force = kept(g / spread(heavy ? inv_mass : one), spread(heavy ? one : Lanes{}));  // N
    Packed torque{};                                                                       // N·m
    if constexpr (kForce) force = force + load4(p.external_force.data() + i);
    if constexpr (kTorque) torque = torque + load4(p.external_torque.data() + i);
    store4(p.force.data() + i, force);
    store4(p.torque.data() + i, torque);
  }
  for (; i < end; ++i) body_force_particle<kForce, kTorque>(p, i, gravity);
}

// Velocity and spin changes h F/m, h τ/I of particles [first, end) into lead and spin_lead.
template <bool kApart>
void leads_range(const ParticleStore& p, std::size_t first, std::size_t end, double h,
                 const ParticleStore::ApartLoads& apart, Vec3* lead, Vec3* spin_lead) {
  std::size_t i = first;
  for (; i + 4 <= end; i += 4) {
    const KickChange kick = kick_change4<kApart>(p, i, h, apart);
    store4(lead + i, kick.velocity);
    store4(spin_lead + i, kick.spin);
  }
  const ParticleStore::ApartLoads loads = kApart ? apart : ParticleStore::ApartLoads{};
  for (; i < end; ++i) {
    lead[i] = integrate::kick_velocity_change(p, i, h, loads);
    spin_lead[i] = integrate::kick_spin_change(p, i, h, loads);
  }
}

// Particles [first, end) kicked by h (integrate::kick_particle).
template <bool kApart>
void kick_range(ParticleStore& p, std::size_t first, std::size_t end, double h,
                const ParticleStore::ApartLoads& apart) {
  std::size_t i = first;
  for (; i + 4 <= end; i += 4) {
    const KickChange kick = kick_change4<kApart>(p, i, h, apart);
    store4(p.velocity.data() + i, load4(p.velocity.data() + i) + kick.velocity);
    store4(p.angular_velocity.data() + i, load4(p.angular_velocity.data() + i) + kick.spin);
  }
  const ParticleStore::ApartLoads loads = kApart ? apart : ParticleStore::ApartLoads{};
  for (; i < end; ++i) integrate::kick_particle(p, i, h, loads);
}

}  // namespace

void set_body_forces(World& world) {
  ParticleStore& p = world.particles;
  const std::size_t n = p.size();
  const Vec3 gravity = world.spec.simulation.gravity.value;  // m/s²
  // Only the load arrays that may hold something are read (ParticleStore::held_loads). One-step
  // loads stay apart: the closing kick adds them.
  const auto has = [&p](std::uint8_t field) { return p.has_external_loads() && (p.held_loads & field); };
  const bool held_force = has(ParticleStore::kForceLoads);
  const bool held_torque = has(ParticleStore::kTorqueLoads);
  const std::span<const std::uint32_t> ranges = particle_ranges(world);
#pragma omp parallel num_threads(world.threading.team(n))
  {
    const auto [first, end] = thread_block(n, omp_get_thread_num(), omp_get_num_threads(), ranges);
    if (held_force)
      held_torque ? body_forces_range<true, true>(p, first, end, gravity)
                  : body_forces_range<true, false>(p, first, end, gravity);
    else
      held_torque ? body_forces_range<false, true>(p, first, end, gravity)
                  : body_forces_range<false, false>(p, first, end, gravity);
  }
  p.once_in_forces = false;  // the forces of a new configuration
}

void set_velocity_leads(World& world, double h) {
  const ParticleStore& p = world.particles;
  ForceWorkspace& ws = world.force_workspace;
  const std::size_t n = p.size();
  ws.velocity_lead.resize(n);
  ws.angular_velocity_lead.resize(n);
  Vec3* const lead = ws.velocity_lead.data();
  Vec3* const spin_lead = ws.angular_velocity_lead.data();
  ws.lead_time = h;
  const std::span<const std::uint32_t> ranges = particle_ranges(world);
  // The forces of the opening kick: with the one-step loads kept apart from them, if any.
  const ParticleStore::ApartLoads apart = p.apart_once_loads();
#pragma omp parallel num_threads(world.threading.team(n))
  {
    const auto [first, end] = thread_block(n, omp_get_thread_num(), omp_get_num_threads(), ranges);
    if (apart.any())
      leads_range<true>(p, first, end, h, apart, lead, spin_lead);
    else
      leads_range<false>(p, first, end, h, apart, lead, spin_lead);  // the loop without loads
  }
}

void closing_kick(World& world, double h) {
  ParticleStore& p = world.particles;
  const std::size_t n = p.size();
  const std::span<const std::uint32_t> ranges = particle_ranges(world);
  const ParticleStore::ApartLoads apart = p.apart_once_loads();  // a partner's one-step loads
#pragma omp parallel num_threads(world.threading.team(n))
  {
    const auto [first, end] = thread_block(n, omp_get_thread_num(), omp_get_num_threads(), ranges);
    if (apart.any())
      kick_range<true>(p, first, end, h, apart);
    else
      kick_range<false>(p, first, end, h, apart);
  }
}

}  // namespace quarry::sim
