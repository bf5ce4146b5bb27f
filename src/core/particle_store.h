// ParticleStore: all particles as a structure of arrays (one std::vector per property).
// Hot arrays (read or written every step) are kept apart from cold bookkeeping. Particle
// *indices* change (removal, spatial re-sort); particle *ids* are persistent 64-bit numbers.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "core/vec3.h"

namespace quarry {

using ParticleId = std::uint64_t;

// Loops over fewer particles than this run on one thread: below it, starting an OpenMP team
// costs more than the work. Results are bit-identical either way; the determinism tests set it
// to 0 so that small scenes do run on several threads.
inline std::size_t parallel_threshold = 2048;

struct ParticleStore {
  // ---- hot: the time step reads/writes these ----
  std::vector<Vec3> position;          // m
  std::vector<Vec3> velocity;          // m/s
  std::vector<Vec3> angular_velocity;  // rad/s
  std::vector<Vec3> force;             // N, total of the current step
  std::vector<Vec3> torque;            // N·m, total of the current step
  std::vector<double> radius;          // m
  std::vector<double> inv_mass;        // 1/kg
  std::vector<std::uint16_t> material; // index into the material table
  // ---- cold ----
  std::vector<ParticleId> id;          // persistent
  std::vector<std::uint16_t> type;     // index into the particle-type table
  std::vector<double> creation_time;   // s
  // Coupling loads (N, N·m), kept until changed. Empty until enable_external_loads(): most
  // runs have none, and 48 bytes per particle of zeros would be read every step.
  std::vector<Vec3> external_force;
  std::vector<Vec3> external_torque;
  // Custom per-particle properties (coupling/user data): name -> one double per particle.
  std::vector<std::string> custom_names;
  std::vector<std::vector<double>> custom_values;

  std::size_t size() const { return position.size(); }

  // Appends one particle at rest; returns its index. Mass from density and radius.
  std::size_t add(ParticleId pid, std::uint16_t type_index, std::uint16_t material_index,
                  const Vec3& x, const Vec3& v, double radius_m, double density, double time);
  // Removes the particles whose flag is set, keeping the order of the others. O(n).
  void remove_flagged(const std::vector<char>& remove);
  // Reorders every array so that new index k holds old index order[k].
  void permute(const std::vector<std::size_t>& order);
  // Adds a custom property initialised to `initial`; returns its index (existing: same index).
  std::size_t register_custom(const std::string& name, double initial);
  void reserve(std::size_t n);
  // Sizes external_force/external_torque to the particles (zeros); no-op if already done.
  void enable_external_loads();
  bool has_external_loads() const { return external_loads_enabled; }
  bool external_loads_enabled = false;
  void clear();

  double mass(std::size_t i) const { return 1.0 / inv_mass[i]; }
  // 1/I (1/(kg·m²)) of the solid sphere, I = 2/5 m R²: derived, not stored (8 bytes per
  // particle saved; one division where it is needed).
  double inv_inertia(std::size_t i) const { return 2.5 * inv_mass[i] / (radius[i] * radius[i]); }
};

}  // namespace quarry
