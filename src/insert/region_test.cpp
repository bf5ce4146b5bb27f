// Tests for Region: membership, uniform sampling with a boundary margin (moments of the sampled
// coordinates against those of the uniform distribution), volume, tight bounds, input errors.
#include "insert/region.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace quarry {

namespace {
RegionSpec box_spec(const Vec3& lo, const Vec3& hi) {
  RegionSpec spec;
  spec.kind = RegionKind::box;
  spec.min = lo;
  spec.max = hi;
  return spec;
}
RegionSpec cylinder_spec(const Vec3& base, const Vec3& axis, double radius, double length) {
  RegionSpec spec;
  spec.kind = RegionKind::cylinder;
  spec.base = base;
  spec.axis = axis;
  spec.radius = radius;
  spec.length = length;
  return spec;
}
constexpr int kSamples = 100000;
}  // namespace

TEST(Region, BoxSamplesUniformlyAtLeastMarginInside) {
  const Region region(box_spec({-1.0, 0.0, 2.0}, {1.0, 0.5, 3.0}));
  EXPECT_DOUBLE_EQ(region.volume(), 1.0);
  EXPECT_DOUBLE_EQ(region.inscribed_radius(), 0.25);
  EXPECT_TRUE(region.contains({0.0, 0.25, 2.5}));
  EXPECT_FALSE(region.contains({0.0, 0.6, 2.5}));
  Random random(1);
  const double margin = 0.1;  // m
  Vec3 sum;
  for (int i = 0; i < kSamples; ++i) {
    const Vec3 p = region.sample_point(random, margin);
    ASSERT_GE(p.x, -0.9);
    ASSERT_LE(p.x, 0.9);
    ASSERT_GE(p.y, 0.1);
    ASSERT_LE(p.y, 0.4);
    ASSERT_GE(p.z, 2.1);
    ASSERT_LE(p.z, 2.9);
    sum += p;
  }
  // Each coordinate is U(lo + margin, hi − margin): mean at the centre, σ = width/√12.
  const Vec3 mean = sum / kSamples;
  EXPECT_NEAR(mean.x, 0.0, 4.0 * 1.8 / std::sqrt(12.0 * kSamples));
  EXPECT_NEAR(mean.y, 0.25, 4.0 * 0.3 / std::sqrt(12.0 * kSamples));
  EXPECT_NEAR(mean.z, 2.5, 4.0 * 0.8 / std::sqrt(12.0 * kSamples));
}

TEST(Region, TiltedCylinderSamplesUniformlyInsideItsMargin) {
  const Vec3 base{0.5, -0.2, 1.0};
  const Vec3 axis = normalized(Vec3{1.0, 1.0, 1.0});
  const double radius = 0.3, length = 1.2, margin = 0.05;  // m
  const Region region(cylinder_spec(base, {2.0, 2.0, 2.0}, radius, length));
  EXPECT_NEAR(region.volume(), std::numbers::pi * radius * radius * length, 1e-15);
  EXPECT_DOUBLE_EQ(region.inscribed_radius(), 0.3);
  Random random(2);
  const double usable = radius - margin;
  double sum_along = 0.0, sum_radial_sq = 0.0;
  for (int i = 0; i < kSamples; ++i) {
    const Vec3 p = region.sample_point(random, margin);
    ASSERT_TRUE(region.contains(p));
    const double along = dot(p - base, axis);
    const double radial_sq = norm2(p - base - along * axis);
    ASSERT_GE(along, margin - 1e-12);
    ASSERT_LE(along, length - margin + 1e-12);
    ASSERT_LE(radial_sq, usable * usable * (1.0 + 1e-12));
    sum_along += along;
    sum_radial_sq += radial_sq;
  }
  // Uniform in a disc of radius R': r² is U(0, R'²) (area ∝ r²), mean R'²/2, σ = R'²/√12;
  // along the axis U(margin, L − margin).
  EXPECT_NEAR(sum_along / kSamples, 0.5 * length,
              4.0 * (length - 2 * margin) / std::sqrt(12.0 * kSamples));
  EXPECT_NEAR(sum_radial_sq / kSamples, 0.5 * usable * usable,
              4.0 * usable * usable / std::sqrt(12.0 * kSamples));
}

TEST(Region, CylinderBoundsAreTightAndContainTheVolume) {
  const Vec3 base{0.1, 0.2, 0.3};
  const Vec3 axis = normalized(Vec3{0.3, -1.0, 0.5});
  const double radius = 0.4, length = 2.0;
  const Region region(cylinder_spec(base, axis, radius, length));
  const Aabb bounds = region.bounds();
  // Rim circles of both end discs, densely sampled: inside the bounds, and reaching them.
  const Vec3 helper = std::abs(axis.x) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
  const Vec3 e1 = normalized(cross(axis, helper));
  const Vec3 e2 = cross(axis, e1);
  Aabb rim;
  for (int k = 0; k < 20000; ++k) {
    const double angle = 2.0 * std::numbers::pi * k / 20000.0;
    for (double along : {0.0, length}) {
      const Vec3 p = base + along * axis + radius * (std::cos(angle) * e1 + std::sin(angle) * e2);
      for (int axis_index = 0; axis_index < 3; ++axis_index) {
        ASSERT_GE(p[axis_index], bounds.lo[axis_index] - 1e-12);
        ASSERT_LE(p[axis_index], bounds.hi[axis_index] + 1e-12);
      }
      rim.expand(p);
    }
  }
  for (int axis_index = 0; axis_index < 3; ++axis_index) {
    EXPECT_NEAR(rim.lo[axis_index], bounds.lo[axis_index], 1e-6);
    EXPECT_NEAR(rim.hi[axis_index], bounds.hi[axis_index], 1e-6);
  }
  // Monte Carlo volume: the fraction of uniform points of the bounds inside the cylinder is
  // V / V_box within 4 binomial standard errors.
  Random random(3);
  const Vec3 size = bounds.hi - bounds.lo;
  const double box_volume = size.x * size.y * size.z;
  int inside = 0;
  for (int i = 0; i < kSamples; ++i) {
    const Vec3 p{bounds.lo.x + size.x * random.uniform(), bounds.lo.y + size.y * random.uniform(),
                 bounds.lo.z + size.z * random.uniform()};
    inside += region.contains(p);
  }
  const double expected = region.volume() / box_volume;
  EXPECT_NEAR(static_cast<double>(inside) / kSamples, expected,
              4.0 * std::sqrt(expected * (1 - expected) / kSamples));
}

TEST(Region, InvalidShapesAreUserErrors) {
  EXPECT_THROW(Region(box_spec({0, 0, 0}, {1, -1, 1})), UserError);
  EXPECT_THROW(Region(cylinder_spec({0, 0, 0}, {0, 0, 1}, 0.0, 1.0)), UserError);
  EXPECT_THROW(Region(cylinder_spec({0, 0, 0}, {0, 0, 0}, 1.0, 1.0)), UserError);
}

}  // namespace quarry
