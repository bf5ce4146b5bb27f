// World: everything a running simulation owns — particles, surfaces, materials, factories,
// neighbour lists with contact history, time. Built from a SimulationSpec (no deck needed);
// advanced by sim::step (step.h). Plain data with a few helpers; no virtual dispatch.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "contact/contact_law.h"
#include "core/particle_store.h"
#include "core/simulation_spec.h"
#include "core/stage_timer.h"
#include "geometry/mesh_topology.h"
#include "geometry/surface.h"
#include "geometry/surface_contact.h"
#include "geometry/surface_grid.h"
#include "insert/factory.h"
#include "neighbor/pair_list.h"

namespace quarry {

// Interaction parameters for every ordered pair of materials (symmetric).
struct MaterialTable {
  std::vector<std::string> names;
  std::vector<MaterialProperties> properties;
  std::vector<InteractionParameters> pairs;  // count × count
  std::size_t count() const { return names.size(); }
  const InteractionParameters& between(std::size_t a, std::size_t b) const {
    return pairs[a * names.size() + b];
  }
};

// Particle–surface contacts of one particle, kept in fixed slots so that tangential history
// follows a contact while it slides from triangle to triangle.
inline constexpr int kWallSlots = 6;
struct WallSlot {
  std::int32_t surface = -1;   // -1: empty slot
  Vec3 normal;                 // unit, surface → particle, at the last step
  ContactHistory history;
  // This step's result, gathered onto the surface's triangles in a fixed order.
  std::uint32_t triangle = 0;
  std::array<double, 3> weights{};
  Vec3 point;                  // m
  Vec3 force_on_particle;      // N
};

// Candidate triangles per particle for particle–surface contacts, rebuilt with the pair list
// (triangles whose bounding box comes within skin of the particle).
struct SurfaceCandidates {
  std::vector<std::uint32_t> offsets;         // n+1
  std::vector<std::uint16_t> surface;         // per entry
  std::vector<std::uint32_t> triangle;        // per entry
  std::vector<std::vector<Vec3>> vertices_at_build;  // per surface (m)
};

struct World {
  SimulationSpec spec;
  ParticleStore particles;
  std::vector<Surface> surfaces;
  std::vector<MeshTopology> topologies;
  std::vector<SurfaceGrid> grids;
  std::vector<MotionSpec> motions;
  MaterialTable materials;
  std::vector<ParticleTypeInfo> types;
  std::vector<std::string> type_names;
  std::vector<Factory> factories;

  PairList pairs;
  std::vector<Vec3> pair_force;       // N on i, per pair (j gets the opposite)
  std::vector<Vec3> pair_torque_i;    // N·m
  std::vector<Vec3> pair_torque_j;    // N·m
  std::vector<double> pair_overlap;   // m (> 0: touching)
  SurfaceCandidates candidates;
  std::vector<WallSlot> wall_slots;   // kWallSlots per particle

  double time = 0.0;                  // s
  std::uint64_t step_count = 0;
  double dt = 0.0;                    // s
  double skin = 0.0;                  // m
  double max_radius = 0.0;            // m, largest particle radius that can exist
  ParticleId next_id = 1;
  std::uint64_t removed_outside = 0;  // particles that left the domain
  std::uint64_t steps_since_sort = 0;
  int insertion_interval_steps = 1;
  std::uint64_t rebuilds = 0;
  bool excessive_overlap = false;     // set by the force stage for the overlap guard
  bool lists_stale = true;            // particles were added/removed: rebuild before forces
  std::vector<std::string> warnings;  // reported once (e.g. factory shortfall)

  StageTimers timers;

  bool has_moving_surfaces() const;
  std::size_t pair_contact_count() const;   // pairs with overlap > 0
  std::size_t wall_contact_count() const;
};

// Builds the world: material table, surfaces (STL or primitives), factories, time step.
// Throws UserError (with the deck locations) for problems only visible now, e.g. a time step
// too large for the Hertz contact time.
World build_world(const SimulationSpec& spec);

// The particle types' info for factories and estimates.
std::vector<ParticleTypeInfo> particle_type_infos(const SimulationSpec& spec);

}  // namespace quarry
