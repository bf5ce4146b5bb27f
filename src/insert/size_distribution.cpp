// SizeSampler: validation, rejection sampling of truncated normal/log-normal radii, the
// largest-deficit rule for discrete mass fractions, and closed-form mean particle masses.
#include "insert/size_distribution.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "insert/portable_math.h"

namespace quarry {

namespace {

// Standard normal density φ and distribution Φ (Abramowitz & Stegun 26.2.1, 26.2.29).
double standard_normal_density(double z) {
  return std::exp(-0.5 * z * z) / std::sqrt(2.0 * std::numbers::pi);
}
double standard_normal_cdf(double z) {
  return 0.5 * std::erfc(-z / std::numbers::sqrt2);
}

// Smallest probability mass the truncation window may keep: below it rejection sampling
// would spin for thousands of draws per radius, and the user almost surely mistyped a bound.
constexpr double kMinimumAcceptance = 1e-3;
// Default truncation of normal/log-normal when no bounds are given: ± 3 standard deviations.
constexpr double kDefaultTruncationSigmas = 3.0;

const char* kind_word(SizeDistributionKind kind) {
  switch (kind) {
    case SizeDistributionKind::fixed:
      return "fixed";
    case SizeDistributionKind::uniform:
      return "uniform";
    case SizeDistributionKind::normal:
      return "normal";
    case SizeDistributionKind::log_normal:
      return "log_normal";
    case SizeDistributionKind::discrete:
      return "discrete";
  }
  return "?";
}

}  // namespace

SizeSampler::SizeSampler(const SizeDistributionSpec& spec) : kind_(spec.kind.value) {
  Diagnostics problems;
  const std::string kind = kind_word(kind_);
  const auto require_positive = [&](const Located<double>& value, const char* name) {
    if (!(value.value > 0.0))
      problems.error(value.where, fmt::format("{} size distribution: {} must be > 0 (m), got {}",
                                              kind, name, value.value));
  };
  switch (kind_) {
    case SizeDistributionKind::fixed:
      require_positive(spec.radius, "radius");
      fixed_radius_ = min_radius_ = max_radius_ = spec.radius.value;
      break;
    case SizeDistributionKind::uniform:
      require_positive(spec.min_radius, "min_radius");
      min_radius_ = spec.min_radius.value;
      max_radius_ = spec.max_radius.value;
      if (max_radius_ < min_radius_)
        problems.error(
            spec.max_radius.where,
            fmt::format("uniform size distribution: max_radius {} is below min_radius {}",
                        max_radius_, min_radius_));
      break;
    case SizeDistributionKind::normal:
    case SizeDistributionKind::log_normal: {
      const bool is_normal = kind_ == SizeDistributionKind::normal;
      const Located<double>& location = is_normal ? spec.mean_radius : spec.log_mean;
      const Located<double>& spread = is_normal ? spec.std_radius : spec.log_std;
      location_ = location.value;
      spread_ = spread.value;
      if (is_normal) require_positive(location, "mean_radius");
      if (!(spread_ > 0.0)) {
        problems.error(spread.where,
                       fmt::format("{} size distribution: {} must be > 0, got {}", kind,
                                   is_normal ? "std_radius" : "log_std", spread_),
                       "for a single size use kind \"fixed\"");
        break;
      }
      const double default_low = location_ - kDefaultTruncationSigmas * spread_;
      const double default_high = location_ + kDefaultTruncationSigmas * spread_;
      min_radius_ = spec.min_radius.value > 0.0 ? spec.min_radius.value
                                                : (is_normal ? default_low : std::exp(default_low));
      max_radius_ = spec.max_radius.value > 0.0
                        ? spec.max_radius.value
                        : (is_normal ? default_high : std::exp(default_high));
      if (!(min_radius_ > 0.0)) {
        problems.error(spec.min_radius.where,
                       fmt::format("normal size distribution reaches radius {} ≤ 0 at mean − 3 std",
                                   min_radius_),
                       "give min_radius > 0 to truncate it");
        break;
      }
      if (!(max_radius_ > min_radius_)) {
        problems.error(spec.max_radius.where,
                       fmt::format("{} size distribution: max_radius {} must exceed min_radius {}",
                                   kind, max_radius_, min_radius_));
        break;
      }
      lower_z_ = ((is_normal ? min_radius_ : std::log(min_radius_)) - location_) / spread_;
      upper_z_ = ((is_normal ? max_radius_ : std::log(max_radius_)) - location_) / spread_;
      const double kept = standard_normal_cdf(upper_z_) - standard_normal_cdf(lower_z_);
      if (kept < kMinimumAcceptance)
        problems.error(
            spec.min_radius.where.line > 0 ? spec.min_radius.where : spec.max_radius.where,
            fmt::format(
                "{} size distribution: [min_radius, max_radius] = [{}, {}] keeps only {:.2g} "
                "of the probability",
                kind, min_radius_, max_radius_, kept),
            "check the bounds against the mean and spread");
      break;
    }
    case SizeDistributionKind::discrete: {
      const auto& radii = spec.discrete_radii;
      const auto& fractions = spec.discrete_mass_fractions;
      if (radii.empty() || radii.size() != fractions.size()) {
        problems.error(spec.kind.where,
                       fmt::format("discrete size distribution needs one mass fraction per radius "
                                   "(got {} radii, {} fractions)",
                                   radii.size(), fractions.size()));
        break;
      }
      double fraction_sum = 0.0;
      for (std::size_t k = 0; k < radii.size(); ++k) {
        require_positive(radii[k], "each radius");
        if (!(fractions[k].value >= 0.0))
          problems.error(fractions[k].where,
                         fmt::format("discrete size distribution: mass fraction {} is "
                                     "negative",
                                     fractions[k].value));
        fraction_sum += fractions[k].value;
      }
      if (std::abs(fraction_sum - 1.0) > 1e-6)
        problems.error(fractions.front().where,
                       fmt::format("discrete size distribution: mass fractions sum to {}, not 1",
                                   fraction_sum));
      for (std::size_t k = 0; k < radii.size(); ++k) {
        class_radius_.push_back(radii[k].value);
        class_mass_fraction_.push_back(fractions[k].value / fraction_sum);
      }
      min_radius_ = *std::min_element(class_radius_.begin(), class_radius_.end());
      max_radius_ = *std::max_element(class_radius_.begin(), class_radius_.end());
      drawn_radius_cubed_per_class_.assign(class_radius_.size(), 0.0);
      break;
    }
  }
  if (problems.has_errors()) throw UserError(std::move(problems));
}

double SizeSampler::sample(Random& random) {
  switch (kind_) {
    case SizeDistributionKind::fixed:
      return fixed_radius_;
    case SizeDistributionKind::uniform:
      return min_radius_ + (max_radius_ - min_radius_) * random.uniform();
    case SizeDistributionKind::normal:
    case SizeDistributionKind::log_normal: {
      // Rejection in standard-normal units keeps exactly the truncated density (the constructor
      // guaranteed an acceptance ≥ 0.1 %). The clamp only absorbs the last-bit rounding of the
      // back-transform.
      double z = random.normal();
      while (z < lower_z_ || z > upper_z_) z = random.normal();
      const double radius = kind_ == SizeDistributionKind::normal
                                ? location_ + spread_ * z
                                : portable_exp(location_ + spread_ * z);
      return std::clamp(radius, min_radius_, max_radius_);
    }
    case SizeDistributionKind::discrete:
      return sample_discrete();
  }
  return fixed_radius_;
}

double SizeSampler::sample_discrete() {
  // Largest deficit: class k is owed w_k·T − C_k, where C_k = Σ R³ already drawn in class k and
  // T = Σ_k C_k (mass ∝ R³ for one density). Deficits sum to zero, so the largest is ≥ 0; drawing
  // it keeps every class within one particle mass of its share (an apportionment rule in the
  // manner of Hamilton's largest remainder). Ties go to the lower class index.
  double total = 0.0;
  for (double drawn : drawn_radius_cubed_per_class_) total += drawn;
  std::size_t chosen = 0;
  double largest_deficit = -1e300;
  for (std::size_t k = 0; k < class_radius_.size(); ++k) {
    if (class_mass_fraction_[k] <= 0.0) continue;
    const double deficit = class_mass_fraction_[k] * total - drawn_radius_cubed_per_class_[k];
    if (deficit > largest_deficit) {
      largest_deficit = deficit;
      chosen = k;
    }
  }
  const double radius = class_radius_[chosen];
  drawn_radius_cubed_per_class_[chosen] += radius * radius * radius;
  return radius;
}

double SizeSampler::mean_particle_mass(double density) const {
  const double sphere_factor = density * 4.0 / 3.0 * std::numbers::pi;  // m = ρ·4/3·π·R³
  switch (kind_) {
    case SizeDistributionKind::fixed:
      return sphere_factor * fixed_radius_ * fixed_radius_ * fixed_radius_;
    case SizeDistributionKind::uniform: {
      // E[R³] = (b⁴ − a⁴) / (4 (b − a)) for R ~ U(a, b).
      const double a = min_radius_, b = max_radius_;
      if (b == a) return sphere_factor * a * a * a;
      return sphere_factor * (b * b * b * b - a * a * a * a) / (4.0 * (b - a));
    }
    case SizeDistributionKind::normal: {
      // Moments of the standard normal truncated to [α, β] (Johnson, Kotz & Balakrishnan,
      // Continuous Univariate Distributions vol. 1, 2nd ed. 1994, ch. 13):
      // m₀ = 1, m₁ = (φ(α) − φ(β))/Z, m_k = (k−1) m_{k−2} + (α^{k−1}φ(α) − β^{k−1}φ(β))/Z,
      // Z = Φ(β) − Φ(α); then E[R³] = Σ_j C(3,j) μ^{3−j} σ^j m_j for R = μ + σ z.
      const double a = lower_z_, b = upper_z_;
      const double phi_a = standard_normal_density(a), phi_b = standard_normal_density(b);
      const double kept = standard_normal_cdf(b) - standard_normal_cdf(a);
      const double m1 = (phi_a - phi_b) / kept;
      const double m2 = 1.0 + (a * phi_a - b * phi_b) / kept;
      const double m3 = 2.0 * m1 + (a * a * phi_a - b * b * phi_b) / kept;
      const double mu = location_, sigma = spread_;
      const double mean_cube = mu * mu * mu + 3.0 * mu * mu * sigma * m1 +
                               3.0 * mu * sigma * sigma * m2 + sigma * sigma * sigma * m3;
      return sphere_factor * mean_cube;
    }
    case SizeDistributionKind::log_normal: {
      // E[R^k] for ln R ~ N(μ, σ²) truncated to ln R in [μ + ασ, μ + βσ]:
      // exp(kμ + k²σ²/2) · (Φ(β − kσ) − Φ(α − kσ)) / (Φ(β) − Φ(α)), here k = 3.
      const double mu = location_, sigma = spread_;
      const double kept = standard_normal_cdf(upper_z_) - standard_normal_cdf(lower_z_);
      const double shifted =
          standard_normal_cdf(upper_z_ - 3.0 * sigma) - standard_normal_cdf(lower_z_ - 3.0 * sigma);
      return sphere_factor * std::exp(3.0 * mu + 4.5 * sigma * sigma) * shifted / kept;
    }
    case SizeDistributionKind::discrete: {
      // With mass fractions w_k the number fractions are n_k ∝ w_k / m_k, so the mean mass is
      // Σ n_k m_k / Σ n_k = 1 / Σ_k (w_k / m_k).
      double inverse = 0.0;
      for (std::size_t k = 0; k < class_radius_.size(); ++k) {
        const double r = class_radius_[k];
        inverse += class_mass_fraction_[k] / (sphere_factor * r * r * r);
      }
      return 1.0 / inverse;
    }
  }
  return 0.0;
}

void SizeSampler::set_state(const std::vector<double>& state) {
  if (state.size() != drawn_radius_cubed_per_class_.size())
    throw std::invalid_argument(fmt::format("SizeSampler::set_state: {} values for {} size classes",
                                            state.size(), drawn_radius_cubed_per_class_.size()));
  drawn_radius_cubed_per_class_ = state;
}

}  // namespace quarry
