// Test support for the contact-law tests (not part of the library): rigid spheres moved by
// velocity Verlet in the order of the time step (half kick, drift, forces at the new
// configuration, half kick), with the contact law as the only force besides optional gravity.
#pragma once

#include <numbers>

#include "contact/contact_law.h"
#include "core/vec3.h"

namespace quarry::contact_test {

struct Sphere {
  Vec3 position;                                                   // m
  Vec3 velocity;                                                   // m/s
  Vec3 angular_velocity;                                           // rad/s
  double radius = 0.0;                                             // m
  double mass = 0.0;                                               // kg
  Vec3 force;                                                      // N
  Vec3 torque;                                                     // N·m
  double inertia() const { return 0.4 * mass * radius * radius; }  // kg·m², solid sphere 2/5 m R²
};

inline double sphere_mass(double radius, double density) {
  return density * 4.0 / 3.0 * std::numbers::pi * radius * radius * radius;  // kg
}

inline MaterialProperties glass_like_soft() {
  // A soft glass-like solid (a common DEM choice of reduced stiffness): kg/m³, Pa, 1.
  return {2500.0, 5.0e7, 0.25};
}

// Kinematics of sphere i against sphere j.
inline ContactKinematics kinematics_between(const Sphere& i, const Sphere& j) {
  const Vec3 separation = i.position - j.position;  // m
  const double distance = norm(separation);         // m
  ContactKinematics kinematics;
  kinematics.normal = separation / distance;
  kinematics.overlap = i.radius + j.radius - distance;
  kinematics.radius_i = i.radius;
  kinematics.radius_j = j.radius;
  kinematics.inv_mass_i = 1.0 / i.mass;
  kinematics.inv_mass_j = 1.0 / j.mass;
  kinematics.velocity_i = i.velocity;
  kinematics.velocity_j = j.velocity;
  kinematics.angular_velocity_i = i.angular_velocity;
  kinematics.angular_velocity_j = j.angular_velocity;
  return kinematics;
}

// Kinematics of sphere i against the floor: the plane z = 0, normal +z, at rest.
inline ContactKinematics kinematics_on_floor(const Sphere& i) {
  ContactKinematics kinematics;
  kinematics.normal = Vec3{0.0, 0.0, 1.0};
  kinematics.overlap = i.radius - i.position.z;
  kinematics.radius_i = i.radius;
  kinematics.inv_mass_i = 1.0 / i.mass;
  kinematics.velocity_i = i.velocity;
  kinematics.angular_velocity_i = i.angular_velocity;
  return kinematics;
}

// The leads of the engine's step (sim::set_velocity_leads): the half kick still to come from
// the previous forces, which carries the drift velocities to the force's time for the dashpots
// (ContactKinematics::lead_time = dt/2 with them).
inline Vec3 velocity_lead(const Sphere& sphere, const Vec3& gravity, double dt) {
  return (0.5 * dt / sphere.mass) * sphere.force + (0.5 * dt) * gravity;
}
inline Vec3 angular_velocity_lead(const Sphere& sphere, double dt) {
  return (0.5 * dt / sphere.inertia()) * sphere.torque;
}

inline void half_kick(Sphere& sphere, const Vec3& gravity, double dt) {
  sphere.velocity += (0.5 * dt / sphere.mass) * sphere.force + (0.5 * dt) * gravity;
  sphere.angular_velocity += (0.5 * dt / sphere.inertia()) * sphere.torque;
}

inline void drift(Sphere& sphere, double dt) {
  sphere.position += dt * sphere.velocity;
}

// One velocity-Verlet step of a sphere on the floor under gravity; returns the contact result.
inline ContactResult step_on_floor(const InteractionParameters& parameters, Sphere& sphere,
                                   ContactHistory& history, const Vec3& gravity, double dt) {
  half_kick(sphere, gravity, dt);
  drift(sphere, dt);
  ContactKinematics kinematics = kinematics_on_floor(sphere);
  kinematics.velocity_lead_i = velocity_lead(sphere, gravity, dt);
  kinematics.angular_velocity_lead_i = angular_velocity_lead(sphere, dt);
  kinematics.lead_time = 0.5 * dt;
  const ContactResult result = evaluate_contact(parameters, kinematics, history, dt);
  sphere.force = result.force_i;
  sphere.torque = result.torque_i;
  half_kick(sphere, gravity, dt);
  return result;
}

struct CollisionRecord {
  double contact_duration = 0.0;    // s, from first touch at t = 0 to separation (interpolated)
  double peak_overlap = 0.0;        // m
  double peak_normal_force = 0.0;   // N
  double least_normal_force = 0.0;  // N, most attractive value seen
  int steps_in_contact = 0;
};

// Collides sphere i with sphere j (j == nullptr: with the floor), without gravity. The bodies
// must start just touching (overlap 0) and approaching; the run stops at separation, leaving
// the rebound velocities in the spheres. The end of the contact is interpolated linearly
// between the last two steps (the overlap is linear in time there: dδ/dt ≈ −rebound speed).
inline CollisionRecord collide(const InteractionParameters& parameters, Sphere& i, Sphere* j,
                               double dt, int max_steps = 1000000) {
  const Vec3 no_gravity{};
  CollisionRecord record;
  ContactHistory history;
  double previous_overlap = 0.0;  // m
  // The forces of the first configuration, as the engine's sim::initialize takes them (the
  // velocities are those of that configuration: no leads). At first touch only a dashpot
  // window can act there: the half of it after the touch.
  {
    const ContactResult result = evaluate_contact(
        parameters, j ? kinematics_between(i, *j) : kinematics_on_floor(i), history, dt);
    i.force = result.force_i;
    i.torque = result.torque_i;
    if (j) {
      j->force = -result.force_i;
      j->torque = result.torque_j;
    }
  }
  for (int step = 0; step < max_steps; ++step) {
    half_kick(i, no_gravity, dt);
    if (j) half_kick(*j, no_gravity, dt);
    drift(i, dt);
    if (j) drift(*j, dt);
    ContactKinematics kinematics = j ? kinematics_between(i, *j) : kinematics_on_floor(i);
    kinematics.velocity_lead_i = velocity_lead(i, no_gravity, dt);
    kinematics.angular_velocity_lead_i = angular_velocity_lead(i, dt);
    kinematics.lead_time = 0.5 * dt;
    if (j) {
      kinematics.velocity_lead_j = velocity_lead(*j, no_gravity, dt);
      kinematics.angular_velocity_lead_j = angular_velocity_lead(*j, dt);
    }
    const ContactResult result = evaluate_contact(parameters, kinematics, history, dt);
    i.force = result.force_i;
    i.torque = result.torque_i;
    if (j) {
      j->force = -result.force_i;
      j->torque = result.torque_j;
    }
    half_kick(i, no_gravity, dt);
    if (j) half_kick(*j, no_gravity, dt);
    if (kinematics.overlap > 0.0) {
      ++record.steps_in_contact;
      previous_overlap = kinematics.overlap;
      if (kinematics.overlap > record.peak_overlap) record.peak_overlap = kinematics.overlap;
      if (result.normal_force > record.peak_normal_force) {
        record.peak_normal_force = result.normal_force;
      }
      if (result.normal_force < record.least_normal_force) {
        record.least_normal_force = result.normal_force;
      }
    } else if (record.steps_in_contact > 0) {
      record.contact_duration =
          step * dt + dt * previous_overlap / (previous_overlap - kinematics.overlap);
      break;
    }
  }
  return record;
}

}  // namespace quarry::contact_test
