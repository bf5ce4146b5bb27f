// The opening pass (sim/guards.cpp, open_range) four particles at a time. Each array of Vec3 is
// read as it lies in memory, four particles in three vectors (x y z x | y z x y | z x y z), with
// GCC's vector extension: AVX2 in the release build, SSE2 pairs in a baseline one. The scalar
// pass costs about 110 instructions per particle and is bound by them, not by memory (the same
// ns per particle at 1,000 particles as at 120,000; docs/performance.md).
//
// Every value is the scalar pass's, from the same operations in the same order lane by lane
// (integrate::kick_drift_particle, Aabb::contains, norm2). So the state and the tally have the same
// bits whichever particles fall into blocks of four, and any thread split gives the same
// results. Included only by guards.cpp; internal linkage.
#pragma once

#include <cstdint>

#include "core/particle_store.h"
#include "core/vec3.h"
#include "sim/world.h"

// The vector types only cross inlined functions of this header, so the note that their ABI
// differs without AVX does not concern any caller (GCC gives it at the end of the including
// file, so it stays off there).
#pragma GCC diagnostic ignored "-Wpsabi"

namespace quarry::sim {
namespace {

static_assert(sizeof(Vec3) == 3 * sizeof(double), "four Vec3s are twelve packed doubles");

typedef double Lanes __attribute__((vector_size(32)));       // one value of four particles
typedef std::int64_t Mask __attribute__((vector_size(32)));  // a comparison's lanes: 0 or -1

// Four consecutive Vec3s as they lie in memory.
struct Packed {
  Lanes a, b, c;  // x0 y0 z0 x1 | y1 z1 x2 y2 | z2 x3 y3 z3
};
static_assert(sizeof(Packed) == 4 * sizeof(Vec3));

// The same four doubles read or written where they lie (8-byte aligned, any type): one vector
// move each. (A memcpy into a local went through the stack in pieces that the vector load then
// could not take from the store buffer: the pass ran slower than the scalar one.)
typedef double UnalignedLanes __attribute__((vector_size(32), aligned(8), may_alias));
typedef std::int64_t UnalignedMask __attribute__((vector_size(32), aligned(8), may_alias));

[[gnu::always_inline]] inline Lanes load_lanes(const double* s) {
  return *reinterpret_cast<const UnalignedLanes*>(s);
}
[[gnu::always_inline]] inline Mask load_mask(const std::uint64_t* s) {
  return *reinterpret_cast<const UnalignedMask*>(s);
}
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

// What the blocks of four found, lane by lane; `add_to` merges it (flags and a maximum: exact).
struct LaneTally {
  Mask non_finite{}, inside{-1, -1, -1, -1}, fast{}, ids_changed{};
  Lanes largest{};  // m²
  void add_to(OpeningTally& t, bool domain) const {
    const auto any = [](Mask m) { return (m[0] | m[1] | m[2] | m[3]) != 0; };
    t.non_finite |= any(non_finite);
    t.any_outside |= domain && any(~inside);
    t.fast |= any(fast);
    t.ids_changed |= any(ids_changed);
    for (int l = 0; l < 4; ++l)
      t.largest_displacement_squared =
          largest[l] > t.largest_displacement_squared ? largest[l] : t.largest_displacement_squared;
  }
};

// The opening pass over particles [i, i + 4): kick by h, drift by dt (s), checks into `lanes`.
// `lo`/`hi`: the domain's corners laid out as Packed (unbounded when there is none).
template <bool kApart, bool kCompare>
[[gnu::always_inline]] inline void open_four(ParticleStore& p, std::size_t i, double h, double dt,
                                             const ParticleStore::ApartLoads& apart,
                                             const Packed& lo, const Packed& hi,
                                             const Vec3* reference, const ParticleId* id_at_build,
                                             LaneTally& lanes) {
  const Lanes inv_mass = load_lanes(p.inv_mass.data() + i), radius = load_lanes(p.radius.data() + i);
  // h·(1/m) and h·(1/I), 1/I = 2.5 (1/m) / R² (ParticleStore::inv_inertia).
  const Lanes a = h * inv_mass, b = h * (2.5 * inv_mass / (radius * radius));
  Packed force = load4(p.force.data() + i), torque = load4(p.torque.data() + i);  // N, N·m
  if constexpr (kApart) {
    if (apart.force) force = force + load4(apart.force + i);
    if (apart.torque) torque = torque + load4(apart.torque + i);
  }
  const Packed v = load4(p.velocity.data() + i) + force * spread(a);             // m/s
  const Packed w = load4(p.angular_velocity.data() + i) + torque * spread(b);    // rad/s
  const Packed x = load4(p.position.data() + i) + v * dt;                        // m
  store4(p.velocity.data() + i, v);
  store4(p.angular_velocity.data() + i, w);
  store4(p.position.data() + i, x);
  // x·0 is 0 for a finite x and NaN for ±inf or NaN.
  const Packed zero = x * 0.0 + v * 0.0 + w * 0.0;
  lanes.non_finite |= (zero.a + zero.b + zero.c) != Lanes{};
  lanes.inside &= (x.a >= lo.a) & (x.a <= hi.a) & (x.b >= lo.b) & (x.b <= hi.b) & (x.c >= lo.c) &
                  (x.c <= hi.c);
  lanes.fast |= sum_components(v * v) * (dt * dt) > 0.25 * radius * radius;
  if constexpr (kCompare) {
    const Packed d = x - load4(reference + i);
    const Lanes d2 = sum_components(d * d);  // m²; NaN compares false, as in the scalar pass
    lanes.largest = d2 > lanes.largest ? d2 : lanes.largest;
    lanes.ids_changed |= load_mask(p.id.data() + i) != load_mask(id_at_build + i);
  }
}

// A box's corner as Packed, for the component-wise comparison of four positions.
inline Packed packed_corner(const Vec3& c) {
  return {Lanes{c.x, c.y, c.z, c.x}, Lanes{c.y, c.z, c.x, c.y}, Lanes{c.z, c.x, c.y, c.z}};
}

}  // namespace
}  // namespace quarry::sim
