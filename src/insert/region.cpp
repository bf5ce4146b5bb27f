// Region: membership, uniform sampling with a boundary margin, volume and bounds of the
// insertion box or cylinder.
#include "insert/region.h"

#include <fmt/format.h>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <numbers>

namespace quarry {

Region::Region(const RegionSpec& spec) : spec_(spec) {
  Diagnostics problems;
  if (spec.kind.value == RegionKind::box) {
    const Vec3& lo = spec.min.value;
    const Vec3& hi = spec.max.value;
    for (int axis = 0; axis < 3; ++axis)
      if (!(hi[axis] > lo[axis]))
        problems.error(spec.max.where,
                       fmt::format("region box: max {} must exceed min {} on the {} axis", hi[axis],
                                   lo[axis], "xyz"[axis]));
  } else if (spec.kind.value == RegionKind::cylinder) {
    if (!(spec.radius.value > 0.0))
      problems.error(
          spec.radius.where,
          fmt::format("region cylinder: radius must be > 0 (m), got {}", spec.radius.value));
    if (!(spec.length.value > 0.0))
      problems.error(
          spec.length.where,
          fmt::format("region cylinder: length must be > 0 (m), got {}", spec.length.value));
    if (!(norm(spec.axis.value) > 0.0))
      problems.error(spec.axis.where, "region cylinder: axis direction must not be zero");
  }
  if (problems.has_errors()) throw UserError(std::move(problems));
  if (spec.kind.value == RegionKind::cylinder) {
    axis_unit_ = normalized(spec.axis.value);
    // Orthonormal basis around a unit vector without branches on near-parallel cases
    // (Duff et al., "Building an Orthonormal Basis, Revisited", JCGT 6(1), 2017).
    const Vec3& n = axis_unit_;
    const double sign = std::copysign(1.0, n.z);
    const double a = -1.0 / (sign + n.z);
    const double b = n.x * n.y * a;
    cross_first_ = {1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x};
    cross_second_ = {b, sign + n.y * n.y * a, -n.y};
  }
}

bool Region::contains(const Vec3& p) const {
  if (spec_.kind.value == RegionKind::box)
    return Aabb{spec_.min.value, spec_.max.value}.contains(p);
  if (spec_.kind.value == RegionKind::point) return p == spec_.position.value;
  const Vec3 offset = p - spec_.base.value;
  const double along = dot(offset, axis_unit_);
  if (along < 0.0 || along > spec_.length.value) return false;
  const Vec3 radial = offset - along * axis_unit_;
  return norm2(radial) <= spec_.radius.value * spec_.radius.value;
}

Vec3 Region::sample_point(Random& random, double margin) const {
  assert(margin >= 0.0 && margin <= inscribed_radius());
  if (spec_.kind.value == RegionKind::point) return spec_.position.value;  // no draw: one place
  if (spec_.kind.value == RegionKind::box) {
    const Vec3& lo = spec_.min.value;
    const Vec3& hi = spec_.max.value;
    Vec3 p;
    for (int axis = 0; axis < 3; ++axis)
      p[axis] = lo[axis] + margin + (hi[axis] - lo[axis] - 2.0 * margin) * random.uniform();
    return p;
  }
  const double along = margin + (spec_.length.value - 2.0 * margin) * random.uniform();
  // Uniform in the unit disc by rejection from its square (acceptance π/4).
  double u = 0.0, v = 0.0;
  do {
    u = 2.0 * random.uniform() - 1.0;
    v = 2.0 * random.uniform() - 1.0;
  } while (u * u + v * v > 1.0);
  const double usable_radius = spec_.radius.value - margin;  // m
  return spec_.base.value + along * axis_unit_ + (usable_radius * u) * cross_first_ +
         (usable_radius * v) * cross_second_;
}

double Region::volume() const {
  if (spec_.kind.value == RegionKind::box) {
    const Vec3 size = spec_.max.value - spec_.min.value;
    return size.x * size.y * size.z;
  }
  if (spec_.kind.value == RegionKind::point) return 0.0;
  return std::numbers::pi * spec_.radius.value * spec_.radius.value * spec_.length.value;
}

Aabb Region::bounds() const {
  if (spec_.kind.value == RegionKind::box) return Aabb{spec_.min.value, spec_.max.value};
  if (spec_.kind.value == RegionKind::point) return Aabb{spec_.position.value, spec_.position.value};
  // A disc of radius R normal to unit a reaches R·√(1 − a_k²) along coordinate axis k.
  Aabb box;
  const Vec3 top = spec_.base.value + spec_.length.value * axis_unit_;
  Vec3 reach;
  for (int axis = 0; axis < 3; ++axis)
    reach[axis] =
        spec_.radius.value * std::sqrt(std::max(0.0, 1.0 - axis_unit_[axis] * axis_unit_[axis]));
  for (const Vec3& end : {spec_.base.value, top}) {
    box.expand(end - reach);
    box.expand(end + reach);
  }
  return box;
}

double Region::inscribed_radius() const {
  if (spec_.kind.value == RegionKind::box) {
    const Vec3 size = spec_.max.value - spec_.min.value;
    return 0.5 * std::min({size.x, size.y, size.z});
  }
  // A point takes a particle of any size: its centre goes there.
  if (spec_.kind.value == RegionKind::point) return std::numeric_limits<double>::infinity();
  return std::min(spec_.radius.value, 0.5 * spec_.length.value);
}

}  // namespace quarry
