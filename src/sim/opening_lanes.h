// The opening pass (sim/guards.cpp, open_range) four particles at a time
// (sim/particle_lanes.h): the kick, the drift and the checks. Every value is the scalar
// pass's, from the same operations in the same order lane by lane
// (integrate::kick_drift_particle, Aabb::contains, norm2): the state and the tally have the
// same bits whichever particles fall into blocks of four, and any thread split gives the same
// results. Included only by guards.cpp; internal linkage.
#pragma once

#include <cstdint>

#include "sim/particle_lanes.h"
#include "sim/world.h"

namespace quarry::sim {
namespace {

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
  const KickChange kick = kick_change4<kApart>(p, i, h, apart);
  const Packed v = load4(p.velocity.data() + i) + kick.velocity;      // m/s
  const Packed w = load4(p.angular_velocity.data() + i) + kick.spin;  // rad/s
  const Packed x = load4(p.position.data() + i) + v * dt;                        // m
  store4(p.velocity.data() + i, v);
  store4(p.angular_velocity.data() + i, w);
  store4(p.position.data() + i, x);
  // x·0 is 0 for a finite x and NaN for ±inf or NaN.
  const Packed zero = x * 0.0 + v * 0.0 + w * 0.0;
  lanes.non_finite |= (zero.a + zero.b + zero.c) != Lanes{};
  lanes.inside &= (x.a >= lo.a) & (x.a <= hi.a) & (x.b >= lo.b) & (x.b <= hi.b) & (x.c >= lo.c) &
                  (x.c <= hi.c);
  const Lanes radius = load_lanes(p.radius.data() + i);  // m
  lanes.fast |= sum_components(v * v) * (dt * dt) > 0.25 * radius * radius;
  if constexpr (kCompare) {
    const Packed d = x - load4(reference + i);
    const Lanes d2 = sum_components(d * d);  // m²; NaN compares false, as in the scalar pass
    lanes.largest = d2 > lanes.largest ? d2 : lanes.largest;
    lanes.ids_changed |= load_mask(p.id.data() + i) != load_mask(id_at_build + i);
  }
}

}  // namespace
}  // namespace quarry::sim
