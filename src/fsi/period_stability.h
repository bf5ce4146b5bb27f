// Linear stability of the coupler's exchange (structure_coupler.h) for its smallest model: one
// particle (mass m_p) on one free node (mass m_n) through a linear contact spring k and the
// DEM's dashpot c = 2ζ√(k m_p) (the DEM sees the surface as a wall: its dashpot uses m_p
// alone). Over one period P the node moves under the constant force of the previous period's
// impulse, the particle against the surface x_n + v_n (t − t_sync) of the last sync, and the
// particle's impulse becomes the node's load of the next period. In the particle–node relative
// coordinates (r, ṙ) and the impulse in transit J this is a linear map over one period (the
// rigid motion drops out); it is stable when the roots of its characteristic cubic lie in the
// unit circle (Jury's test). docs/fem.md "Stability of PERIOD" has the derivation and a table.
#pragma once

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

}  // namespace quarry::fsi
