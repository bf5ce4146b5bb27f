// Changes made to a world from outside, between steps: the particle, load and surface operations
// the coupling interface (include/quarry/quarry.h) is built on. Each leaves the state complete
// (DESIGN §2), so the next step starts from a consistent world.
#pragma once

#include <cstdint>
#include <span>
#include <unordered_map>
#include <vector>

#include "sim/world.h"

namespace quarry::sim {

struct NewParticle {
  std::uint16_t type = 0;     // particle-type index
  Vec3 position;              // m
  Vec3 velocity;              // m/s
  Vec3 angular_velocity;      // rad/s
  double radius = 0.0;        // m; ≤ 0: drawn from the type's size distribution
  ParticleId id = 0;          // 0: the next free id; else this id (kept from a file)
};

// Adds particles at the world's time and returns their new ids (in the order given). Their
// force is set to the body forces (gravity); contacts they make act from the next step's force
// stage on (the lists are rebuilt then). Throws std::invalid_argument, naming the entry, for an
// unknown type, a non-finite value, a radius above the largest the world was sized for, or a
// position outside the domain, or a given id that exists already (or is given twice); nothing is
// added then. A given id moves next_id past it, so later ids never collide. Cost: O(added) plus
// a list rebuild (and O(n) to check given ids against the particles there are).
std::vector<ParticleId> add_particles(World& world, std::span<const NewParticle> particles);

// Removes the particles with these ids. Throws std::invalid_argument naming the first id that
// does not exist (or is given twice); nothing is removed then. The remaining particles' forces
// keep the removed ones' contacts until the next force stage. Cost: O(n).
void remove_particles(World& world, std::span<const ParticleId> ids);

enum class LoadMode : std::uint8_t { add, replace };
enum class LoadHold : std::uint8_t { next_step, until_changed };

// External force (N) and torque (N·m) on particles, by engine index: entry k applies to particle
// indices[k] (indices empty: entry k to particle k, and then there is one entry per particle).
// `forces` and `torques` hold 3 doubles per entry (x, y, z), or are empty (left as they are).
// With `replace` the value replaces the particle's held (or one-step) load, with `add` it is added
// to it. Held loads act until changed; one-step loads act in the next step only.
// Held loads are part of particles.force and torque at once (the next opening kick uses them);
// one-step loads stay apart from them (the step's kicks add them, ParticleStore::once_in_forces)
// unless something has settled them into the forces (settle_once_loads). Throws
// std::invalid_argument on a size mismatch, an index out of range or given twice, or a
// non-finite value (nothing changed then). Cost: one pass over the entries to check them and one
// over the particles' loads and forces, on the world's threads.
void set_external_loads(World& world, std::span<const std::uint32_t> indices, std::span<const double> forces,
                        std::span<const double> torques, LoadMode mode, LoadHold hold);

// The next step's one-step loads as arrays a partner writes in place (the C ABI's writable view,
// zero copies): particles.external_force_once and external_torque_once, by engine index, as they
// stand (zeros after a step; what set_external_loads put there before). They are kept apart from
// force/torque (taken out if settle_once_loads had put them there); the step's kicks add them,
// formed as set_external_loads(replace, next_step) with the written values would have them, bit
// for bit.
// Cost: nothing after a step; one pass over the particles when the loads were inside the forces.
// `field`: ParticleStore::kForceLoads or kTorqueLoads, the array the caller will write.
void open_once_loads(World& world, std::uint8_t field);
// Adds the one-step loads kept apart to force/torque (one pass), so that what reads the forces
// outside the kicks (the C ABI's copies and views, checkpoints) sees the whole of them; nothing
// when there are none, or when they are inside already. The kicks then use the forces alone.
void settle_once_loads(World& world);
// The inverse: takes the one-step loads out of force/torque where settle_once_loads had put them
// (one pass), so that they are apart again; nothing otherwise. (F + L) − L is F only to within an
// ulp of F + L.
void unsettle_once_loads(World& world);

// The particles in type order (seed 004: all of type 0, then type 1, …; within a type by engine
// index): order[k] is the engine index of the k-th particle; type_start[t] the first position of
// type t (types + 1 entries). Remade only when the layout epoch changed. Cost: O(n) then.
struct TypeOrder {
  std::uint64_t epoch = ~std::uint64_t{0};
  std::size_t particles = ~std::size_t{0};
  std::vector<std::uint32_t> order;
  std::vector<std::uint64_t> type_start;
  bool identity = false;  // order[k] == k for every k (one type, or types already grouped)
};
void update_type_order(const World& world, TypeOrder& order);

// Engine index of every particle id, remade when the layout epoch changed. Cost: O(n) then,
// O(1) a look-up.
struct IdIndex {
  std::uint64_t epoch = ~std::uint64_t{0};
  std::size_t particles = ~std::size_t{0};
  std::unordered_map<ParticleId, std::uint32_t> index;
};
void update_id_index(const World& world, IdIndex& ids);

}  // namespace quarry::sim
