// One time step of the simulation, and the stages it is made of (DESIGN §2).
#pragma once

#include "sim/world.h"

namespace quarry::sim {

// Advances the world by one time step dt. Throws PhysicsError if the state becomes invalid.
void step(World& world);

// Stages, in the order step() calls them; exposed for tests and the C ABI.
void move_surfaces(World& world, double time);           // prescribed motion at `time` (s)
void insert_and_remove(World& world);                    // factories; particles leaving the domain
void update_neighbors(World& world, bool force_rebuild); // Verlet/candidate lists when needed
void compute_forces(World& world);                        // contacts, gravity, external forces
void check_finite(const World& world);                    // NaN/inf guard (after the drift)
void check_overlaps(const World& world);                  // overlap guard (after the forces)

// Rebuilds every list now (after particles were added/removed/moved from outside).
void rebuild_lists(World& world);

}  // namespace quarry::sim
