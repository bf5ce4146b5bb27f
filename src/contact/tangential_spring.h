// Incremental tangential spring-dashpot with Coulomb cap, shared by Hertz-Mindlin and the linear
// law; evaluated in the force stage, it updates the pair's stored tangential displacement.
// Sources: Cundall & Strack 1979; EDEM guide; history rescaling as LAMMPS pair gran/*/history.
#pragma once

#include <cmath>

#include "core/vec3.h"

namespace quarry::contact {

// Rotates a vector stored at the previous step (tangential displacement, rolling torque) into
// the current tangent plane (normal to unit_normal), keeping its magnitude: between steps the
// pair turned as a body, and the stored spring must turn with it instead of shrinking.
// A stored vector exactly along the normal has no defined tangential direction and becomes zero.
inline Vec3 rotate_into_tangent_plane(const Vec3& stored, const Vec3& unit_normal) {
  const Vec3 projected = stored - dot(stored, unit_normal) * unit_normal;
  const double projected_length2 = norm2(projected);  // m² (or the stored unit squared)
  if (projected_length2 <= 0.0) return Vec3{};
  return projected * std::sqrt(norm2(stored) / projected_length2);
}

// One step of the tangential spring. Updates `tangential_displacement` (m, the history δt) and
// returns the tangential force on i (N).
//   δt ← rotate(δt) + vt dt;   Ft = −kt δt − ct vd   (Cundall & Strack 1979; EDEM guide)
//   with vt the velocity that moved the bodies over the step and vd the one at the force's time
//   (contact_law.h, ContactKinematics's leads; the same vector when they coincide)
//   if |Ft| > friction_limit: Ft ← friction_limit Ft/|Ft|, and δt ← −(Ft + ct vt)/kt so that
//   spring + dashpot give exactly the capped force (LAMMPS pair gran/hooke/history rescaling;
//   LIGGGHTS' tangential_model_history instead caps the spring part alone and drops the dashpot
//   while sliding — we cap the total, as the design asks, so the force never exceeds μ|Fn|).
// Preconditions: unit_normal has length 1; both velocities ⟂ unit_normal (m/s);
// stiffness (N/m), damping_coefficient (N·s/m), friction_limit (N) >= 0; dt (s) >= 0 (0: no increment).
inline Vec3 tangential_spring_force(Vec3& tangential_displacement, const Vec3& unit_normal,
                                    const Vec3& tangential_velocity,
                                    const Vec3& damped_tangential_velocity, double stiffness,
                                    double damping_coefficient, double friction_limit, double dt) {
  tangential_displacement =
      rotate_into_tangent_plane(tangential_displacement, unit_normal) + tangential_velocity * dt;
  const Vec3 damping_force = -damping_coefficient * damped_tangential_velocity;  // N
  Vec3 force = -stiffness * tangential_displacement + damping_force;      // N
  const double force_length2 = norm2(force);                              // N²
  if (force_length2 > friction_limit * friction_limit) {
    force *= friction_limit / std::sqrt(force_length2);
    tangential_displacement = stiffness > 0.0 ? -(force - damping_force) / stiffness : Vec3{};
  }
  return force;
}

// The same with one velocity for the spring's growth and the dashpot.
inline Vec3 tangential_spring_force(Vec3& tangential_displacement, const Vec3& unit_normal,
                                    const Vec3& tangential_velocity, double stiffness,
                                    double damping_coefficient, double friction_limit, double dt) {
  return tangential_spring_force(tangential_displacement, unit_normal, tangential_velocity,
                                 tangential_velocity, stiffness, damping_coefficient,
                                 friction_limit, dt);
}

}  // namespace quarry::contact
