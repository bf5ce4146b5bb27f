// Plane-stress J2 return map (Simo & Hughes 1998 §3.4): uniaxial stress follows the bilinear
// curve σ = σ_y0 + E H/(E + H) (ε − σ_y0/E) (tangent modulus E_t = E H/(E + H)); equibiaxial
// and shear states land on the yield surface with ε̄_p from the consistency condition; elastic
// states are untouched.
#include "fem/plane_stress_j2.h"

#include <gtest/gtest.h>

#include <cmath>

namespace quarry::fem {
namespace {

constexpr double kE = 210e9, kNu = 0.3, kYield = 250e6, kHardening = 2.1e9;

PlaneStressMaterial steel() { return {kE, kNu, kYield, kHardening}; }

TEST(PlaneStressJ2, ElasticIncrementIsHookesLaw) {
  Voigt3 stress{};
  double plastic = 0.0;
  update_plane_stress(steel(), {1e-4, -0.3e-4, 2e-4}, stress, plastic);
  const double factor = kE / (1.0 - kNu * kNu);
  EXPECT_NEAR(stress[0], factor * (1e-4 - kNu * 0.3e-4), 1.0);
  EXPECT_NEAR(stress[1], factor * (-0.3e-4 + kNu * 1e-4), 1.0);
  EXPECT_NEAR(stress[2], kE / (2.0 * (1.0 + kNu)) * 2e-4, 1.0);
  EXPECT_EQ(plastic, 0.0);
}

TEST(PlaneStressJ2, UniaxialStressFollowsTheBilinearCurve) {
  // Drive ε_xx in small steps, with ε_yy chosen each step (by a secant on σ_yy) so that σ_yy = 0:
  // a uniaxial stress path. Compare with σ = σ_y0 + E_t (ε − σ_y0/E) and ε̄_p = (σ − σ_y0)/H.
  Voigt3 stress{};
  double plastic = 0.0;
  double strain = 0.0;
  const double increment = 2e-5;
  const double tangent = kE * kHardening / (kE + kHardening);
  for (int i = 0; i < 500; ++i) {
    // Lateral increment so that σ_yy stays 0: solve g(ε_yy) = σ_yy(ε_yy) = 0 by secant.
    double lateral0 = -kNu * increment, lateral1 = -0.5 * increment;
    auto sigma_yy = [&](double lateral) {
      Voigt3 s = stress;
      double p = plastic;
      update_plane_stress(steel(), {increment, lateral, 0.0}, s, p);
      return s[1];
    };
    double g0 = sigma_yy(lateral0), g1 = sigma_yy(lateral1);
    for (int k = 0; k < 50 && std::abs(g1) > 1e-6 && g1 != g0; ++k) {
      const double next = lateral1 - g1 * (lateral1 - lateral0) / (g1 - g0);
      lateral0 = lateral1;
      g0 = g1;
      lateral1 = next;
      g1 = sigma_yy(lateral1);
    }
    update_plane_stress(steel(), {increment, lateral1, 0.0}, stress, plastic);
    strain += increment;
  }
  const double expected = kYield + tangent * (strain - kYield / kE);
  EXPECT_NEAR(stress[0], expected, 1e-6 * expected);
  EXPECT_NEAR(stress[1], 0.0, 1.0);
  EXPECT_NEAR(plastic, (stress[0] - kYield) / kHardening, 1e-9);
}

TEST(PlaneStressJ2, PlasticStatesEndOnTheHardenedYieldSurface) {
  const Voigt3 increments[] = {{5e-3, 5e-3, 0.0}, {0.0, 0.0, 8e-3}, {4e-3, -1e-3, 3e-3}};
  for (const Voigt3& increment : increments) {
    Voigt3 stress{};
    double plastic = 0.0;
    update_plane_stress(steel(), increment, stress, plastic);
    EXPECT_GT(plastic, 0.0);
    const double yield = kYield + kHardening * plastic;
    EXPECT_NEAR(von_mises(stress), yield, 1e-9 * yield);
  }
}

TEST(PlaneStressJ2, EquibiaxialReturnKeepsTheStressRatio) {
  // Equibiaxial trial: the return scales a only, so σxx = σyy = σ_y (perfect plasticity).
  PlaneStressMaterial perfect = steel();
  perfect.hardening_modulus = 0.0;
  Voigt3 stress{};
  double plastic = 0.0;
  update_plane_stress(perfect, {1e-2, 1e-2, 0.0}, stress, plastic);
  EXPECT_NEAR(stress[0], kYield, 1e-6 * kYield);
  EXPECT_NEAR(stress[1], kYield, 1e-6 * kYield);
  // Equibiaxial plastic strain rates: ε̄_p = total plastic ε_xx · 2 (flow ratio 1:1, ε̄ = 2 ε_xx
  // for ε_xx = ε_yy under incompressibility); elastic part σ_y(1 − ν)/E per direction.
  EXPECT_NEAR(plastic, 2.0 * (1e-2 - kYield * (1.0 - kNu) / kE), 1e-9);
}

}  // namespace
}  // namespace quarry::fem
