// Linear stability of the coupler's exchange (structure_coupler.h) for its smallest model: one
// particle (mass m_p) on one free node (mass m_n) through a linear contact spring k and the
// DEM's dashpot c = 2ζ√(k m_p) (the DEM sees the surface as a wall: its dashpot uses m_p
// alone). Over one period P the node moves under the constant force of the previous period's
// impulse, the particle against the surface x_n + v_n (t − t_sync) of the last sync, and the
// particle's impulse becomes the node's load of the next period. In the particle–node relative
// coordinates (r, ṙ) and the impulse in transit J this is a linear map over one period (the
// rigid motion drops out); it is stable when the roots of its characteristic cubic lie in the
// unit circle (Jury's test). docs/fem.md "Stability of PERIOD" has the derivation and a table.
// The same exchange with the structure's own dynamics at the node (its mode Ω and the
// mass-proportional damping α) is a 5×5 map, whose spectral radius is found numerically; it
// gives the damping a structure needs for a PERIOD.
#pragma once

#include <numbers>

namespace quarry::fsi {

// ω = √(k/m*), 1/m* = 1/m_p + 1/m_n (rad/s); `omega_period` ω·P (1); `damping_ratio` ζ of the
// particle against a fixed wall, c/(2√(k m_p)) in [0, 1); `mass_ratio` m_n/m_p (> 0).
// Whether the per-period map is stable (all its non-rigid eigenvalues strictly inside |λ| = 1).
bool exchange_is_stable(double omega_period, double damping_ratio, double mass_ratio);

// The largest ω·P below which the exchange is stable for all shorter periods: the first
// crossing of |λ| = 1 found by a scan in steps of 0.005 up to ω·P = 10 and bisection to 1e-9.
// Returns +∞ if none is found up to 10 (a node much heavier than the particle with enough
// contact damping: the structure barely moves). 0 for ζ = 0: without contact damping the lag
// (a negative damping of about k·P·m_p/(m_p + m_n)) grows the contact mode at any period.
// Throws std::invalid_argument for a value out of range.
double critical_omega_period(double damping_ratio, double mass_ratio);

// The structure at the node, besides its mass: a spring to ground K = m_n Ω² (the node's own
// mode, Ω in rad/s; 0 for a free mass) and mass-proportional damping, force −α m_n v (α in 1/s).
// Both as multiples of 1/P.
struct NodeDynamics {
  double omega_period = 0.0;    // Ω·P (1), ≥ 0
  double damping_period = 0.0;  // α·P (1), ≥ 0
};

// ln of the spectral radius of the per-period map in (x_p, v_p, x_n, v_n, J): the contact
// mode's (or the node's) growth per period, > 0 when the exchange grows; a free node's rigid
// motion counts as 0. Numerically (Gelfand's formula over 2^40 periods), to about 1e-10.
// Throws std::invalid_argument for a value out of range.
double exchange_growth_per_period(double omega_period, double damping_ratio, double mass_ratio, NodeDynamics node);

// The least α·P for which the exchange with the node's mode Ω·P does not grow (0 if it does
// not grow undamped), to 1e-3 relative; +∞ above α·P = 100 (a node damped that much no longer
// vibrates: the PERIOD, not damping, is the remedy).
double required_damping_period(double omega_period, double damping_ratio, double mass_ratio,
                               double node_omega_period);

// The most damping any mode of the structure may need: required_damping_period over the
// free node (Ω = 0) and Ω·P from 0.05 to the structure's highest mode (at most 2π; central
// differences reach Ω = 2/dt) in steps of 0.05, refined around the worst. Modes with Ω·P beyond
// 2π fall in bands that need less (the held force acts on them as a step). Returns α·P and the
// Ω·P where it is needed.
struct DampingNeed {
  double damping_period = 0.0;     // α·P (1)
  double node_omega_period = 0.0;  // Ω·P (1) of the worst mode; 0: the free node
};
DampingNeed required_damping_over_modes(double omega_period, double damping_ratio, double mass_ratio,
                                        double highest_node_omega_period = 2.0 * std::numbers::pi);

}  // namespace quarry::fsi
