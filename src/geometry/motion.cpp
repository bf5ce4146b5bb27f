// Prescribed motion of surfaces: closed-form poses from the reference mesh at each time.
#include "geometry/motion.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/diagnostics.h"

namespace quarry {

namespace {

Vec3 unit_rotation_axis(const MotionSpec& motion) {
  const Vec3 direction = motion.axis_direction.value;
  if (!(norm(direction) > 0.0))
    throw UserError(motion.axis_direction.where, "rotation axis direction is the zero vector",
                    "give the axis as a non-zero vector, e.g. [0, 0, 1]");
  return normalized(direction);
}

}  // namespace

void apply_motion(const MotionSpec& motion, double time, Surface& surface) {
  const double start = motion.start_time.value, stop = motion.stop_time.value;  // s
  if (stop < start)
    throw UserError(motion.stop_time.where,
                    "motion stop time is before its start time",
                    "the surface moves between start_time and stop_time; swap or correct them");
  const std::size_t count = surface.reference_vertices.size();
  surface.vertices.resize(count);
  surface.vertex_velocities.assign(count, Vec3{});
  const bool moving = time >= start && time <= stop;
  const double elapsed = std::clamp(time, start, stop) - start;  // s

  switch (motion.kind.value) {
    case MotionKind::none:
      surface.vertices = surface.reference_vertices;
      break;
    case MotionKind::translation: {
      const Vec3 velocity = motion.velocity.value;  // m/s
      const Vec3 displacement = velocity * elapsed;  // m
      for (std::size_t i = 0; i < count; ++i) {
        surface.vertices[i] = surface.reference_vertices[i] + displacement;
        if (moving) surface.vertex_velocities[i] = velocity;
      }
      break;
    }
    case MotionKind::rotation: {
      const Vec3 axis = unit_rotation_axis(motion);
      const Vec3 pivot = motion.axis_point.value;                   // m
      const double angular_speed = motion.angular_velocity.value;   // rad/s
      const double angle = angular_speed * elapsed;                 // rad
      const double cosine = std::cos(angle), sine = std::sin(angle);
      for (std::size_t i = 0; i < count; ++i) {
        const Vec3 arm = surface.reference_vertices[i] - pivot;
        // Rodrigues: r' = r cosθ + (k × r) sinθ + k (k·r)(1 − cosθ).
        const Vec3 rotated = arm * cosine + cross(axis, arm) * sine + axis * (dot(axis, arm) * (1.0 - cosine));
        surface.vertices[i] = pivot + rotated;
        if (moving) surface.vertex_velocities[i] = cross(axis * angular_speed, rotated);  // v = ω × r
      }
      break;
    }
    case MotionKind::vibration: {
      const Vec3 amplitude = motion.amplitude.value;                                  // m
      const double angular_frequency = 2.0 * std::numbers::pi * motion.frequency.value;  // rad/s
      // x = x0 + A sin(2π f τ), v = 2π f A cos(2π f τ).
      const Vec3 displacement = amplitude * std::sin(angular_frequency * elapsed);
      const Vec3 velocity = amplitude * (angular_frequency * std::cos(angular_frequency * elapsed));
      for (std::size_t i = 0; i < count; ++i) {
        surface.vertices[i] = surface.reference_vertices[i] + displacement;
        if (moving) surface.vertex_velocities[i] = velocity;
      }
      break;
    }
  }
  surface.update_normals_and_areas();
}

double max_vertex_speed(const MotionSpec& motion, const Surface& surface) {
  switch (motion.kind.value) {
    case MotionKind::none:
      return 0.0;
    case MotionKind::translation:
      return norm(motion.velocity.value);
    case MotionKind::rotation: {
      const Vec3 axis = unit_rotation_axis(motion);
      double largest_arm2 = 0.0;  // m²
      for (const Vec3& x : surface.reference_vertices) {
        const Vec3 arm = x - motion.axis_point.value;
        largest_arm2 = std::max(largest_arm2, norm2(arm - axis * dot(arm, axis)));
      }
      return std::abs(motion.angular_velocity.value) * std::sqrt(largest_arm2);
    }
    case MotionKind::vibration:
      return 2.0 * std::numbers::pi * std::abs(motion.frequency.value) * norm(motion.amplitude.value);
  }
  return 0.0;
}

}  // namespace quarry
