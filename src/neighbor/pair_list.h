// PairList: half Verlet list (pairs i < j closer than Ri + Rj + skin; Verlet, Phys. Rev. 159
// (1967) 98) in CSR form with per-pair contact history. Rebuilt in time-step stage 2 when a
// particle moved > skin/2; the force stage (stage 3) iterates it row by row.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/particle_store.h"
#include "core/scratch_array.h"
#include "core/vec3.h"
#include "neighbor/cell_grid.h"
#include "core/counting_sort.h"

namespace quarry {

// Scratch memory of build_pair_list, kept between builds so that a warmed-up rebuild does not
// allocate. Not part of the list's meaning; callers never read it. Sized for a low peak:
// the build never holds more than the new list, the previous list's *contacts* (pairs with
// history) and a few integers per particle.
struct PairListWorkspace {
  CellGrid grid;
  std::vector<Vec3> wrapped_positions;         // m, moved into the period (periodic axes only)
  std::vector<std::uint32_t> old_index_of;     // per new particle: index at the last build
  std::vector<std::uint32_t> id_table;         // id → index at the last build (~0u: none);
  std::vector<ParticleId> id_table_keys;       //   dense by id when ids are compact, else hashed
  // The previous build's pairs that carry history, kept while the new list is made.
  std::vector<std::uint32_t> previous_offsets;   // n_previous + 1
  // Written in parallel before they are read: no serial zeroing pass (core/scratch_array.h).
  ScratchArray<std::uint32_t> previous_partner;
  ScratchArray<Vec3> previous_tangential_displacement;  // m
  ScratchArray<double> previous_normal_force;           // N
  ScratchArray<Vec3> previous_rolling_torque;           // N·m (empty unless rolling history)
  ScratchArray<std::uint8_t> previous_jkr_attached;     // 0/1 (empty unless JKR history)
  std::vector<ParticleId> previous_ids;
};

struct PairList {
  std::vector<std::uint32_t> offsets;   // n+1; pairs of i are [offsets[i], offsets[i+1])
  std::vector<std::uint32_t> partner;   // j > i (index), ascending within each i
  // Contact history aligned with `partner` (carried across rebuilds by particle-id pair):
  std::vector<Vec3> tangential_displacement;   // m
  // N: the contact's normal force of the last step, + repulsive (ContactHistory::normal_force).
  std::vector<double> normal_force;
  std::vector<Vec3> rolling_torque;            // N·m; empty unless keep_rolling_history
  // 1 while a JKR contact adheres (ContactHistory::jkr_attached), which it does beyond touching
  // down to δ_c < 0; empty unless keep_jkr_history. Symmetric in the pair.
  std::vector<std::uint8_t> jkr_attached;
  std::vector<Vec3> reference_positions;       // m, positions at the last build
  std::vector<ParticleId> ids_at_build;        // particle ids at the last build (index order)
  double skin = 0;                             // m
  std::size_t builds = 0;
  // Only the EPSD rolling model has a rolling-torque history; without it the array would be
  // 24 bytes per pair of nothing (World sets this from the material table).
  bool keep_rolling_history = true;
  // Only JKR interactions adhere (World sets this from the material table).
  bool keep_jkr_history = false;
  // Periodic axes of the domain (World sets this from the spec): pairs are found across the
  // periodic faces and their separation is the minimum image (core/periodic_box.h). Each pair
  // is listed once, for its nearest image: the period must be at least
  // shortest_period(R_max, skin) so that no second image is within reach.
  PeriodicBox periodic;
  PairListWorkspace workspace;

  std::size_t size() const { return partner.size(); }
  // True if the last build was for these n particles: its reference positions and ids can be
  // compared with theirs, index by index.
  bool built_for(std::size_t n) const { return reference_positions.size() == n && ids_at_build.size() == n; }
};

// Rebuilds the list: pairs i < j with |xj − xi|² < ((Ri + Rj) + skin)² (evaluated in exactly
// this order in double precision, so a brute-force check with the same expression agrees;
// xj − xi is the minimum image list.periodic.minimum_image(xj − xi) when some axis is periodic).
// History of pairs present at the last build is carried over, matched by ParticleStore::id,
// so it survives re-sorting, removal and insertion between builds; new pairs start with zero
// history. History is stored as seen from the lower index i (δt of i relative
// to j, rolling torque on i): if a re-sort makes the former partner the lower index, both
// vectors are negated, so contact kernels must treat them as antisymmetric in the pair.
// Also refreshes reference_positions and ids_at_build.
// Deterministic: the same particles give the same list, bit for bit, for any thread count.
// Pre: skin ≥ 0; ids unique; n < 2^32 and fewer than 2^32 pairs. Throws PhysicsError if a
// position is not finite. Cost: O(n + pairs) with a cell grid of edge 2·Rmax + skin, two
// passes (count, fill) so that no pair buffer is needed; OpenMP over particle ranges.
void build_pair_list(const ParticleStore& particles, double skin, PairList& list);

// Takes the particles flagged in `removed` (by index at the last build) out of the list as
// ParticleStore::remove_flagged takes them out of the store (keeping the others' order): their
// rows and every pair with one of them go; the other pairs keep their order, their history and
// their reference positions, partners renumbered. What the list then holds is what a build
// for the remaining particles at the last build's positions would hold, so the rebuild
// criterion goes on from the last build (issue 21: a hopper whose outflow left the domain a
// few particles at a time rebuilt its lists at every such step). Bumps `builds` (the list
// changed). Pre: built_for(removed.size()). Cost: O(n + pairs), serial.
void remove_from_pair_list(PairList& list, const std::vector<char>& removed);

// True if the lists must be rebuilt before they can be trusted: never built, the particle
// count or ids (order) changed, or, with d = max_i |xi − xi(build)| and s the largest
// displacement of a moving surface's vertex since the build (m):
//   d > skin/2        two particles that were not listed (gap > skin) may now touch;
//   d + s > skin      a triangle that was not a candidate (its box farther than R + skin from
//                     the particle's centre) may now touch it: the gap closes by at most d + s
//                     (a point of a triangle moves by a convex mix of its vertices' moves).
// Cost: O(n), one parallel pass over positions; the answer does not depend on thread count.
bool pair_list_needs_rebuild(const ParticleStore& particles, const PairList& list,
                             double surface_displacement = 0.0);

// The same decision from a pass over the particles that the caller made itself (the time step
// folds it into the drift): `largest_displacement_squared` = max_i |xi − xi(build)|² (m²),
// `ids_changed` = some id differs from ids_at_build. Pre: the particle count is that of the build.
bool pair_list_needs_rebuild(const PairList& list, double largest_displacement_squared, bool ids_changed,
                             double surface_displacement);

}  // namespace quarry
