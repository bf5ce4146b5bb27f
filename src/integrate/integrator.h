// Explicit integrators for the particles' translation and rotation (spheres: no gyroscopic
// term). Velocity Verlet (Swope et al. 1982, "kick-drift-kick") is the default; symplectic
// Euler (semi-implicit Euler: kick with F(x_n), then drift) the alternative. Both are
// second/first order symplectic schemes; tests/integrator_order_test checks their orders.
#pragma once

#include <cstddef>

#include "core/particle_store.h"

namespace quarry::integrate {

// v += h F/m, ω += h τ/I (h = dt/2 for a half kick), on values a pass holds in registers.
// Every kick is this one expression, so a kick run inside another pass gives the same bits
// as the kick pass.
inline void kick_values(Vec3& velocity, Vec3& angular_velocity, const Vec3& force, const Vec3& torque,
                        double inv_mass, double inv_inertia, double h) {
  velocity += force * (h * inv_mass);
  angular_velocity += torque * (h * inv_inertia);
}

// Particle i kicked by h.
inline void kick_particle(ParticleStore& p, std::size_t i, double h) {
  kick_values(p.velocity[i], p.angular_velocity[i], p.force[i], p.torque[i], p.inv_mass[i], p.inv_inertia(i), h);
}

// Every particle kicked by h.
inline void kick(ParticleStore& p, double h) {
  const std::size_t n = p.size();
#pragma omp parallel for schedule(static) if (n > parallel_threshold)
  for (std::size_t i = 0; i < n; ++i) kick_particle(p, i, h);
}

// Particle i: kick by h then drift by dt (kick_drift's body, for passes that do more per particle).
inline void kick_drift_particle(ParticleStore& p, std::size_t i, double h, double dt) {
  kick_particle(p, i, h);
  p.position[i] += p.velocity[i] * dt;
}

// Kick by h then drift by dt in one pass over memory (the first half of a step).
inline void kick_drift(ParticleStore& p, double h, double dt) {
  const std::size_t n = p.size();
#pragma omp parallel for schedule(static) if (n > parallel_threshold)
  for (std::size_t i = 0; i < n; ++i) kick_drift_particle(p, i, h, dt);
}

// x += dt v.
inline void drift(ParticleStore& p, double dt) {
  const std::size_t n = p.size();
#pragma omp parallel for schedule(static) if (n > parallel_threshold)
  for (std::size_t i = 0; i < n; ++i) p.position[i] += p.velocity[i] * dt;
}

}  // namespace quarry::integrate
