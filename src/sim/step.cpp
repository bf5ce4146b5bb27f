// The time step, read top to bottom (DESIGN §2). Velocity Verlet: half kick, drift, move the
// geometry, forces at the new configuration, half kick. Symplectic Euler: full kick with the
// forces of the previous configuration, drift, geometry, forces. The order matters: forces
// are always computed at one consistent configuration of particles and surfaces.
#include "sim/step.h"

#include <stdexcept>

#include "integrate/integrator.h"
#include "sim/opening_pass.h"

namespace quarry::sim {

void step(World& world, StepEnd end) {
  const double dt = world.dt;
  const bool verlet = world.spec.simulation.integrator.value == Integrator::velocity_verlet;
  const double opening_kick = verlet ? 0.5 * dt : dt;  // s
  const bool defer = verlet && end == StepEnd::kick_pending;
  DriftScan scan;  // what the drift saw: NaNs, particles outside the domain, displacements
  {
    // The last step's closing kick first, if it was left to this pass.
    ScopedStage timer(world.timers, world.timers.stage("integrate"));
    scan = kick_drift_scan(world, opening_kick, dt);
  }
  world.time += dt;
  world.step_count += 1;
  {
    // Before anything else looks at positions: a NaN particle must stop the run, not be
    // mistaken for one that left the domain.
    ScopedStage timer(world.timers, world.timers.stage("guards"));
    check_finite(world, scan);
  }
  {
    ScopedStage timer(world.timers, world.timers.stage("geometry"));
    move_surfaces(world, world.time);
  }
  {
    ScopedStage timer(world.timers, world.timers.stage("insert/remove"));
    insert_and_remove(world, scan);
  }
  {
    ScopedStage timer(world.timers, world.timers.stage("neighbor"));
    update_neighbors(world, scan);
  }
  // Forces at the new configuration, then velocity Verlet's closing half kick, in one team of
  // threads (the stages time themselves) — or the kick is left to the next step's first pass,
  // or that whole first pass is done here as well, each particle once its force is final
  // (then booked under "pair forces" and "surface forces").
  if (end == StepEnd::next_opened) {
    const OpeningPass next = OpeningPass::of(world, verlet ? 0.5 * dt : 0.0, opening_kick, dt);
    compute_forces_and_kick(world, 0.0, &next);
  } else {
    compute_forces_and_kick(world, verlet && !defer ? 0.5 * dt : 0.0);
    if (defer) world.pending_kick = 0.5 * dt;
  }
  {
    ScopedStage timer(world.timers, world.timers.stage("guards"));
    if (world.excessive_overlap) complete_step(world);  // the report shows the final velocities
    check_overlaps(world);
  }
}

void complete_step(World& world) {
  if (world.next_opened)
    throw std::logic_error("complete_step: the next step's opening pass is done; only step() may follow");
  if (world.pending_kick == 0.0) return;
  integrate::kick(world.particles, world.pending_kick);
  world.pending_kick = 0.0;
}

void advance(World& world, std::uint64_t steps) {
  for (std::uint64_t s = 0; s < steps; ++s) step(world, s + 1 < steps ? StepEnd::next_opened : StepEnd::complete);
}

}  // namespace quarry::sim
