// The dashpots over a time step: what a contact's damping does between two force evaluations.
//
// A force evaluated once per step stands for the step's window [t − dt/2, t + dt/2] (velocity
// Verlet's two half kicks). For the spring, a smooth function of the overlap, the value at the
// centre is the window's mean to O(dt²). The Hertz dashpot's coefficient grows as δ^{1/4} from
// the first touch, so where a contact begins or ends inside a window the centre value is not
// its mean: the rebound then depends on where the steps fall (at the default 0.2 T_R, e = 0.1
// came out 0.090–0.101 with the phase before this). Two remedies, for Hertz–Mindlin
// (contact_law.h, hertz_dashpot_window, says why not for the linear and JKR laws):
//  - the coefficient is its mean along the window's straight overlap path δ(t) = δ + u (t − t_c),
//    counting only δ > 0, and a window whose centre is just short of contact (δ ≤ 0 < δ + s) is
//    a contact too, with the dashpot alone (no spring: it has no overlap at its centre);
//  - the dashpot takes the normal velocity at the force's time implicitly, u = u_lead +
//    w (F − F_prev) with F = F_spring − c u: the lead (the previous forces' half kick,
//    sim::set_velocity_leads) already holds this contact's previous force F_prev, so the
//    contact replaces it by its new force, w = h (1/m_i + 1/m_j). In a one-dimensional model of
//    the step the explicit lead alone left e = 0.1 at 0.964 e; an extrapolated lead fixed that
//    but made a column of ten beads at e ≤ 0.1 diverge at 0.3–0.4 T_R; the implicit one did not.
// Together, measured on the engine: e_out within 0.23 % of e for e = 0.1 … 0.9 at 0.2 T_R at
// six phases, on a wall and between spheres (tests/verification/restitution_test.cpp).
#pragma once

#include <algorithm>
#include <cmath>

namespace quarry::contact {

// Below this ratio of the window's half path s to the overlap the centre value is used: the
// mean differs from it by (s/δ)²/32 < 3e-4 there, and settled contacts keep their arithmetic.
inline constexpr double kWindowThreshold = 0.1;

// x^{5/4} (x ≥ 0).
inline double power_five_quarters(double x) {
  return x * std::sqrt(std::sqrt(x));
}

// True if the window of a contact at overlap δ (m) with half path s = |u| dt/2 (m) is not
// represented by its centre: it reaches δ ≤ 0, or s is a sizeable part of δ.
inline bool window_matters(double overlap, double half_path) {
  return !(half_path <= kWindowThreshold * overlap);
}

// Mean of δ^{1/4} (m^{1/4}) over the window along δ(t), δ from max(δ − s, 0) to δ + s:
// ∫ δ^{1/4} dδ / (2s) = [(δ+s)^{5/4} − max(δ−s, 0)^{5/4}] / (2.5 s). Pre: s > 0, δ + s > 0.
inline double hertz_window_quarter_power(double overlap, double half_path) {
  const double upper = overlap + half_path;                 // m
  const double lower = std::max(overlap - half_path, 0.0);  // m
  return (power_five_quarters(upper) - power_five_quarters(lower)) / (2.5 * half_path);
}

// The normal velocity (m/s, < 0 closing) the dashpot c (N·s/m) sees at the force's time when
// this contact's force is F = spring_force − c u (spring_force: everything but the dashpot, N,
// + repulsive) and the lead velocity u_lead contains its previous force previous_force (N):
// u = u_lead + w (F − F_prev)  ⇒  u = (u_lead + w (spring_force − F_prev)) / (1 + w c).
// w = h (1/m_i + 1/m_j) (s/kg); w = 0 gives u_lead.
inline double implicit_normal_velocity(double lead_normal_velocity, double spring_force,
                                       double previous_force, double damping, double w) {
  return (lead_normal_velocity + w * (spring_force - previous_force)) / (1.0 + w * damping);
}

}  // namespace quarry::contact
