// SizeSampler: draws particle radii from a particle type's size distribution at insertion
// (src/insert, called by Factory before placement). Fixed, uniform, truncated normal,
// truncated log-normal, and discrete sizes with mass fractions ("largest deficit" rule).
#pragma once

#include <vector>

#include "core/simulation_spec.h"
#include "insert/random.h"

namespace quarry {

// Distributions and their bounds [min_radius(), max_radius()] (m):
//  fixed       radius.
//  uniform     U(min_radius, max_radius).
//  normal      N(mean_radius, std_radius²) truncated to [min_radius, max_radius] by rejection;
//              bounds not given (max_radius ≤ 0) default to mean ± 3 std.
//  log_normal  ln(R / 1 m) ~ N(log_mean, log_std²), i.e. median exp(log_mean), truncated to
//              [min_radius, max_radius]; bounds not given default to exp(log_mean ± 3 log_std).
//  discrete    radii discrete_radii[k] with MASS fractions discrete_mass_fractions[k]: each draw
//              takes the class whose inserted mass is furthest below its share of the total
//              (deficit w_k·M − M_k, ties to the lower index), so the inserted mass fractions
//              match the request to within one particle mass at every moment.
// The sampler assumes every radius it returns is inserted (the factory retries a radius it
// could not place rather than drawing a new one), so the per-class masses are inserted masses.
class SizeSampler {
 public:
  // Throws UserError (with every problem of the spec, at its deck location) for invalid input:
  // non-positive radii, min > max, negative spreads, a truncation window holding less than
  // 0.1 % of the normal probability, discrete lists of unequal length or fractions that are
  // negative or do not sum to 1 (± 1e-6).
  explicit SizeSampler(const SizeDistributionSpec& spec);

  // Next radius (m). Cost: O(1) expected (O(number of classes) for discrete).
  double sample(Random& random);
  double max_radius() const { return max_radius_; }  // m
  double min_radius() const { return min_radius_; }  // m
  // Expected particle mass (kg) of a draw for the given density (kg/m³), in closed form:
  // ρ·4/3·π·E[R³]; for discrete mass fractions w_k the number-weighted mean 1 / Σ w_k/m_k.
  double mean_particle_mass(double density) const;

  // Mutable state for checkpoints: per discrete class the sum of R³ over its draws (m³; mass
  // up to the common factor ρ·4/3·π, so independent of density); empty for the other kinds.
  std::vector<double> state() const { return drawn_radius_cubed_per_class_; }
  // Restores state(); throws std::invalid_argument if the size does not match the spec.
  void set_state(const std::vector<double>& state);

 private:
  double sample_discrete();

  SizeDistributionKind kind_;
  double min_radius_ = 0.0, max_radius_ = 0.0;  // m
  double fixed_radius_ = 0.0;                   // m
  double location_ = 0.0, spread_ = 0.0;        // normal: mean, std (m); log-normal: of ln(R/1 m)
  double lower_z_ = 0.0, upper_z_ = 0.0;        // truncation window in standard-normal units
  std::vector<double> class_radius_;            // m
  std::vector<double> class_mass_fraction_;     // 1
  std::vector<double> drawn_radius_cubed_per_class_;  // m³, Σ R³ of the draws (∝ mass)
};

}  // namespace quarry
