// One time step of the simulation, and the stages it is made of (DESIGN §2).
#pragma once

#include "sim/world.h"

namespace quarry::sim {

// Advances the world by one time step dt. Throws PhysicsError if the state becomes invalid.
// With defer_closing_kick, velocity Verlet's closing half kick is left pending
// (World::pending_kick) and done by the next step's opening pass, which reads and writes every
// particle's velocity anyway: the same operations in the same order, so the same bits, with
// one pass over the particles less per step. Until complete_step(), the velocities are then
// half a kick short: whoever looks at them between steps (monitors, output, checkpoints)
// completes the step first.
void step(World& world, bool defer_closing_kick = false);
// Applies a pending closing kick (nothing if there is none).
void complete_step(World& world);
// `steps` steps, each closing kick done by the next step's opening pass; completed at the end.
void advance(World& world, std::uint64_t steps);

// What the opening kick-drift saw of the new state (kick_drift_scan). Three stages would each
// read every position again for it — the NaN guard, the domain check, the list's displacement
// check — so the step takes it from the drift's own pass over the particles instead.
struct DriftScan {
  std::size_t particles = 0;         // n at the scan
  std::size_t first_non_finite = 0;  // first index with a non-finite x, v or ω; n if none
  bool any_outside = false;          // some particle is outside the domain
  bool list_compared = false;        // the list was built for these n particles: the two below hold
  bool ids_changed = false;          // some id differs from the list's ids at build
  double largest_displacement_squared = 0.0;  // m², max |xi − xi(build)|² over finite particles
};

// Stages, in the order step() calls them; exposed for tests and the C ABI.
// Kick by the pending closing kick (if any), then by h (s), drift by dt (s); clears the pending kick.
DriftScan kick_drift_scan(World& world, double h, double dt);
void move_surfaces(World& world, double time);           // prescribed motion at `time` (s)
void insert_and_remove(World& world);                    // factories; particles leaving the domain
void update_neighbors(World& world, bool force_rebuild); // Verlet/candidate lists when needed
void compute_forces(World& world);                        // contacts, gravity, external forces
// compute_forces, then every particle kicked by h (s): the closing half kick of velocity
// Verlet in the same team of threads (the same bits as compute_forces, then integrate::kick).
void compute_forces_and_kick(World& world, double h);
void check_finite(const World& world);                    // NaN/inf guard (after the drift)
void check_overlaps(const World& world);                  // overlap guard (after the forces)
// The same stages taking what the drift's scan saw instead of a pass of their own.
void check_finite(const World& world, const DriftScan& scan);
void insert_and_remove(World& world, const DriftScan& scan);
void update_neighbors(World& world, const DriftScan& scan);

// Rebuilds every list now (after particles were added/removed/moved from outside).
void rebuild_lists(World& world);

}  // namespace quarry::sim
