// Linear spring-dashpot normal law (Cundall & Strack 1979), the alternative to Hertz-Mindlin,
// evaluated in the force stage. Damping from restitution as for a damped linear oscillator
// (Ting, Corkum, Kauffman & Greco 1989): the restitution is reproduced exactly.
#pragma once

#include <cmath>

#include "contact/normal_hertz.h"

namespace quarry::contact {

// Fn = kn δ, constant stiffness kn (N/m).
inline NormalSpring linear_normal_spring(double stiffness, double overlap) {
  return {stiffness * overlap, stiffness};
}

// c = −2 β sqrt(k m*) (N·s/m): −β is the fraction of critical damping 2 sqrt(k m*), and a
// linear oscillator with that fraction rebounds with e = exp(β π / sqrt(1 − β²)), which is the
// inverse of β = ln e / sqrt(ln² e + π²). Used for the tangential dashpot with k = kt as well.
inline double linear_damping_coefficient(double damping_ratio_beta, double stiffness,
                                         double effective_mass) {
  return -2.0 * damping_ratio_beta * std::sqrt(stiffness * effective_mass);
}

}  // namespace quarry::contact
