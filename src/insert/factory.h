// Factory: inserts the particles of one deck factory — all at once or at a mass rate — at
// random non-overlapping positions inside its region (called by the sim between time steps,
// every few steps). Sizes from SizeSampler, positions from Region, randomness from Random.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "core/particle_store.h"
#include "core/periodic_box.h"
#include "core/simulation_spec.h"
#include "insert/random.h"
#include "insert/region.h"
#include "insert/size_distribution.h"

namespace quarry {

// What a factory needs to know about its particle type (resolved by the sim from the deck).
struct ParticleTypeInfo {
  std::uint16_t type_index = 0, material_index = 0;
  double density = 0.0;  // kg/m³
  SizeDistributionSpec size;
  bool fixed = false;    // particles that do not move (ParticleStore::make_fixed)
};

// Answers whether a sphere (centre m, radius m) would overlap any surface (the sim supplies it).
using SurfaceOverlapQuery = std::function<bool(const Vec3& centre, double radius)>;

// Outcome of one insert_due call.
struct InsertionReport {
  std::int64_t inserted = 0;  // particles placed by this call
  std::int64_t failed = 0;    // due particles that found no free place (kept for the next call)
  double inserted_mass = 0;   // kg placed by this call
};

// Rules (all deterministic: the same seed and the same call times give the same particles):
// - Due amount at time t (s), with t capped at stop_time: without mass_rate everything at
//   start_time; with mass_rate the due mass is mass_rate · (t − start_time), up to the target.
//   A count target with a rate follows the same mass schedule and releases the remaining count
//   once t ≥ start_time + target_count · mean mass / mass_rate.
// - A radius is drawn for each due particle (the sampler's mass bookkeeping counts it from then
//   on). Mass schedule: draw while the drawn mass < due mass − ½ mean particle mass, so the
//   final mass lies within one particle mass of the target (at least target − ½ mean mass).
// - Placement: up to max_attempts random centres per particle, each at least its radius inside
//   the region, rejected if it overlaps an existing particle (any in the store near the region),
//   an earlier new one, or a surface. A particle that finds no place keeps its radius and is
//   retried first at the next call, so a momentarily full region catches up later; nothing is
//   dropped silently: shortfall() counts what is still missing.
// - A call at time ≥ stop_time is the last: it places what was due at stop_time, then the
//   factory is finished.
class Factory {
 public:
  // Throws UserError for an invalid spec (both or neither of target_count / target_mass,
  // non-positive target or rate, stop_time < start_time, max_attempts < 1, a region too small
  // for the largest particle) or an invalid region or size distribution. Precondition:
  // type.density > 0.
  Factory(const FactorySpec& spec, const ParticleTypeInfo& type, std::uint64_t seed);

  // Inserts the particles due at `time` (s) into `particles` with ids next_id, next_id + 1, …
  // (next_id is advanced), initial velocity and angular velocity from the spec, creation time `time`.
  // Cost: O(particles.size()) to find those near the region, plus O(due × max_attempts) local
  // overlap tests and surface queries. `stop_requested`, if given, is asked every 1024
  // particles: when it says yes the call returns at once, the rest still due (placed by a later
  // call), so that a stop asked for during a long insertion is taken.
  InsertionReport insert_due(double time, ParticleStore& particles, ParticleId& next_id,
                             const SurfaceOverlapQuery& touches_surface,
                             const std::function<bool()>& stop_requested = {});

  // Target reached (everything drawn and placed), or a call at time ≥ stop_time has happened.
  bool finished() const;
  // Particles of the target not inserted yet (for a mass target: the particles waiting for a
  // place plus the not-yet-drawn rest of the target in mean particle masses, rounded up). The
  // sim reports it as a warning when finished() and it is > 0.
  std::int64_t shortfall() const;
  std::int64_t inserted_count() const { return inserted_count_; }
  double inserted_mass() const { return inserted_mass_; }  // kg
  std::int64_t waiting_count() const { return static_cast<std::int64_t>(waiting_radii_.size()); }
  const FactorySpec& spec() const { return spec_; }
  const Region& region() const { return region_; }
  // The domain's periodic axes (issue #20): a new particle must not overlap an existing one
  // through a periodic face either. Default: none.
  void set_periodic(const PeriodicBox& periodic) { periodic_ = periodic; }

  // Checkpoint: all mutable state (generator, sampler, counters, waiting radii) as 64-bit
  // words (doubles bit-cast). load_state on a factory built from the same spec and type
  // continues exactly as the saved one would have. load_state throws UserError if the words
  // are not a factory state of this spec.
  std::vector<std::uint64_t> save_state() const;
  void load_state(const std::vector<std::uint64_t>& state);

 private:
  void draw_due_radii(double time);
  void draw_one();
  double particle_mass(double radius) const;  // kg
  bool fully_drawn() const;

  FactorySpec spec_;
  ParticleTypeInfo type_;
  Region region_;
  PeriodicBox periodic_;
  SizeSampler sampler_;
  Random random_;
  double mean_particle_mass_ = 0.0;  // kg
  // ---- mutable state (saved in checkpoints) ----
  std::int64_t drawn_count_ = 0;  // radii drawn so far (placed or waiting)
  double drawn_mass_ = 0.0;       // kg
  std::int64_t inserted_count_ = 0;
  double inserted_mass_ = 0.0;         // kg
  std::vector<double> waiting_radii_;  // m, drawn but not yet placed, in draw order
  bool closed_ = false;                // a call at time ≥ stop_time has happened
};

}  // namespace quarry
