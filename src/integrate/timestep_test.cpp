// Time-step formulas against hand-computed values and against the Hertz impact theory they
// come from (Johnson 1985 §11.1; EDEM guide).
#include "integrate/timestep.h"

#include <gtest/gtest.h>

#include <cmath>

namespace quarry {
namespace {

TEST(TimeStep, ShearModulusOfIsotropicSolid) {
  // G = E / (2 (1 + ν)) = 7e10 / 2.5 = 2.8e10 Pa.
  EXPECT_NEAR(shear_modulus(7.0e10, 0.25), 2.8e10, 1e-3);
  EXPECT_NEAR(shear_modulus(2.0e11, 0.0), 1.0e11, 1e-3);
}

TEST(TimeStep, RayleighTimeStepMatchesHandComputation) {
  // R = 1 mm, ρ = 2500 kg/m³, G = 1e9 Pa, ν = 0.25 (EDEM guide):
  // sqrt(ρ/G) = sqrt(2.5e-6) = 1.5811388e-3 s/m; π R sqrt(ρ/G) = 4.9672941e-6 s;
  // 0.1631 · 0.25 + 0.8766 = 0.917375; T_R = 4.9672941e-6 / 0.917375 = 5.4146823e-6 s.
  EXPECT_NEAR(rayleigh_time_step(1.0e-3, 2500.0, 1.0e9, 0.25), 5.4146823e-6, 1e-13);
  // Linear in R: ten times the radius, ten times the time step.
  EXPECT_NEAR(rayleigh_time_step(1.0e-2, 2500.0, 1.0e9, 0.25), 5.4146823e-5, 1e-12);
}

TEST(TimeStep, HertzImpactFormulasMatchHandComputation) {
  // m* = 1e-3 kg, R* = 5e-3 m, E* = 1e8 Pa, V = 2 m/s:
  // m*² / (R* E*² V) = 1e-6 / (5e-3 · 1e16 · 2) = 1e-20 s⁵; ^(1/5) = 1e-4 s; T_h = 2.87e-4 s.
  EXPECT_NEAR(hertz_contact_time(1.0e-3, 5.0e-3, 1.0e8, 2.0), 2.87e-4, 1e-12);
  // δmax = (15 · 1e-3 · 4 / (16 · 1e8 · sqrt(5e-3)))^{2/5} = (0.06 / 1.1313708e8)^{2/5}
  //      = (5.3033009e-10)^{2/5} = 1.9490299e-4 m  (Johnson 1985 eq. 11.23).
  EXPECT_NEAR(hertz_peak_overlap(1.0e-3, 5.0e-3, 1.0e8, 2.0), 1.9490299e-4, 1e-11);
  // Fmax = 4/3 · 1e8 · sqrt(5e-3) · (1.9490299e-4)^{3/2} = 9.4280904e6 · 2.7209780e-6 = 25.653788
  // N.
  EXPECT_NEAR(hertz_peak_force(1.0e-3, 5.0e-3, 1.0e8, 2.0), 25.653788, 1e-5);
}

TEST(TimeStep, HertzImpactFormulasAreConsistentWithHertzTheory) {
  const double mass = 3.0e-3, radius = 2.0e-3, youngs = 4.0e9, speed = 0.7;     // kg, m, Pa, m/s
  const double peak_overlap = hertz_peak_overlap(mass, radius, youngs, speed);  // m
  // All kinetic energy is stored at the peak: ½ m* V² = ∫0^δmax 4/3 E* sqrt(R*) δ^{3/2} dδ
  // = 8/15 E* sqrt(R*) δmax^{5/2}  (Johnson 1985 §11.1).
  EXPECT_NEAR(8.0 / 15.0 * youngs * std::sqrt(radius) * std::pow(peak_overlap, 2.5),
              0.5 * mass * speed * speed, 1e-12 * mass * speed * speed);
  // Exact duration T = 2 (δmax/V) ∫0¹ (1 − x^{5/2})^{−1/2} dx with the integral
  // (2/5) B(2/5, 1/2) = 1.4716 (Johnson eq. 11.24: T = 2.94 δmax/V = 2.868 (…)^{1/5}); EDEM's
  // rounded 2.87 lies within 0.1 %.
  const double integral = 0.4 * std::tgamma(0.4) * std::tgamma(0.5) / std::tgamma(0.9);  // 1
  const double exact_duration = 2.0 * integral * peak_overlap / speed;                   // s
  EXPECT_NEAR(hertz_contact_time(mass, radius, youngs, speed), exact_duration,
              1e-3 * exact_duration);
  // Peak force against the force–overlap law at δmax.
  EXPECT_NEAR(hertz_peak_force(mass, radius, youngs, speed),
              4.0 / 3.0 * youngs * std::sqrt(radius) * std::pow(peak_overlap, 1.5),
              1e-12 * hertz_peak_force(mass, radius, youngs, speed));
}

}  // namespace
}  // namespace quarry
