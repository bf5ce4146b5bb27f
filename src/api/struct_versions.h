// The C ABI's input structs across minor versions (include/quarry/quarry.h, "versioning"): a
// caller compiled against an older quarry.h passes the struct_size of its own, shorter struct,
// and must be served. So the least struct_size accepted is the struct's FIRST published size, not
// today's, and a struct that grew is read only as far as the caller's struct_size goes, the rest
// taking defaults. The first sizes come from the compiler: a struct that grew keeps its first
// layout frozen here (checked field by field against today's); every other struct is pinned at
// its last ABI 1.0 field, so that one growing cannot go unnoticed.
//
// Growing a struct: append the field; freeze the layout it had (as abi_1_0::quarry_settings);
// specialise kFirstPublishedSize if it is the first growth; read the new field only when the
// caller's struct_size covers it (as read_settings). A new field must make the struct longer:
// one that fits in the old struct's tail padding (sizeof unchanged) cannot be told from an old
// caller's padding bytes.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>

#include "quarry/quarry.h"

namespace quarry::api {

namespace abi_1_0 {

// quarry_settings as ABI 1.0 published it (it ended at seed).
struct quarry_settings {
  std::uint32_t struct_size;
  double time_step;
  double rayleigh_fraction;
  double gravity[3];
  double domain_min[3];
  double domain_max[3];
  double end_time;
  double impact_speed;
  double skin;
  std::int32_t integrator;
  std::int32_t sort_interval;
  double max_overlap_fraction;
  std::uint64_t seed;
};

}  // namespace abi_1_0

// Today's quarry_settings begins with 1.0's fields, each where it was.
#define QUARRY_SAME_PLACE(field)                                                                 \
  static_assert(offsetof(quarry_settings, field) == offsetof(abi_1_0::quarry_settings, field) && \
                    sizeof(quarry_settings::field) == sizeof(abi_1_0::quarry_settings::field),   \
                "quarry_settings." #field " moved: a minor version may only append fields")
QUARRY_SAME_PLACE(struct_size);
QUARRY_SAME_PLACE(time_step);
QUARRY_SAME_PLACE(rayleigh_fraction);
QUARRY_SAME_PLACE(gravity);
QUARRY_SAME_PLACE(domain_min);
QUARRY_SAME_PLACE(domain_max);
QUARRY_SAME_PLACE(end_time);
QUARRY_SAME_PLACE(impact_speed);
QUARRY_SAME_PLACE(skin);
QUARRY_SAME_PLACE(integrator);
QUARRY_SAME_PLACE(sort_interval);
QUARRY_SAME_PLACE(max_overlap_fraction);
QUARRY_SAME_PLACE(seed);
#undef QUARRY_SAME_PLACE
static_assert(offsetof(quarry_settings, periodic) >= sizeof(abi_1_0::quarry_settings),
              "quarry_settings.periodic (ABI 1.1) must lie past the end of a 1.0 caller's struct");

// The least struct_size accepted for T: its size in ABI 1.0, where every struct was first
// published.
template <class T>
inline constexpr std::size_t kFirstPublishedSize = sizeof(T);
template <>
inline constexpr std::size_t kFirstPublishedSize<quarry_settings> =
    sizeof(abi_1_0::quarry_settings);

// T ends at `last` (sizeof is last's end rounded up to T's alignment): a field appended after it
// fails this, so that the struct's 1.0 size is frozen above before it changes.
#define QUARRY_LAST_FIELD(T, last)                                                                 \
  static_assert(sizeof(T) == (offsetof(T, last) + sizeof(T::last) + alignof(T) - 1) / alignof(T) * \
                                 alignof(T),                                                       \
                #T " has a field after " #last                                                     \
                   ": freeze its earlier layout in api/struct_versions.h")
QUARRY_LAST_FIELD(quarry_settings, periodic);  // 1.1
QUARRY_LAST_FIELD(quarry_open_info, timeout_ms);
QUARRY_LAST_FIELD(quarry_material, poisson_ratio);
QUARRY_LAST_FIELD(quarry_interaction, cohesion_energy_density);
QUARRY_LAST_FIELD(quarry_particle_type, max_radius);
QUARRY_LAST_FIELD(quarry_advance_result, time);
QUARRY_LAST_FIELD(quarry_particle_data, epoch);
QUARRY_LAST_FIELD(quarry_new_particles, ids);
QUARRY_LAST_FIELD(quarry_surface_desc, driver);
QUARRY_LAST_FIELD(quarry_surface_info, driver);
QUARRY_LAST_FIELD(quarry_surface_loads, time);
#undef QUARRY_LAST_FIELD

// quarry_default_settings' values (here, not in api.cpp, for the server as well: a 1.0 client's
// request leaves the 1.1 fields to them).
inline quarry_settings default_settings() {
  quarry_settings s{};
  s.struct_size = sizeof s;
  s.rayleigh_fraction = 0.2;
  s.gravity[2] = -9.81;
  s.end_time = 1.0;
  s.skin = -1.0;
  s.integrator = QUARRY_INTEGRATOR_VELOCITY_VERLET;
  s.sort_interval = 1000;
  s.max_overlap_fraction = 0.1;
  s.seed = 12345;
  s.periodic[0] = s.periodic[1] = s.periodic[2] = 0;
  return s;
}

// A caller's settings as this library's struct: the bytes its struct_size covers (at least 1.0's:
// the caller checked struct_size ≥ kFirstPublishedSize) and the defaults for the fields of later
// minors its quarry.h did not have. Reads nothing past the caller's struct_size.
inline quarry_settings read_settings(const quarry_settings* caller) {
  quarry_settings s = default_settings();
  const auto* bytes = reinterpret_cast<const unsigned char*>(caller);
  std::memcpy(&s, bytes, sizeof(abi_1_0::quarry_settings));
  if (caller->struct_size >= offsetof(quarry_settings, periodic) + sizeof s.periodic)  // 1.1
    std::memcpy(s.periodic, bytes + offsetof(quarry_settings, periodic), sizeof s.periodic);
  s.struct_size = sizeof s;
  return s;
}

}  // namespace quarry::api
