// One time step of the simulation and the stages it is made of, in the order step() runs them
// (DESIGN §2). After initialize() and after every step() the state is complete: positions,
// velocities and forces belong to one time, nothing is left half done, so a coupling partner
// may read and write between calls.
#pragma once

#include <span>

#include "sim/world.h"

namespace quarry::sim {

// Brings a freshly built (or changed) world to a complete state at its current time: surfaces
// at their driver's pose, particles due from the factories inserted, lists built, forces of the
// configuration computed (body, contact, post-force hooks). Idempotent in what it leaves, but
// it evaluates the contacts, so call it once, before the first step. Throws UserError or
// PhysicsError as step() does.
void initialize(World& world);

// Advances the world by one time step dt: the stages below, then the output due at the new
// time. Throws PhysicsError if the state becomes invalid (the world then holds the step's state
// for the report). Pre: initialize() has run.
void step(World& world);

// `steps` steps.
void advance(World& world, std::uint64_t steps);

// What the opening kick-drift saw of the new state (kick_drift_scan): the pass's tally, and
// where it stands. Three stages would each read every position again for it — the NaN guard,
// the domain check, the list's displacement check — so the step takes it from the drift's own
// pass over the particles instead.
struct DriftScan : OpeningTally {
  std::size_t particles = 0;         // n at the scan
  std::size_t first_non_finite = 0;  // first index with a non-finite x, v or ω; n if none
  bool list_compared = false;        // the list was built for these n particles: the tally's
                                     // ids_changed and largest displacement hold
};

// ---- stages, in the order step() calls them; exposed for tests and the coupling interface ----
// Kick by h (s), drift by dt (s), and scan the new state.
DriftScan kick_drift_scan(World& world, double h, double dt);
void check_finite(const World& world, const DriftScan& scan);  // NaN/inf guard (after the drift)
// Tunnelling guard (after the drift): a particle that moved more than half its radius in the
// drift and passed within its radius of a surface on the way stops the run (PhysicsError): its
// contact cannot be resolved, and a thin wall can be crossed without being seen. Costs nothing
// unless scan.fast.
void check_tunnelling(const World& world, const DriftScan& scan, double dt);
// Moves every surface to its driver's pose at `time` (s): prescribed motion, or a coupled
// surface's last set vertices moved on with their velocities.
void drive_surfaces(World& world, double time);
void insert_and_remove(World& world,
                       const DriftScan& scan);  // factories; particles leaving the domain
void update_neighbors(World& world, const DriftScan& scan);  // Verlet/candidate lists when needed
// particles.force = m g + held external force, torque = held external torque: the sums the
// contact stage adds onto. (One-step loads stay apart: the kicks add them.)
void set_body_forces(World& world);
// The per-particle leads h F/m and h τ/I (m/s, rad/s) from the forces of the step before (with
// the one-step loads kept apart, as the opening kick used them), which
// carry the drift velocities to the force's time for the contact dashpots (ContactKinematics):
// h = dt/2 in velocity Verlet, 0 where the velocities are already those of the force's time.
// Call before set_body_forces overwrites the forces.
void set_velocity_leads(World& world, double h);
// Velocity Verlet's closing half kick by h (s): v += h F/m, ω += h τ/I with the step's forces
// (and the one-step loads kept apart), as integrate::kick_particle on each particle.
void closing_kick(World& world, double h);
// Particle–particle and particle–surface contacts added onto the body forces; the surfaces'
// per-step loads (per triangle and vertex) filled.
void compute_contact_forces(World& world);
void run_hooks(World& world, HookStage stage);  // post_force, end_of_step, end_of_run
void check_overlaps(const World& world);        // overlap guard (after the forces)
// The loads of the step added to every sized load window; the one-step external loads expire
// (taken out of the forces if settle_once_loads had put them there, and zeroed).
void end_of_step_loads(World& world);

// The same stages when no scan is at hand (after changes from outside): a pass of their own.
void check_finite(const World& world);
void insert_and_remove(World& world);
void update_neighbors(World& world, bool force_rebuild);

// Rebuilds every list now (after particles were added/removed/moved from outside).
void rebuild_lists(World& world);

// ---- changes from outside, between steps (the coupling interface) ----
// Sets a coupled surface's vertices (m) and velocities (m/s; empty: at rest) at the world's
// time; the surface then moves on with those velocities until the next set (drive_surfaces).
// Throws std::logic_error if the surface is not coupled, std::invalid_argument on a size that
// is not its vertex count.
void set_surface_vertices(World& world, std::size_t surface, std::span<const Vec3> positions,
                          std::span<const Vec3> velocities);

}  // namespace quarry::sim
