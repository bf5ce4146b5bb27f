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
  // External loads set by a coupling partner (N, N·m): `held` act until changed, `once` for
  // the next step only. Held loads are part of `force`/`torque` (the body-force stage adds
  // them); one-step loads are kept apart and added by the kicks as they use the forces (see
  // once_in_forces). Empty until enable_external_loads(): most runs have none, and 96 bytes per
  // particle of zeros would be read every step.
  std::vector<Vec3> external_force;
  std::vector<Vec3> external_torque;
  std::vector<Vec3> external_force_once;
  std::vector<Vec3> external_torque_once;
  // Which of these arrays may hold non-zero values (kForceLoads | kTorqueLoads, held and one-step
  // apart): the stages that read loads skip the others (a partner that sets forces only never
  // has torques read). The end of a step zeroes the one-step loads.
  // once_in_forces: the one-step loads are inside force/torque, because something outside the
  // step read or saved the forces (sim::settle_once_loads: what reads the forces sees the whole
  // of them). Else they stay apart and each kick adds them to the forces it uses (apart_once_loads):
  // a partner that writes them and steps costs the step two reads of them, not a pass that adds
  // them to the forces and one that takes them out again.
  static constexpr std::uint8_t kForceLoads = 1, kTorqueLoads = 2;
  std::uint8_t held_loads = 0, once_loads = 0;
  bool once_in_forces = false;
  // Custom per-particle properties (coupling or user data), stored in particle order,
  // `components` values per particle; they follow their particle through removal and re-sorts.
  struct CustomProperty {
    std::string name;
    std::string unit;               // SI unit as text ("K", "m/s"; "" dimensionless)
    std::uint32_t components = 1;
    double initial = 0.0;           // value of every component of a new particle
    std::vector<double> values;     // size() · components
  };
  std::vector<CustomProperty> custom;
  // Bumped whenever particle indices change (insertion, removal, re-sort): an index or a
  // pointer into the arrays taken at another epoch is stale (the C ABI's views carry it).
  std::uint64_t layout_epoch = 0;

  std::size_t size() const { return position.size(); }

  // Appends one particle at rest; returns its index. Mass from density and radius.
  std::size_t add(ParticleId pid, std::uint16_t type_index, std::uint16_t material_index,
                  const Vec3& x, const Vec3& v, double radius_m, double density, double time);
  // Removes the particles whose flag is set, keeping the order of the others. O(n).
  void remove_flagged(const std::vector<char>& remove);
  // Reorders every array so that new index k holds old index order[k].
  void permute(const std::vector<std::size_t>& order);
  // Adds a custom property of `components` values per particle, every particle's set to
  // `initial`; returns its index. A name already registered returns the existing index
  // (throws std::invalid_argument if its components differ). Pre: components ≥ 1.
  std::size_t register_custom(const std::string& name, std::uint32_t components = 1,
                              double initial = 0.0, const std::string& unit = "");
  // Index of the custom property `name`, or custom.size() if there is none.
  std::size_t find_custom(const std::string& name) const;
  void reserve(std::size_t n);
  // Sizes the external-load arrays to the particles (zeros); no-op if already done.
  void enable_external_loads();
  bool has_external_loads() const { return external_loads_enabled; }
  // The one-step loads a kick adds to the forces it reads (null where there are none, or where
  // they are inside force/torque already).
  struct ApartLoads {
    const Vec3* force = nullptr;   // N
    const Vec3* torque = nullptr;  // N·m
    bool any() const { return force != nullptr || torque != nullptr; }
  };
  ApartLoads apart_once_loads() const {
    if (!external_loads_enabled || once_in_forces) return {};
    return {(once_loads & kForceLoads) ? external_force_once.data() : nullptr,
            (once_loads & kTorqueLoads) ? external_torque_once.data() : nullptr};
  }
  bool external_loads_enabled = false;
  void clear();

  // Makes particle i fixed (a `fixed: true` type): inv_mass 0 (infinite mass and inertia, so no
  // force moves or turns it), velocity and angular velocity zero.
  void make_fixed(std::size_t i) {
    inv_mass[i] = 0.0;
    velocity[i] = Vec3{};
    angular_velocity[i] = Vec3{};
  }
  bool fixed(std::size_t i) const { return inv_mass[i] == 0.0; }

  double mass(std::size_t i) const { return 1.0 / inv_mass[i]; }  // +inf for a fixed particle
  // 1/I (1/(kg·m²)) of the solid sphere, I = 2/5 m R²: derived, not stored (8 bytes per
  // particle saved; one division where it is needed).
  double inv_inertia(std::size_t i) const { return 2.5 * inv_mass[i] / (radius[i] * radius[i]); }
};

// Each particle's index after ParticleStore::remove_flagged(removed) (which keeps the order); a
// removed particle gets the index its next kept one will have. For what holds particle indices
// across a removal (the wall contacts, the neighbour lists).
std::vector<std::uint32_t> indices_after_removal(const std::vector<char>& removed);
// The index of the first particle flagged in `removed` (its size if none): what lies before it
// keeps its index and its place through a removal.
std::size_t first_removed(const std::vector<char>& removed);

}  // namespace quarry
