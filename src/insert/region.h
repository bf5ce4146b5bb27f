// Region: the volume a factory fills (box or cylinder with its axis in any direction, or a point:
// every particle centred there, one at a time, as from a nozzle), used at insertion to draw
// candidate centres and by monitors to test membership (boxes and cylinders only).
#pragma once

#include "core/simulation_spec.h"
#include "core/vec3.h"
#include "insert/random.h"

namespace quarry {

class Region {
 public:
  // Throws UserError at the deck location for a box with max ≤ min on some axis, or a cylinder
  // with non-positive radius or length, or a zero axis direction.
  explicit Region(const RegionSpec& spec);

  // Whether p (m) lies inside or on the boundary. Cost: O(1).
  bool contains(const Vec3& p) const;
  // A point (m) uniformly distributed over the points at least `margin` (m) from the boundary.
  // Precondition: 0 ≤ margin ≤ inscribed_radius(). Uses only uniform() draws (the cylinder
  // disc by rejection, no trigonometry), so the point is bit-identical on every platform.
  Vec3 sample_point(Random& random, double margin) const;
  double volume() const;  // m³
  Aabb bounds() const;    // m, tight
  // Radius (m) of the largest sphere that fits inside: the largest admissible margin.
  double inscribed_radius() const;
  const RegionSpec& spec() const { return spec_; }

 private:
  RegionSpec spec_;
  // Cylinder frame: unit axis and two unit vectors spanning the cross-section.
  Vec3 axis_unit_, cross_first_, cross_second_;
};

}  // namespace quarry
