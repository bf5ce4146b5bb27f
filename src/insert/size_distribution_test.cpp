// Tests for SizeSampler: sample mean and variance of each distribution against its closed form
// (tolerance 4 standard errors of the sample), closed-form mean particle masses against direct
// numerical integration, the discrete mass-fraction rule, checkpoint state, and input errors.
#include "insert/size_distribution.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>

namespace quarry {

namespace {

constexpr double kDensity = 2500.0;  // kg/m³
constexpr int kSamples = 200000;

double sphere_mass(double radius) {
  return kDensity * 4.0 / 3.0 * std::numbers::pi * radius * radius * radius;
}
double phi(double z) {
  return std::exp(-0.5 * z * z) / std::sqrt(2.0 * std::numbers::pi);
}
double big_phi(double z) {
  return 0.5 * std::erfc(-z / std::numbers::sqrt2);
}

// ∫ f over [a, b] by composite Simpson with 20000 panels (error ~ h⁴, far below the tolerances).
double simpson(const std::function<double(double)>& f, double a, double b) {
  const int panels = 20000;
  const double h = (b - a) / panels;
  double sum = f(a) + f(b);
  for (int i = 1; i < panels; ++i) sum += f(a + i * h) * (i % 2 ? 4.0 : 2.0);
  return sum * h / 3.0;
}

struct SampleMoments {
  double mean, variance, variance_standard_error;
};

SampleMoments sample_moments(SizeSampler& sampler, Random& random, double lo, double hi) {
  std::vector<double> radii(kSamples);
  for (auto& r : radii) {
    r = sampler.sample(random);
    EXPECT_GE(r, lo);
    EXPECT_LE(r, hi);
  }
  double mean = 0.0;
  for (double r : radii) mean += r;
  mean /= kSamples;
  double m2 = 0.0, m4 = 0.0;
  for (double r : radii) {
    const double d = (r - mean) * (r - mean);
    m2 += d;
    m4 += d * d;
  }
  m2 /= kSamples;
  m4 /= kSamples;
  // Standard error of a sample variance: √((μ₄ − σ⁴)/n) (Kendall & Stuart, The Advanced
  // Theory of Statistics vol. 1, sampling moments).
  return {mean, m2, std::sqrt((m4 - m2 * m2) / kSamples)};
}

}  // namespace

TEST(SizeSampler, FixedAlwaysGivesTheRadius) {
  SizeDistributionSpec spec;
  spec.radius = 1.5e-3;
  SizeSampler sampler(spec);
  Random random(1);
  for (int i = 0; i < 100; ++i) EXPECT_EQ(sampler.sample(random), 1.5e-3);
  EXPECT_EQ(sampler.min_radius(), 1.5e-3);
  EXPECT_EQ(sampler.max_radius(), 1.5e-3);
  EXPECT_DOUBLE_EQ(sampler.mean_particle_mass(kDensity), sphere_mass(1.5e-3));
}

TEST(SizeSampler, UniformMatchesMeanVarianceAndThirdMoment) {
  // U(a, b): mean (a+b)/2, variance (b−a)²/12, E[R³] = (b⁴ − a⁴)/(4(b − a)).
  const double a = 1e-3, b = 3e-3;
  SizeDistributionSpec spec;
  spec.kind = SizeDistributionKind::uniform;
  spec.min_radius = a;
  spec.max_radius = b;
  SizeSampler sampler(spec);
  Random random(2);
  const SampleMoments m = sample_moments(sampler, random, a, b);
  const double variance = (b - a) * (b - a) / 12.0;
  EXPECT_NEAR(m.mean, 0.5 * (a + b), 4.0 * std::sqrt(variance / kSamples));
  EXPECT_NEAR(m.variance, variance, 4.0 * m.variance_standard_error);
  EXPECT_NEAR(sampler.mean_particle_mass(kDensity),
              sphere_mass(1.0) * (b * b * b * b - a * a * a * a) / (4.0 * (b - a)),
              1e-12 * sphere_mass(b));
}

TEST(SizeSampler, TruncatedNormalMatchesClosedFormMoments) {
  // Normal(μ, σ²) truncated to [a, b], α = (a−μ)/σ, β = (b−μ)/σ, Z = Φ(β) − Φ(α):
  // mean μ + σ (φ(α) − φ(β))/Z; variance σ² [1 + (αφ(α) − βφ(β))/Z − ((φ(α) − φ(β))/Z)²]
  // (Johnson, Kotz & Balakrishnan, Continuous Univariate Distributions vol. 1, 2nd ed. 1994, ch.
  // 13). Asymmetric truncation so that a sampler ignoring the bounds would fail.
  const double mu = 2e-3, sigma = 0.5e-3, a = 1.5e-3, b = 3.2e-3;
  SizeDistributionSpec spec;
  spec.kind = SizeDistributionKind::normal;
  spec.mean_radius = mu;
  spec.std_radius = sigma;
  spec.min_radius = a;
  spec.max_radius = b;
  SizeSampler sampler(spec);
  const double alpha = (a - mu) / sigma, beta = (b - mu) / sigma,
               z = big_phi(beta) - big_phi(alpha);
  const double shift = (phi(alpha) - phi(beta)) / z;
  const double mean = mu + sigma * shift;
  const double variance =
      sigma * sigma * (1.0 + (alpha * phi(alpha) - beta * phi(beta)) / z - shift * shift);
  Random random(3);
  const SampleMoments m = sample_moments(sampler, random, a, b);
  EXPECT_NEAR(m.mean, mean, 4.0 * std::sqrt(variance / kSamples));
  EXPECT_NEAR(m.variance, variance, 4.0 * m.variance_standard_error);
  // Mean mass ρ·4/3·π·E[R³] against ∫ m(r) f(r) dr with the truncated density by quadrature.
  const auto density = [&](double r) { return phi((r - mu) / sigma) / (sigma * z); };
  const double integrated = simpson([&](double r) { return sphere_mass(r) * density(r); }, a, b);
  EXPECT_NEAR(sampler.mean_particle_mass(kDensity), integrated, 1e-9 * integrated);
}

TEST(SizeSampler, NormalWithoutBoundsIsTruncatedAtThreeSigma) {
  SizeDistributionSpec spec;
  spec.kind = SizeDistributionKind::normal;
  spec.mean_radius = 2e-3;
  spec.std_radius = 0.2e-3;
  SizeSampler sampler(spec);
  EXPECT_DOUBLE_EQ(sampler.min_radius(), 1.4e-3);
  EXPECT_DOUBLE_EQ(sampler.max_radius(), 2.6e-3);
}

TEST(SizeSampler, TruncatedLogNormalMatchesClosedFormMomentsAndMedian) {
  // ln R ~ N(μ, σ²) truncated to [a, b]; with α, β the bounds in standard units of ln R,
  // E[R^k] = exp(kμ + k²σ²/2) (Φ(β − kσ) − Φ(α − kσ)) / (Φ(β) − Φ(α))
  // (Johnson, Kotz & Balakrishnan vol. 1, 2nd ed. 1994, ch. 14).
  const double mu = std::log(2e-3), sigma = 0.3, a = 1.2e-3, b = 3.5e-3;
  SizeDistributionSpec spec;
  spec.kind = SizeDistributionKind::log_normal;
  spec.log_mean = mu;
  spec.log_std = sigma;
  spec.min_radius = a;
  spec.max_radius = b;
  SizeSampler sampler(spec);
  const double alpha = (std::log(a) - mu) / sigma, beta = (std::log(b) - mu) / sigma;
  const auto raw_moment = [&](int k) {
    return std::exp(k * mu + 0.5 * k * k * sigma * sigma) *
           (big_phi(beta - k * sigma) - big_phi(alpha - k * sigma)) /
           (big_phi(beta) - big_phi(alpha));
  };
  const double mean = raw_moment(1);
  const double variance = raw_moment(2) - mean * mean;
  Random random(4);
  const SampleMoments m = sample_moments(sampler, random, a, b);
  EXPECT_NEAR(m.mean, mean, 4.0 * std::sqrt(variance / kSamples));
  EXPECT_NEAR(m.variance, variance, 4.0 * m.variance_standard_error);
  // The closed form itself, against quadrature of the log-normal density r⁻¹ φ((ln r − μ)/σ)/σ.
  const double z = big_phi(beta) - big_phi(alpha);
  const auto density = [&](double r) { return phi((std::log(r) - mu) / sigma) / (r * sigma * z); };
  EXPECT_NEAR(simpson([&](double r) { return r * density(r); }, a, b), mean, 1e-9 * mean);
  const double integrated = simpson([&](double r) { return sphere_mass(r) * density(r); }, a, b);
  EXPECT_NEAR(sampler.mean_particle_mass(kDensity), integrated, 1e-9 * integrated);

  // Default bounds exp(μ ± 3σ) are symmetric in ln R, so the median stays exp(μ): the fraction
  // below it is 1/2 within 4 binomial standard errors 4·½/√n.
  SizeDistributionSpec untruncated;
  untruncated.kind = SizeDistributionKind::log_normal;
  untruncated.log_mean = mu;
  untruncated.log_std = sigma;
  SizeSampler median_sampler(untruncated);
  int below = 0;
  for (int i = 0; i < kSamples; ++i) below += median_sampler.sample(random) < std::exp(mu);
  EXPECT_NEAR(static_cast<double>(below) / kSamples, 0.5, 4.0 * 0.5 / std::sqrt(kSamples));
}

TEST(SizeSampler, DiscreteMassFractionsStayWithinOneParticleMassAtEveryDraw) {
  const std::vector<double> radii = {1e-3, 2e-3, 4e-3};
  const std::vector<double> fractions = {0.2, 0.5, 0.3};
  SizeDistributionSpec spec;
  spec.kind = SizeDistributionKind::discrete;
  for (std::size_t k = 0; k < radii.size(); ++k) {
    spec.discrete_radii.emplace_back(radii[k]);
    spec.discrete_mass_fractions.emplace_back(fractions[k]);
  }
  SizeSampler sampler(spec);
  EXPECT_EQ(sampler.min_radius(), 1e-3);
  EXPECT_EQ(sampler.max_radius(), 4e-3);
  Random random(5);
  std::vector<double> class_mass(radii.size(), 0.0);
  std::vector<int> class_count(radii.size(), 0);
  double total = 0.0;
  const double largest_mass = sphere_mass(4e-3);
  for (int draw = 0; draw < 20000; ++draw) {
    const double r = sampler.sample(random);
    const auto k =
        static_cast<std::size_t>(std::find(radii.begin(), radii.end(), r) - radii.begin());
    ASSERT_LT(k, radii.size());
    class_mass[k] += sphere_mass(r);
    class_count[k] += 1;
    total += sphere_mass(r);
    for (std::size_t j = 0; j < radii.size(); ++j)
      ASSERT_LE(std::abs(class_mass[j] - fractions[j] * total), largest_mass)
          << "draw " << draw << " class " << j;
  }
  // Mean mass 1 / Σ w_k/m_k equals total mass / count.
  const int count = class_count[0] + class_count[1] + class_count[2];
  EXPECT_NEAR(sampler.mean_particle_mass(kDensity), total / count, largest_mass / count);
}

TEST(SizeSampler, DiscreteStateRestoresTheSequence) {
  SizeDistributionSpec spec;
  spec.kind = SizeDistributionKind::discrete;
  spec.discrete_radii = {Located<double>(1e-3), Located<double>(3e-3)};
  spec.discrete_mass_fractions = {Located<double>(0.7), Located<double>(0.3)};
  SizeSampler sampler(spec);
  Random random(6);
  for (int i = 0; i < 37; ++i) sampler.sample(random);
  const std::vector<double> saved = sampler.state();
  ASSERT_EQ(saved.size(), 2u);
  std::vector<double> expected;
  for (int i = 0; i < 40; ++i) expected.push_back(sampler.sample(random));
  SizeSampler restored(spec);
  restored.set_state(saved);
  for (int i = 0; i < 40; ++i) EXPECT_EQ(restored.sample(random), expected[i]);
  EXPECT_THROW(restored.set_state({1.0}), std::invalid_argument);
}

TEST(SizeSampler, InvalidSpecsAreUserErrorsWithEveryProblemAtOnce) {
  SizeDistributionSpec uniform;
  uniform.kind = SizeDistributionKind::uniform;
  uniform.min_radius = 2e-3;
  uniform.max_radius = Located<double>(1e-3, SourceLocation{"deck.yaml", 12, 20});
  try {
    SizeSampler sampler(uniform);
    ADD_FAILURE() << "max < min accepted";
  } catch (const UserError& error) {
    ASSERT_EQ(error.diagnostics().all().size(), 1u);
    EXPECT_EQ(error.diagnostics().all()[0].where.line, 12);
  }
  SizeDistributionSpec discrete;
  discrete.kind = SizeDistributionKind::discrete;
  discrete.discrete_radii = {Located<double>(-1e-3), Located<double>(2e-3)};
  discrete.discrete_mass_fractions = {Located<double>(0.5), Located<double>(0.4)};
  try {
    SizeSampler sampler(discrete);
    ADD_FAILURE() << "negative radius and fractions summing to 0.9 accepted";
  } catch (const UserError& error) {
    EXPECT_EQ(error.diagnostics().all().size(), 2u);
  }
  SizeDistributionSpec no_spread;
  no_spread.kind = SizeDistributionKind::normal;
  no_spread.mean_radius = 1e-3;
  EXPECT_THROW(SizeSampler{no_spread}, UserError);
  SizeDistributionSpec far_tail;  // window 10σ above the mean keeps ~1e-23 of the probability
  far_tail.kind = SizeDistributionKind::normal;
  far_tail.mean_radius = 1e-3;
  far_tail.std_radius = 1e-4;
  far_tail.min_radius = 2e-3;
  far_tail.max_radius = 3e-3;
  EXPECT_THROW(SizeSampler{far_tail}, UserError);
}

}  // namespace quarry
