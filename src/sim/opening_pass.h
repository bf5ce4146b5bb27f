// A step's opening pass for one particle: the last step's closing half kick if it was left
// pending, the opening kick, the drift, and what the guards and the neighbour stage need to
// know of the new state (DriftScan). One expression for the two places that run it: the
// step's own pass over the particles (kick_drift_scan), and the previous step's force stage
// when that stage is told the next step follows at once (StepEnd::next_opened), which does it
// for each particle as soon as its force is final, while its data is still in cache.
#pragma once

#include "integrate/integrator.h"
#include "sim/world.h"

namespace quarry::sim {

// Per-thread tallies of a parallel opening pass, merged (exact: flags and a maximum, so any
// merge order gives the same result).
#pragma omp declare reduction(merge : OpeningTally : omp_out.merge(omp_in)) initializer(omp_priv = OpeningTally{})

struct OpeningPass {
  double pending = 0.0;  // s: closing half kick of the last step (0: none)
  double h = 0.0;        // s: opening kick
  double dt = 0.0;       // s: drift
  const Aabb* domain = nullptr;              // null: no domain check
  const Vec3* reference = nullptr;           // positions at the list's build (null: not compared)
  const ParticleId* id_at_build = nullptr;   // ids at the list's build

  // The pass the world's next step opens with: kick by `pending` then `h`, drift by `dt`.
  static OpeningPass of(const World& world, double pending, double h, double dt) {
    OpeningPass pass{pending, h, dt};
    const Aabb& box = world.spec.simulation.domain.value;
    if (!box.empty()) pass.domain = &box;
    const PairList& list = world.pairs;
    if (list.built_for(world.particles.size())) {
      pass.reference = list.reference_positions.data();
      pass.id_at_build = list.ids_at_build.data();
    }
    return pass;
  }

  // Particle i: integrate::kick_particle by `pending` (if any) and by h, then the drift, with
  // the particle's data held in registers (through the arrays the compiler would reload it
  // after each store, as a store of a Vec3 may alias any double). The same operations as the
  // integrator's, so the same bits (floating-point contraction is off project-wide).
  // Branch-free scan: x·0 is 0 for a finite x and NaN for ±inf or NaN, so one sum tells
  // whether all nine components are finite (the first offender is searched only if one is).
  [[gnu::always_inline]] inline void run(ParticleStore& p, std::size_t i, OpeningTally& tally) const {
    const double inv_mass = p.inv_mass[i], inv_inertia = p.inv_inertia(i);  // 1/kg, 1/(kg m²)
    const Vec3 f = p.force[i], torque = p.torque[i];                         // N, N·m
    Vec3 v = p.velocity[i], w = p.angular_velocity[i];                       // m/s, rad/s
    if (pending != 0.0) integrate::kick_values(v, w, f, torque, inv_mass, inv_inertia, pending);
    integrate::kick_values(v, w, f, torque, inv_mass, inv_inertia, h);
    const Vec3 x = p.position[i] + v * dt;  // m
    p.velocity[i] = v;
    p.angular_velocity[i] = w;
    p.position[i] = x;
    const double zero = (x.x * 0.0 + x.y * 0.0 + x.z * 0.0) + (v.x * 0.0 + v.y * 0.0 + v.z * 0.0) +
                        (w.x * 0.0 + w.y * 0.0 + w.z * 0.0);
    tally.non_finite |= !(zero == 0.0);
    if (domain) tally.any_outside |= !domain->contains(x);  // (predictable: almost always inside)
    if (reference) {
      // NaN compares false: a non-finite particle is reported through `non_finite`, not here.
      const double d2 = norm2(x - reference[i]);  // m²
      double& largest = tally.largest_displacement_squared;  // m²
      largest = d2 > largest ? d2 : largest;
      tally.ids_changed |= p.id[i] != id_at_build[i];
    }
  }

  // Particle i's opening kick and drift taken back, to within rounding (the pending closing
  // kick stays: it completes the step). Only for a step whose force stage found an excessive
  // overlap after it had opened the next one: the run stops there, and the guard's report and
  // the last frame must show that step's state, not half a step further. The same operations
  // for any thread count, so the same bits.
  [[gnu::always_inline]] inline void undo(ParticleStore& p, std::size_t i) const {
    const Vec3 v = p.velocity[i];  // m/s
    p.position[i] = p.position[i] - v * dt;
    p.velocity[i] = v - p.force[i] * (h * p.inv_mass[i]);
    p.angular_velocity[i] = p.angular_velocity[i] - p.torque[i] * (h * p.inv_inertia(i));
  }
};

}  // namespace quarry::sim
