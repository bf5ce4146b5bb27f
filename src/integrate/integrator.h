// Explicit integrators for the particles' translation and rotation (spheres: no gyroscopic
// term). Velocity Verlet (Swope et al. 1982, "kick-drift-kick") is the default; symplectic
// Euler (semi-implicit Euler: kick with F(x_n), then drift) the alternative. Both are
// second/first order symplectic schemes; tests/integrator_order_test checks their orders.
#pragma once

#include <omp.h>

#include <cstddef>
#include <cstdint>
#include <span>

#include "core/particle_store.h"
#include "core/threading.h"

namespace quarry::integrate {

// Particle i's force (N) and torque (N·m) as a kick uses them: the stored ones plus the one-step
// loads kept apart from them (`apart`, null where none). The sum is the one
// sim::settle_once_loads would store, so the bits are the same whether the loads were put into
// the forces before or are added here.
inline Vec3 kick_force(const ParticleStore& p, std::size_t i, const ParticleStore::ApartLoads& apart) {
  return apart.force ? p.force[i] + apart.force[i] : p.force[i];
}
inline Vec3 kick_torque(const ParticleStore& p, std::size_t i, const ParticleStore::ApartLoads& apart) {
  return apart.torque ? p.torque[i] + apart.torque[i] : p.torque[i];
}

// What a kick by h (s) adds to particle i's velocity, h F/m (m/s), and spin, h τ/I (rad/s),
// F and τ those of kick_force and kick_torque.
inline Vec3 kick_velocity_change(const ParticleStore& p, std::size_t i, double h,
                                 const ParticleStore::ApartLoads& apart) {
  return kick_force(p, i, apart) * (h * p.inv_mass[i]);
}
inline Vec3 kick_spin_change(const ParticleStore& p, std::size_t i, double h,
                             const ParticleStore::ApartLoads& apart) {
  return kick_torque(p, i, apart) * (h * p.inv_inertia(i));
}

// Particle i kicked by h (s): v += h F/m, ω += h τ/I (h = dt/2 for a half kick).
inline void kick_particle(ParticleStore& p, std::size_t i, double h, const ParticleStore::ApartLoads& apart = {}) {
  p.velocity[i] += kick_velocity_change(p, i, h, apart);
  p.angular_velocity[i] += kick_spin_change(p, i, h, apart);
}

// Every particle kicked by h (s), on `team` threads, thread t taking range t of `ranges`
// (thread_block; equal blocks if they do not fit).
inline void kick(ParticleStore& p, double h, int team = 1, std::span<const std::uint32_t> ranges = {}) {
  const std::size_t n = p.size();
  const ParticleStore::ApartLoads apart = p.apart_once_loads();
#pragma omp parallel num_threads(team)
  {
    const auto [first, end] = thread_block(n, omp_get_thread_num(), omp_get_num_threads(), ranges);
    if (apart.any())
      for (std::size_t i = first; i < end; ++i) kick_particle(p, i, h, apart);
    else
      for (std::size_t i = first; i < end; ++i) kick_particle(p, i, h);
  }
}

// Particle i: kick by h then drift by dt (s).
inline void kick_drift_particle(ParticleStore& p, std::size_t i, double h, double dt,
                                const ParticleStore::ApartLoads& apart = {}) {
  kick_particle(p, i, h, apart);
  p.position[i] += p.velocity[i] * dt;
}

// Kick by h then drift by dt in one pass over memory (the first half of a step).
inline void kick_drift(ParticleStore& p, double h, double dt, int team = 1) {
  const std::size_t n = p.size();
  const ParticleStore::ApartLoads apart = p.apart_once_loads();
#pragma omp parallel for schedule(static) num_threads(team)
  for (std::size_t i = 0; i < n; ++i) kick_drift_particle(p, i, h, dt, apart);
}

}  // namespace quarry::integrate
