// One time step of the simulation, and the stages it is made of (DESIGN §2).
#pragma once

#include "sim/world.h"

namespace quarry::sim {

struct OpeningPass;

// How step() leaves the world.
enum class StepEnd {
  // The step is complete: velocities and positions are the step's final ones.
  complete,
  // Velocity Verlet's closing half kick is left pending (World::pending_kick), for the next
  // step's opening pass, which reads and writes every particle's velocity anyway: the same
  // operations in the same order, so the same bits, with one pass over the particles less per
  // step. Whoever looks at the velocities between steps (monitors, output, checkpoints) calls
  // complete_step() first.
  kick_pending,
  // Further still: the force stage does the next step's whole opening pass (closing kick,
  // opening kick, drift, and the scan of the new state), each particle as soon as its force is
  // final, while its data is still in cache — no pass over the particles of its own at all.
  // The state is then between the next step's opening pass and the rest of it, which cannot be
  // undone: only step() may follow (complete_step() and checkpoints refuse it). For callers
  // that know the next step follows with nothing looking in between (sim::advance, the run
  // loop between outputs). If the force stage finds an excessive overlap, the run is to stop
  // at this step: the opening is taken back (to within rounding, OpeningPass::undo) and the
  // step ends complete, so that the guard's report and the last frame show this step's state.
  next_opened,
};

// Advances the world by one time step dt. Throws PhysicsError if the state becomes invalid.
void step(World& world, StepEnd end = StepEnd::complete);
// Applies a pending closing kick (nothing if there is none). Throws std::logic_error if the
// next step's opening pass is already done (StepEnd::next_opened): that cannot be completed.
void complete_step(World& world);
// `steps` steps, each leaving the next step's opening pass to its force stage but the last,
// which ends complete.
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

// Stages, in the order step() calls them; exposed for tests and the C ABI.
// Kick by the pending closing kick (if any), then by h (s), drift by dt (s); clears the pending kick.
DriftScan kick_drift_scan(World& world, double h, double dt);
void move_surfaces(World& world, double time);           // prescribed motion at `time` (s)
void insert_and_remove(World& world);                    // factories; particles leaving the domain
void update_neighbors(World& world, bool force_rebuild); // Verlet/candidate lists when needed
void compute_forces(World& world);                        // contacts, gravity, external forces
// compute_forces, then every particle kicked by h (s): the closing half kick of velocity
// Verlet in the same team of threads (the same bits as compute_forces, then integrate::kick).
// With `next`, each particle also takes that opening pass of the next step once its force is
// final (StepEnd::next_opened; then h is 0).
void compute_forces_and_kick(World& world, double h, const OpeningPass* next = nullptr);
void check_finite(const World& world);                    // NaN/inf guard (after the drift)
void check_overlaps(const World& world);                  // overlap guard (after the forces)
// The same stages taking what the drift's scan saw instead of a pass of their own.
void check_finite(const World& world, const DriftScan& scan);
void insert_and_remove(World& world, const DriftScan& scan);
void update_neighbors(World& world, const DriftScan& scan);

// Rebuilds every list now (after particles were added/removed/moved from outside).
void rebuild_lists(World& world);

}  // namespace quarry::sim
