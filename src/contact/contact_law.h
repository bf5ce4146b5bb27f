// The contact law: one call per touching pair (particle–particle or particle–wall) in the force
// stage, composing normal (Hertz, JKR or linear), tangential (Mindlin spring + Coulomb), rolling
// and SJKR cohesion kernels. EDEM's Hertz-Mindlin no-slip (EDEM theory reference guide), DESIGN §4.
#pragma once

#include <algorithm>

#include "contact/cohesion_jkr.h"
#include "contact/cohesion_sjkr.h"
#include "contact/dashpot_window.h"
#include "contact/effective_properties.h"
#include "contact/normal_hertz.h"
#include "contact/normal_linear.h"
#include "contact/rolling_resistance.h"
#include "contact/tangential_spring.h"
#include "core/simulation_spec.h"
#include "core/vec3.h"

namespace quarry {

// Everything the law needs about one material pair, precomputed once (make_interaction).
struct InteractionParameters {
  NormalModel normal_model = NormalModel::hertz_mindlin;
  double effective_youngs_modulus = 0.0;  // E* (Pa)
  double effective_shear_modulus = 0.0;   // G* (Pa)
  double restitution = 1.0;               // e (1)
  double damping_ratio_beta = 0.0;        // β = ln e / sqrt(ln² e + π²) (1), in [−1, 0]
  double static_friction = 0.0;           // μs (1)
  double rolling_friction = 0.0;          // μr (1)
  RollingModel rolling_model = RollingModel::none;
  double cohesion_energy_density = 0.0;  // k (J/m³), SJKR
  double surface_energy = 0.0;           // γ (J/m²), JKR (cohesion_jkr.h); > 0 selects JKR
  double linear_normal_stiffness = 0.0;  // kn (N/m), linear law only
  double linear_tangential_ratio = 0.0;  // kt / kn (1), linear law only
  bool clip_attraction = false;          // clip elastic + damping normal force at 0
  // Hertz–Mindlin dashpots per unit sqrt(a m*): γn = −2 sqrt(5/6) β sqrt(kn m*) with
  // kn = 2 E* a gives γn = hertz_normal_damping · sqrt(a m*), and likewise with kt = 8 G* a
  // (hertz_mindlin_damping_coefficient); set by make_interaction. Units N·s/m per sqrt(m·kg).
  double hertz_normal_damping = 0.0;
  double hertz_tangential_damping = 0.0;
};

// Builds the pair parameters from two materials and the deck's interaction. Always checks the
// user's values (restitution in (0, 1], frictions and cohesion >= 0, positive moduli, Poisson
// ratio in (−1, 0.5], linear stiffness > 0 for the linear law) and throws UserError listing
// every problem at the spec's source locations. Cost: negligible; call once per pair at setup.
InteractionParameters make_interaction(const MaterialProperties& a, const MaterialProperties& b,
                                       const InteractionSpec& spec);

// Geometry and motion of one contact at the current configuration.
struct ContactKinematics {
  Vec3 normal;                  // unit, from j's centre (or the surface point) towards i's
  double overlap = 0.0;         // m (> 0 when touching)
  double radius_i = 0.0;        // m
  double radius_j = 0.0;        // m; 0 means a wall (flat, infinite radius and mass)
  double inv_mass_i = 0.0;      // 1/kg
  double inv_mass_j = 0.0;      // 1/kg; 0 for a wall (infinite mass)
  Vec3 velocity_i, velocity_j;  // m/s (wall: surface velocity at the contact point,
                                // conveyor velocity included)
  Vec3 angular_velocity_i, angular_velocity_j;  // rad/s (wall: zero)
  // What the velocities above lack to be those of the force's time (m/s, rad/s). With velocity
  // Verlet the positions are x(t+dt) but the velocities v(t+dt/2), which moved them: right for
  // the springs' increments (v dt is the step's displacement), half a step late for the
  // dashpots. The lead is the predicted rest of the step, h F(t)/m and h τ(t)/I with h = dt/2,
  // so the dashpots see v(t+dt) + O(dt²) and the restitution error is second order in dt
  // (without it e = 0.1 came out 0.091 at the default step). Zero for symplectic Euler and walls.
  Vec3 velocity_lead_i, velocity_lead_j;                  // m/s
  Vec3 angular_velocity_lead_i, angular_velocity_lead_j;  // rad/s
  // h (s): the time the leads span (dt/2 for velocity Verlet, 0 for symplectic Euler and for
  // readers of a frame); the dashpot's implicit velocity uses it (contact/dashpot_window.h).
  double lead_time = 0.0;
};

// Per-contact state carried from step to step (kept by the contact list, keyed by pair).
struct ContactHistory {
  Vec3 tangential_displacement;  // m, δt (in the current tangent plane)
  Vec3 rolling_torque;           // N·m, EPSD spring torque on i
  // JKR only: the pair adheres (it touched, δ > 0, and has not been pulled past δ_c < 0
  // since): the hysteresis of the JKR contact, which holds at negative overlap.
  bool jkr_attached = false;
  // N: this contact's normal force of the last step (ContactResult::normal_force), which the
  // velocity leads contain; the dashpot replaces it by the new one (dashpot_window.h).
  double normal_force = 0.0;
};

struct ContactResult {
  Vec3 force_i;               // N on i; j (or the wall) gets −force_i at the contact point
  Vec3 torque_i, torque_j;    // N·m about each centre (torque_j = 0 for a wall)
  double normal_force = 0.0;  // N, signed component of force_i along normal (+ = repulsive),
                              // cohesion included
};

// True if the dashpots of this law take the window's mean and the implicit velocity
// (dashpot_window.h): Hertz–Mindlin without JKR, whose dashpot grows continuously from zero
// at first touch. A linear or JKR contact's force jumps at first touch; across that jump the
// implicit velocity is only first order (a one-dimensional model of the step, linear law at
// t_c/200, e = 0.1: 0.9998–1.023 e over the phases against 1.0001 e with the explicit lead),
// so they keep the explicit lead of the centre.
inline bool hertz_dashpot_window(const InteractionParameters& parameters) {
  return parameters.normal_model == NormalModel::hertz_mindlin && !(parameters.surface_energy > 0.0);
}

// A pair short of contact (δ ≤ 0, no JKR adhesion): the dashpot alone if the step's window
// reaches contact (δ + s > 0, s = |u| dt/2 with u the normal velocity at the force's time),
// else nothing. Either way the springs are released. Part of evaluate_contact.
[[gnu::noinline]] inline ContactResult window_contact(const InteractionParameters& parameters,
                                                           const ContactKinematics& kinematics,
                                                           ContactHistory& history, double dt) {
  const double previous_force = history.normal_force;  // N
  history = ContactHistory{};
  if (!(dt > 0.0) || !hertz_dashpot_window(parameters)) return ContactResult{};
  const Vec3& normal = kinematics.normal;
  // ω × r is normal to n for spheres: only the centres' velocities have a normal part (m/s).
  const double lead_normal_velocity =
      dot((kinematics.velocity_i + kinematics.velocity_lead_i) -
              (kinematics.velocity_j + kinematics.velocity_lead_j),
          normal);
  const double half_path = 0.5 * dt * std::fabs(lead_normal_velocity);  // m, s
  const double overlap = kinematics.overlap;                             // m, ≤ 0
  if (!(overlap + half_path > 0.0)) return ContactResult{};
  const double inverse_sum = kinematics.inv_mass_i + kinematics.inv_mass_j;  // 1/kg
  const double effective_mass = inverse_sum > 0.0 ? 1.0 / inverse_sum : 0.0;  // kg
  const double effective_radius =
      contact::effective_radius(kinematics.radius_i, kinematics.radius_j);  // m
  const double damping = parameters.hertz_normal_damping *
                         std::sqrt(std::sqrt(effective_radius) * effective_mass) *
                         contact::hertz_window_quarter_power(overlap, half_path);  // N·s/m, mean
  const double velocity = contact::implicit_normal_velocity(
      lead_normal_velocity, 0.0, previous_force, damping, kinematics.lead_time * inverse_sum);
  double force = -damping * velocity;  // N, + repulsive
  if (parameters.clip_attraction && force < 0.0) force = 0.0;
  history.normal_force = force;
  ContactResult result;
  result.normal_force = force;
  result.force_i = force * normal;  // along the line of centres: no torque
  return result;
}

// Evaluates the contact law for one pair and updates its history. No allocation, inline.
// Conventions (DESIGN §4): R*, m* from effective_radius/effective_mass (wall: Ri, mi).
// Contact point at distance Ri − δ/2 from i's centre along −n (wall: Ri − δ, i.e. on the wall),
// and Rj − δ/2 from j's centre along +n. Relative velocity at the contact point includes ω × r.
// Normal: elastic + dashpot (no clipping unless clip_attraction, so the end of a contact may be
// attractive and the input restitution is reproduced). Tangential: tangential_spring_force
// with the Coulomb limit μs |Fn| using the elastic + dashpot normal force, before cohesion.
// Springs grow with the drift velocities, dashpots use them plus the leads (force time).
// Rolling: constant directional torque uses each body's own ω and radius and the same |Fn|;
// EPSD limits |Mr| to μr R* |Fn|. Cohesion (SJKR) pulls i towards j: −k A n.
// JKR (surface_energy > 0): the normal spring is jkr_normal_force at the contact radius a of
// the overlap, the contact forms at δ > 0 and holds down to δ_c (history.jkr_attached); the
// stiffnesses of the dashpots and the tangential spring are Hertz's at that a (2E*a, 8G*a), and
// the Coulomb and rolling limits use the Hertz load of a, 4E*a³/(3R*), plus the dashpot (the
// load the contact circle carries, as SJKR's limits use the force before cohesion).
// Dashpots (dashpot_window.h): their coefficient is the mean over the step's window along the
// straight overlap path (Hertz: of δ^{1/4}; linear: the share of the window in contact) where
// the window's half path s = |u| dt/2 is more than a tenth of δ, and they take the normal
// velocity at the force's time implicitly with this contact's new force. A pair short of
// contact whose window reaches it (δ ≤ 0 < δ + s) feels the dashpot alone.
// Precondition: dt ≥ 0 (0: the force of the stored history, no increment: how sim/frame_contacts
// reads a frame's contact forces). If overlap <= 0 the pair is not touching (unless JKR holds
// it or the window reaches contact): the result is zero and the history is cleared (the spring
// is released when contact is lost).
[[gnu::always_inline]] inline ContactResult evaluate_contact(const InteractionParameters& parameters,
                                      const ContactKinematics& kinematics, ContactHistory& history,
                                      double dt) {
  if (!(kinematics.overlap > 0.0) && !history.jkr_attached)
    return window_contact(parameters, kinematics, history, dt);
  const Vec3& normal = kinematics.normal;
  const double overlap = kinematics.overlap;  // m
  const bool against_wall = !(kinematics.radius_j > 0.0);
  const double effective_radius =
      contact::effective_radius(kinematics.radius_i, kinematics.radius_j);
  // 1/m* = 1/mi + 1/mj; a wall has 1/mj = 0 (kg).
  // m* = 1/(1/mi + 1/mj): a fixed particle (1/m = 0) gives m* = the other's mass; two fixed
  // ones (or a fixed one on a wall) have no relative motion to damp: m* = 0, not 1/0.
  const double inverse_sum = kinematics.inv_mass_i + kinematics.inv_mass_j;  // 1/kg
  const double effective_mass = inverse_sum > 0.0 ? 1.0 / inverse_sum : 0.0;

  // Distances (m) from each centre to the contact point: r_i = −lever_i n, r_j = +lever_j n.
  const double lever_i =
      against_wall ? kinematics.radius_i - overlap : kinematics.radius_i - 0.5 * overlap;
  const double lever_j = against_wall ? 0.0 : kinematics.radius_j - 0.5 * overlap;
  // Relative velocity of the material points at the contact, (v_i + ω_i × r_i) − (v_j + ω_j × r_j)
  // = (v_i − v_j) − (lever_i ω_i + lever_j ω_j) × n (m/s): one cross product instead of two.
  const Vec3 lever_spin =
      lever_i * kinematics.angular_velocity_i + lever_j * kinematics.angular_velocity_j;  // m/s
  const Vec3 relative_velocity =
      (kinematics.velocity_i - kinematics.velocity_j) - cross(lever_spin, normal);  // m/s
  const double drift_normal_velocity = dot(relative_velocity, normal);  // m/s
  const Vec3 tangential_velocity = relative_velocity - drift_normal_velocity * normal;  // m/s
  // The same at the force's time (the dashpots'): the leads' share added.
  const Vec3 lead_spin = lever_i * kinematics.angular_velocity_lead_i +
                         lever_j * kinematics.angular_velocity_lead_j;  // m/s
  const Vec3 damped_velocity =
      relative_velocity + ((kinematics.velocity_lead_i - kinematics.velocity_lead_j) -
                           cross(lead_spin, normal));                  // m/s
  const double normal_velocity = dot(damped_velocity, normal);        // m/s, < 0 closing
  const Vec3 damped_tangential_velocity = damped_velocity - normal_velocity * normal;  // m/s
  const double half_path = 0.5 * dt * std::fabs(normal_velocity);    // m, the window's s

  contact::NormalSpring normal_spring;
  double normal_damping = 0.0;        // N·s/m
  double tangential_stiffness = 0.0;  // N/m
  double tangential_damping = 0.0;    // N·s/m
  double friction_load = 0.0;         // N, the normal load of the Coulomb and rolling limits
  if (parameters.surface_energy > 0.0) {
    const contact::JkrScales scales = contact::jkr_scales(
        parameters.surface_energy, parameters.effective_youngs_modulus, effective_radius);
    if (!(overlap >= scales.break_overlap)) {  // pulled apart: the contact breaks
      history = ContactHistory{};
      return ContactResult{};
    }
    history.jkr_attached = true;
    const double contact_radius = contact::jkr_contact_radius(scales, overlap);  // m, a
    normal_spring.elastic_force =
        contact::jkr_normal_force(parameters.surface_energy, parameters.effective_youngs_modulus,
                                  effective_radius, contact_radius);
    normal_spring.stiffness = 2.0 * parameters.effective_youngs_modulus * contact_radius;
    tangential_stiffness = 8.0 * parameters.effective_shear_modulus * contact_radius;
    const double root = std::sqrt(contact_radius * effective_mass);  // sqrt(m·kg)
    normal_damping = parameters.hertz_normal_damping * root;
    tangential_damping = parameters.hertz_tangential_damping * root;
    friction_load = 4.0 / 3.0 * parameters.effective_youngs_modulus * contact_radius *
                    contact_radius * contact_radius / effective_radius;  // the dashpot below
  } else if (parameters.normal_model == NormalModel::hertz_mindlin) {
    normal_spring = contact::hertz_normal_spring(parameters.effective_youngs_modulus,
                                                 effective_radius, overlap);
    tangential_stiffness = contact::mindlin_tangential_stiffness(parameters.effective_shear_modulus,
                                                                 effective_radius, overlap);
    // hertz_mindlin_damping_coefficient with its constant part precomputed: sqrt(k m*) with
    // k ∝ a = sqrt(R* δ) (the helpers' square root; the compiler computes it once).
    // Where the window matters, the mean of δ^{1/4} over it instead (dashpot_window.h).
    const double root =
        contact::window_matters(overlap, half_path) && dt > 0.0
            ? std::sqrt(std::sqrt(effective_radius) * effective_mass) *
                  contact::hertz_window_quarter_power(overlap, half_path)
            : std::sqrt(std::sqrt(effective_radius * overlap) * effective_mass);  // sqrt(m·kg)
    normal_damping = parameters.hertz_normal_damping * root;
    tangential_damping = parameters.hertz_tangential_damping * root;
  } else {
    normal_spring = contact::linear_normal_spring(parameters.linear_normal_stiffness, overlap);
    normal_damping = contact::linear_damping_coefficient(parameters.damping_ratio_beta,
                                                         normal_spring.stiffness, effective_mass);
    tangential_stiffness = parameters.linear_tangential_ratio * normal_spring.stiffness;
    tangential_damping = contact::linear_damping_coefficient(
        parameters.damping_ratio_beta, tangential_stiffness, effective_mass);
  }

  double cohesion_force = 0.0;  // N, attractive magnitude
  if (parameters.cohesion_energy_density > 0.0) {
    const double contact_area =
        against_wall ? contact::sphere_wall_contact_area(kinematics.radius_i, overlap)
                     : contact::sphere_sphere_contact_area(kinematics.radius_i, kinematics.radius_j,
                                                           overlap);  // m²
    cohesion_force = contact::sjkr_cohesion_force(parameters.cohesion_energy_density, contact_area);
  }
  // The dashpot's velocity at the force's time, with this contact's new force (implicit).
  const double damped_normal_velocity = contact::implicit_normal_velocity(
      normal_velocity, normal_spring.elastic_force - cohesion_force, history.normal_force,
      normal_damping,
      hertz_dashpot_window(parameters) ? kinematics.lead_time * inverse_sum : 0.0);  // m/s
  double contact_normal_force =
      normal_spring.elastic_force - normal_damping * damped_normal_velocity;  // N
  if (parameters.clip_attraction && contact_normal_force < 0.0) contact_normal_force = 0.0;
  if (!(parameters.surface_energy > 0.0))
    friction_load = contact_normal_force;
  else
    friction_load -= normal_damping * damped_normal_velocity;
  const double normal_force_magnitude = std::fabs(friction_load);  // N, |Fn|

  const Vec3 tangential_force = contact::tangential_spring_force(
      history.tangential_displacement, normal, tangential_velocity, damped_tangential_velocity,
      tangential_stiffness, tangential_damping, parameters.static_friction * normal_force_magnitude,
      dt);

  ContactResult result;
  result.normal_force = contact_normal_force - cohesion_force;
  history.normal_force = result.normal_force;
  result.force_i = result.normal_force * normal + tangential_force;
  // Both bodies feel the tangential force at the same point: τi = (−lever_i n) × Ft,
  // τj = (lever_j n) × (−Ft).
  const Vec3 normal_cross_tangential_force = cross(normal, tangential_force);  // N
  result.torque_i = -lever_i * normal_cross_tangential_force;
  result.torque_j = -lever_j * normal_cross_tangential_force;

  switch (parameters.rolling_model) {
    case RollingModel::none:
      break;
    case RollingModel::constant_torque:
      result.torque_i += contact::constant_directional_rolling_torque(
          parameters.rolling_friction, normal_force_magnitude, kinematics.radius_i,
          kinematics.angular_velocity_i + kinematics.angular_velocity_lead_i);
      if (!against_wall) {
        result.torque_j += contact::constant_directional_rolling_torque(
            parameters.rolling_friction, normal_force_magnitude, kinematics.radius_j,
            kinematics.angular_velocity_j + kinematics.angular_velocity_lead_j);
      }
      break;
    case RollingModel::epsd: {
      const double rolling_stiffness = contact::epsd_rolling_stiffness(
          normal_spring.stiffness, parameters.rolling_friction, effective_radius);  // N·m/rad
      const Vec3 rolling_torque = contact::epsd_rolling_torque(
          history.rolling_torque, normal,
          kinematics.angular_velocity_i - kinematics.angular_velocity_j, rolling_stiffness,
          parameters.rolling_friction * effective_radius * normal_force_magnitude, dt);
      result.torque_i += rolling_torque;
      if (!against_wall) result.torque_j -= rolling_torque;
      break;
    }
  }
  return result;
}

// The run's overlap guard for a particle pair (simulation.max_overlap_fraction): true if the
// overlap δ (m) passes limit × the smaller radius (m). Both force paths flag it with this
// test, in the arithmetic of the report that follows (sim::check_overlaps).
inline bool overlap_past_limit(double overlap, double radius_i, double radius_j, double limit) {
  return overlap > limit * std::min(radius_i, radius_j);
}

}  // namespace quarry
