// The time step, read top to bottom (DESIGN §2). Velocity Verlet: half kick, drift, move the
// geometry, forces at the new configuration, half kick. Symplectic Euler: full kick with the
// forces of the previous configuration, drift, geometry, forces. The order matters: forces
// are always computed at one consistent configuration of particles and surfaces.
#include "sim/step.h"

#include "integrate/integrator.h"

namespace quarry::sim {

void step(World& world) {
  const double dt = world.dt;
  const bool verlet = world.spec.simulation.integrator.value == Integrator::velocity_verlet;
  DriftScan scan;  // what the drift saw: NaNs, particles outside the domain, displacements
  {
    ScopedStage timer(world.timers, world.timers.stage("integrate"));
    scan = kick_drift_scan(world, verlet ? 0.5 * dt : dt, dt);
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
  // threads (the stages time themselves).
  compute_forces_and_kick(world, verlet ? 0.5 * dt : 0.0);
  {
    ScopedStage timer(world.timers, world.timers.stage("guards"));
    check_overlaps(world);
  }
}

}  // namespace quarry::sim
