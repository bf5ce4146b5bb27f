// Rolling resistance torques, added in the force stage after the tangential force:
// EDEM's constant directional torque ("type A"; Ai, Chen, Rotter & Ooi 2011, model A) and the
// elastic-plastic spring-dashpot (EPSD, Ai et al. 2011 model C, spring part only).
#pragma once

#include <cmath>

#include "contact/tangential_spring.h"
#include "core/vec3.h"

namespace quarry::contact {

// τ = −μr |Fn| R ω̂ (EDEM guide, rolling friction "type A"; Ai et al. 2011 eq. for model A):
// opposes the body's own angular velocity; zero when it does not rotate. N·m.
// Known limitation of the model (Ai et al. 2011): it does not vanish at rest and makes ω
// oscillate about zero instead of settling; EPSD is the remedy.
inline Vec3 constant_directional_rolling_torque(double rolling_friction,
                                                double normal_force_magnitude, double radius,
                                                const Vec3& angular_velocity) {
  const double angular_speed = norm(angular_velocity);  // rad/s
  if (angular_speed <= 0.0) return Vec3{};
  return angular_velocity * (-rolling_friction * normal_force_magnitude * radius / angular_speed);
}

// kr = 2.25 kn μr² R*²  (Ai et al. 2011, model C, after Iwashita & Oda 1998), N·m/rad, with
// kn the current normal tangent stiffness (Sn for Hertz, kn for the linear law).
inline double epsd_rolling_stiffness(double normal_stiffness, double rolling_friction,
                                     double effective_radius) {
  return 2.25 * normal_stiffness * rolling_friction * rolling_friction * effective_radius *
         effective_radius;
}

// One step of the EPSD rolling spring (Ai et al. 2011 model C without its viscous part):
//   Δθr = (ωi − ωj) dt projected onto the tangent plane (twist about n excluded);
//   Mr ← rotate(Mr) − kr Δθr;  |Mr| <= torque_limit = μr R* |Fn| (full mobilisation).
// Updates `rolling_torque` (the history, N·m) and returns the torque on i (j gets −Mr).
// The stored torque is turned with the pair like the tangential displacement.
inline Vec3 epsd_rolling_torque(Vec3& rolling_torque, const Vec3& unit_normal,
                                const Vec3& relative_angular_velocity, double rolling_stiffness,
                                double torque_limit, double dt) {
  const Vec3 rolling_angular_velocity =
      relative_angular_velocity - dot(relative_angular_velocity, unit_normal) * unit_normal;
  rolling_torque = rotate_into_tangent_plane(rolling_torque, unit_normal) -
                   rolling_stiffness * dt * rolling_angular_velocity;
  const double torque_length2 = norm2(rolling_torque);  // (N·m)²
  if (torque_length2 > torque_limit * torque_limit) {
    rolling_torque *= torque_limit / std::sqrt(torque_length2);
  }
  return rolling_torque;
}

}  // namespace quarry::contact
