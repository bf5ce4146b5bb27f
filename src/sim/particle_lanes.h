// The step's per-particle passes four particles at a time (sim/opening_lanes.h,
// sim/particle_passes.cpp): the loads, stores and shuffles of Vec3 arrays they share (the
// vector types are core/lanes.h's). Each array of Vec3 is read as it lies in memory, four
// particles in three vectors (x y z x | y z x y | z x y z), with GCC's vector extension: AVX2
// in the release build, SSE2 pairs in a baseline one. The scalar opening pass was bound by its
// instructions, not by memory (docs/performance.md, "Four particles at a time").
//
// A pass built from these gives the scalar pass's values to the bit: the same operations in
// the same order lane by lane, so the results do not depend on which particles fall into
// blocks of four, hence not on the thread split. Internal linkage: include only from .cpp
// files of sim/.
#pragma once

#include <cstdint>

#include "core/lanes.h"
#include "core/particle_store.h"
#include "core/vec3.h"

namespace quarry::sim {
namespace {

static_assert(sizeof(Vec3) == 3 * sizeof(double), "four Vec3s are twelve packed doubles");

// Four consecutive Vec3s as they lie in memory.
struct Packed {
  Lanes a, b, c;  // x0 y0 z0 x1 | y1 z1 x2 y2 | z2 x3 y3 z3
};
static_assert(sizeof(Packed) == 4 * sizeof(Vec3));

[[gnu::always_inline]] inline Packed load4(const Vec3* v) {
  const double* const d = &v->x;
  return {load_lanes(d), load_lanes(d + 4), load_lanes(d + 8)};
}
[[gnu::always_inline]] inline void store4(Vec3* v, const Packed& p) {
  double* const d = &v->x;
  *reinterpret_cast<UnalignedLanes*>(d) = p.a;
  *reinterpret_cast<UnalignedLanes*>(d + 4) = p.b;
  *reinterpret_cast<UnalignedLanes*>(d + 8) = p.c;
}

[[gnu::always_inline]] inline Packed operator+(const Packed& p, const Packed& q) {
  return {p.a + q.a, p.b + q.b, p.c + q.c};
}
[[gnu::always_inline]] inline Packed operator-(const Packed& p, const Packed& q) {
  return {p.a - q.a, p.b - q.b, p.c - q.c};
}
[[gnu::always_inline]] inline Packed operator*(const Packed& p, const Packed& q) {
  return {p.a * q.a, p.b * q.b, p.c * q.c};
}
[[gnu::always_inline]] inline Packed operator*(const Packed& p, double s) {
  return {p.a * s, p.b * s, p.c * s};
}

// One value per particle (s0 s1 s2 s3) laid over its three components.
[[gnu::always_inline]] inline Packed spread(Lanes s) {
  return {__builtin_shuffle(s, Mask{0, 0, 0, 1}), __builtin_shuffle(s, Mask{1, 1, 2, 2}),
          __builtin_shuffle(s, Mask{2, 3, 3, 3})};
}

// Each particle's x + y + z of packed q, summed in that order (as norm2 does).
[[gnu::always_inline]] inline Lanes sum_components(const Packed& q) {
  const Lanes x = __builtin_shuffle(__builtin_shuffle(q.a, q.b, Mask{0, 3, 6, 7}), q.c, Mask{0, 1, 2, 5});
  const Lanes y = __builtin_shuffle(__builtin_shuffle(q.a, q.b, Mask{1, 4, 7, 7}), q.c, Mask{0, 1, 2, 6});
  const Lanes z = __builtin_shuffle(__builtin_shuffle(q.a, q.b, Mask{2, 5, 5, 5}), q.c, Mask{0, 1, 4, 7});
  return x + y + z;
}

// The force (N) or torque (N·m) a kick uses for particles [i, i + 4): the stored one plus the
// one-step load kept apart, null where none (integrate::kick_force, kick_torque).
template <bool kApart>
[[gnu::always_inline]] inline Packed kick_load4(const Vec3* stored, const Vec3* apart, std::size_t i) {
  const Packed load = load4(stored + i);
  if constexpr (kApart) if (apart) return load + load4(apart + i);
  return load;
}

// What a kick by h (s) adds to the velocities and spins of particles [i, i + 4): h F/m (m/s)
// and h τ/I (rad/s), 1/I = 2.5 (1/m) / R² as ParticleStore::inv_inertia computes it
// (integrate::kick_velocity_change, kick_spin_change, lane by lane).
struct KickChange {
  Packed velocity, spin;  // m/s, rad/s
};
template <bool kApart>
[[gnu::always_inline]] inline KickChange kick_change4(const ParticleStore& p, std::size_t i, double h,
                                                      const ParticleStore::ApartLoads& apart) {
  const Lanes inv_mass = load_lanes(p.inv_mass.data() + i), radius = load_lanes(p.radius.data() + i);
  const Lanes linear = h * inv_mass, angular = h * (2.5 * inv_mass / (radius * radius));
  return {kick_load4<kApart>(p.force.data(), apart.force, i) * spread(linear),
          kick_load4<kApart>(p.torque.data(), apart.torque, i) * spread(angular)};
}

// A box's corner as Packed, for the component-wise comparison of four positions.
inline Packed packed_corner(const Vec3& c) {
  return {Lanes{c.x, c.y, c.z, c.x}, Lanes{c.y, c.z, c.x, c.y}, Lanes{c.z, c.x, c.y, c.z}};
}

}  // namespace
}  // namespace quarry::sim
