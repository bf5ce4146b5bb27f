// Tests of prescribed motion against closed forms: rigid rotation (a quarter turn maps x̂ to
// ŷ; v = ω × r), translation x0 + v t, vibration x0 + A sin 2πft with v = 2πfA cos 2πft,
// and holding still outside [start, stop].
#include "geometry/motion.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "geometry/primitives.h"

namespace quarry {
namespace {

Surface two_points_surface() {
  Surface s;
  s.reference_vertices = {{1, 0, 0}, {0, 0, 2}, {2, 1, 0}};
  s.vertices = s.reference_vertices;
  s.triangles = {{0, 1, 2}};
  s.update_normals_and_areas();
  s.reset_loads();
  return s;
}

void expect_near(const Vec3& a, const Vec3& b, double tolerance) {
  EXPECT_NEAR(a.x, b.x, tolerance);
  EXPECT_NEAR(a.y, b.y, tolerance);
  EXPECT_NEAR(a.z, b.z, tolerance);
}

MotionSpec rotation(double angular_velocity, Vec3 point, Vec3 direction) {
  MotionSpec m;
  m.kind = MotionKind::rotation;
  m.angular_velocity = angular_velocity;
  m.axis_point = point;
  m.axis_direction = direction;
  return m;
}

TEST(Motion, QuarterTurnMapsXToY) {
  Surface s = two_points_surface();
  const double omega = std::numbers::pi / 2;  // rad/s: a quarter turn in 1 s
  apply_motion(rotation(omega, {0, 0, 0}, {0, 0, 3}), 1.0, s);  // axis need not be unit
  expect_near(s.vertices[0], {0, 1, 0}, 1e-15);
  expect_near(s.vertices[1], {0, 0, 2}, 1e-15);  // on the axis
  expect_near(s.vertices[2], {-1, 2, 0}, 1e-15);
  expect_near(s.vertex_velocities[0], {-omega, 0, 0}, 1e-15);  // ω ẑ × ŷ = −ω x̂
  expect_near(s.vertex_velocities[1], {0, 0, 0}, 1e-15);
  // Normals follow: the triangle's normal turns by the same quarter turn about z.
  const Vec3 before = normalized(cross(Vec3{-1, 0, 2}, Vec3{1, 1, 0}));
  expect_near(s.triangle_normals[0], {-before.y, before.x, before.z}, 1e-15);
}

TEST(Motion, RotationAboutAnOffsetAxisMatchesFiniteDifferences) {
  Surface s = two_points_surface();
  const MotionSpec m = rotation(2.5, {1, 1, 0}, {1, -1, 2});
  const double t = 0.37, dt = 1e-6;  // s
  apply_motion(m, t + dt, s);
  const auto ahead = s.vertices;
  apply_motion(m, t - dt, s);
  const auto behind = s.vertices;
  apply_motion(m, t, s);
  for (std::size_t i = 0; i < 3; ++i) {
    // Central difference: error ~ |ω|³ r dt² / 6 ≈ 1e-11 m/s; round-off ~ 1e-16/1e-6 = 1e-10 m/s.
    expect_near(s.vertex_velocities[i], (ahead[i] - behind[i]) / (2 * dt), 1e-8);
    // Rigid: distance from the axis is preserved.
    const Vec3 axis = normalized(Vec3{1, -1, 2});
    const Vec3 r0 = s.reference_vertices[i] - Vec3{1, 1, 0}, r = s.vertices[i] - Vec3{1, 1, 0};
    EXPECT_NEAR(norm(r - axis * dot(r, axis)), norm(r0 - axis * dot(r0, axis)), 1e-14);
  }
  double largest_arm = 0.0;  // m, distance of the farthest vertex from the axis
  const Vec3 axis = normalized(Vec3{1, -1, 2});
  for (const Vec3& x : s.reference_vertices) {
    const Vec3 r = x - Vec3{1, 1, 0};
    largest_arm = std::max(largest_arm, norm(r - axis * dot(r, axis)));
  }
  EXPECT_NEAR(max_vertex_speed(m, s), 2.5 * largest_arm, 1e-14);
}

TEST(Motion, TranslationMovesInsideItsWindowAndHoldsOutside) {
  Surface s = two_points_surface();
  MotionSpec m;
  m.kind = MotionKind::translation;
  m.velocity = Vec3{0.5, 0, -1};
  m.start_time = 1.0;
  m.stop_time = 3.0;
  apply_motion(m, 0.5, s);  // before start: reference pose, at rest
  expect_near(s.vertices[0], {1, 0, 0}, 0.0);
  expect_near(s.vertex_velocities[0], {0, 0, 0}, 0.0);
  apply_motion(m, 2.0, s);  // x0 + v (t − start)
  expect_near(s.vertices[0], {1.5, 0, -1}, 1e-15);
  expect_near(s.vertex_velocities[0], {0.5, 0, -1}, 0.0);
  apply_motion(m, 10.0, s);  // after stop: held at x0 + v (stop − start), at rest
  expect_near(s.vertices[2], {3, 1, -2}, 1e-15);
  expect_near(s.vertex_velocities[2], {0, 0, 0}, 0.0);
  EXPECT_DOUBLE_EQ(max_vertex_speed(m, s), std::sqrt(1.25));
}

TEST(Motion, VibrationFollowsTheSineAndItsDerivative) {
  Surface s = two_points_surface();
  MotionSpec m;
  m.kind = MotionKind::vibration;
  m.amplitude = Vec3{0, 0, 0.002};  // m
  m.frequency = 25.0;               // Hz
  m.start_time = 0.1;
  m.stop_time = 0.5;
  const double t = 0.1 + 0.01;  // a quarter period after start: peak displacement, zero speed
  apply_motion(m, t, s);
  expect_near(s.vertices[1], {0, 0, 2.002}, 1e-15);
  expect_near(s.vertex_velocities[1], {0, 0, 0}, 1e-15);
  apply_motion(m, 0.1 + 0.02, s);  // half period: back at x0, moving down at 2πfA
  expect_near(s.vertices[1], {0, 0, 2}, 1e-15);
  expect_near(s.vertex_velocities[1], {0, 0, -2 * std::numbers::pi * 25 * 0.002}, 1e-14);
  EXPECT_NEAR(max_vertex_speed(m, s), 2 * std::numbers::pi * 25 * 0.002, 1e-15);
  apply_motion(m, 0.52, s);  // after stop: sin(2π·25·0.4) = 0 → x0, at rest
  expect_near(s.vertices[1], {0, 0, 2}, 1e-15);
  expect_near(s.vertex_velocities[1], {0, 0, 0}, 0.0);
}

TEST(Motion, NoMotionRestoresTheReferencePose) {
  Surface s = make_plane({0, 0, 0}, {0, 0, 1}, 1.0, 2);
  for (auto& v : s.vertices) v += Vec3{0, 0, 1};
  apply_motion(MotionSpec{}, 5.0, s);
  EXPECT_EQ(s.vertices, s.reference_vertices);
  EXPECT_EQ(max_vertex_speed(MotionSpec{}, s), 0.0);
}

TEST(Motion, ZeroRotationAxisIsAUserErrorAtTheDeckLocation) {
  Surface s = two_points_surface();
  MotionSpec m = rotation(1.0, {}, {0, 0, 0});
  m.axis_direction.where = SourceLocation{"deck.yaml", 12, 7};
  try {
    apply_motion(m, 1.0, s);
    FAIL() << "expected UserError";
  } catch (const UserError& error) {
    EXPECT_EQ(error.diagnostics().all().at(0).where.line, 12);
  }
}

}  // namespace
}  // namespace quarry
