// Explicit integrators for the particles' translation and rotation (spheres: no gyroscopic
// term). Velocity Verlet (Swope et al. 1982, "kick-drift-kick") is the default; symplectic
// Euler (semi-implicit Euler: kick with F(x_n), then drift) the alternative. Both are
// second/first order symplectic schemes; tests/integrator_order_test checks their orders.
#pragma once

#include <cstddef>

#include "core/particle_store.h"

namespace quarry::integrate {

// Particle i kicked by h (s): v += h F/m, ω += h τ/I (h = dt/2 for a half kick).
inline void kick_particle(ParticleStore& p, std::size_t i, double h) {
  p.velocity[i] += p.force[i] * (h * p.inv_mass[i]);
  p.angular_velocity[i] += p.torque[i] * (h * p.inv_inertia(i));
}

// Every particle kicked by h (s), on `team` threads.
inline void kick(ParticleStore& p, double h, int team = 1) {
  const std::size_t n = p.size();
#pragma omp parallel for schedule(static) num_threads(team)
  for (std::size_t i = 0; i < n; ++i) kick_particle(p, i, h);
}

// Particle i: kick by h then drift by dt (s).
inline void kick_drift_particle(ParticleStore& p, std::size_t i, double h, double dt) {
  kick_particle(p, i, h);
  p.position[i] += p.velocity[i] * dt;
}

// Kick by h then drift by dt in one pass over memory (the first half of a step).
inline void kick_drift(ParticleStore& p, double h, double dt, int team = 1) {
  const std::size_t n = p.size();
#pragma omp parallel for schedule(static) num_threads(team)
  for (std::size_t i = 0; i < n; ++i) kick_drift_particle(p, i, h, dt);
}

}  // namespace quarry::integrate
