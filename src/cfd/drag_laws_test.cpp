// Drag laws: values from each published formula evaluated independently (python3 literals, the
// script in each comment), the Stokes limits and their order, the known jumps at the switches,
// force along the slip, bad input, and the seed's settling particle (terminal velocity).
#include "cfd/drag_laws.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

namespace quarry::cfd {
namespace {

constexpr double kPi = std::numbers::pi;

constexpr std::array<DragLaw, 6> kAllLaws{DragLaw::stokes,    DragLaw::schiller_naumann,
                                          DragLaw::di_felice, DragLaw::gidaspow,
                                          DragLaw::koch_hill, DragLaw::beetstra};

// The reference points' fluid and particle: ρ_f = 1000 kg/m³, μ = 1e-3 Pa·s, d = 1e-3 m, so
// Re = 1000 |u − v| on the slip and Re_p = 1000 ε |u − v| on the superficial slip. The particle
// is at rest and the fluid moves at `slip` m/s along (2, 3, 6)/7, off every axis.
DragInput reference_input(double porosity, double slip) {
  DragInput input;
  input.diameter = 1e-3;
  input.fluid_density = 1000.0;
  input.fluid_viscosity = 1e-3;
  input.porosity = porosity;
  input.fluid_velocity = slip * Vec3{2.0 / 7.0, 3.0 / 7.0, 6.0 / 7.0};
  return input;
}

struct ReferencePoint {
  double porosity;  // ε (1)
  double slip;      // |u − v| (m/s)
  double force;     // |F| (N), from the published formula
};

// |F| to 1e-12 relative: the same formula in double, only the order of operations differs.
// F = β_p (u − v) is checked through the coefficient too.
void expect_reference_values(DragLaw law, const std::vector<ReferencePoint>& points) {
  for (const ReferencePoint& point : points) {
    SCOPED_TRACE(std::string(drag_law_name(law)) + " at ε = " + std::to_string(point.porosity) +
                 ", |u − v| = " + std::to_string(point.slip) + " m/s");
    const DragResult result = drag_force(law, reference_input(point.porosity, point.slip));
    EXPECT_NEAR(norm(result.force), point.force, 1e-12 * point.force);
    EXPECT_NEAR(result.coefficient * point.slip, point.force, 1e-12 * point.force);
  }
}

// Each block's literals come from one python3 (3.11, Debian) session, printed with repr():
//   from math import pi, sqrt, exp, log, log10
//   rho, mu, d = 1000.0, 1e-3, 1e-3; A = pi*d*d/4; Vp = pi*d**3/6
//   cd_sn = lambda re: 24/re*(1+0.15*re**0.687) if re < 1000 else 0.44
// then the law's F(eps, s) as written in its test, s the slip |u − v| (m/s).

TEST(DragReference, StokesWithTheSeedsPorosityFactor) {
  // F = 3*pi*eps*d*mu*s (seed 001). Re = 2.725, 10, 100: beyond Stokes' range, but the law is
  // linear in s whatever Re.
  expect_reference_values(DragLaw::stokes, {{1.0, 0.002725, 2.5682519943096557e-08},
                                            {0.8, 0.01, 7.539822368615504e-08},
                                            {0.45, 0.1, 4.241150082346221e-07}});
}

TEST(DragReference, SchillerNaumannOnBothSidesOfRe1000) {
  // F = 0.5*rho*cd_sn(rho*s*d/mu)*A*s*s; eps enters nowhere (ε = 0.6 at Re = 500 shows it).
  // Re = 0.27, 10, 500, 999.9, 1000.1, 5000.
  expect_reference_values(DragLaw::schiller_naumann, {{1.0, 0.00027, 2.699954866707101e-09},
                                                      {1.0, 0.01, 1.6301197829009836e-07},
                                                      {0.6, 0.5, 5.523953681337212e-05},
                                                      {1.0, 0.9999, 0.00017208696267075432},
                                                      {1.0, 1.0001, 0.00017282215519450408},
                                                      {1.0, 5.0, 0.004319689898685966}});
}

TEST(DragReference, DiFelice) {
  // re = rho*eps*s*d/mu; chi = 3.7 - 0.65*exp(-(1.5-log10(re))**2/2); cd = (0.63+4.8/sqrt(re))**2
  // F = 0.5*cd*rho*A*eps**2*s*s*eps**(-chi).   Re_p = 0.01, 1, 30 (near χ's dip at 10^1.5),
  // 225, 5000.
  expect_reference_values(DragLaw::di_felice, {{1.0, 0.00001, 9.286849869605255e-11},
                                               {0.9, 1.0 / 900.0, 1.6722697219538353e-08},
                                               {0.6, 0.05, 3.809202959871692e-06},
                                               {0.45, 0.5, 0.00023999890122849133},
                                               {0.4, 12.5, 0.13455179998139366}});
}

TEST(DragReference, GidaspowOnBothSidesOfEpsilon08AndRe1000) {
  // The Eulerian beta of Gidaspow 1994 and F = beta*Vp/(1-eps)*s:
  //   eps < 0.8: beta = 150*(1-eps)**2*mu/(eps*d*d) + 1.75*(1-eps)*rho*s/d
  //   else: re = rho*eps*s*d/mu; beta = 0.75*cd_sn(re)*eps*(1-eps)*rho*s/d*eps**(-2.65)
  // At eps = 1 (where beta/(1-eps) is 0/0) its limit 0.75*cd_sn(re)*rho*s/d*eps**(-1.65)*Vp*s.
  // Points: ε = 0.4; ε = 0.79, 0.8, 0.81 at Re = 50; ε = 0.95 at Re_p = 950 and 1045; ε = 1.
  expect_reference_values(DragLaw::gidaspow, {{0.4, 0.001, 1.1872602236691428e-07},
                                              {0.79, 0.05, 3.3346282781379e-06},
                                              {0.8, 0.05, 2.460993875859231e-06},
                                              {0.81, 0.05, 2.3946477939690666e-06},
                                              {0.95, 1.0, 0.00019072177887288674},
                                              {0.95, 1.1, 0.00022753802480628382},
                                              {1.0, 0.00027, 2.699954866707101e-09}});
}

TEST(DragReference, GidaspowPerParticleForceIsTheEulerianBetaOverTheNumberDensity) {
  // beta (kg/(m³·s)) of the previous test at (0.4, 0.001) and (0.95, 1.0): β = n β_p.
  const DragInput packed = reference_input(0.4, 0.001);
  const DragInput dilute = reference_input(0.95, 1.0);
  EXPECT_NEAR(volumetric_exchange_coefficient(gidaspow_drag(packed).coefficient, packed), 136050.0,
              1e-12 * 136050.0);
  EXPECT_NEAR(volumetric_exchange_coefficient(gidaspow_drag(dilute).coefficient, dilute),
              18212.588317739617, 1e-12 * 18212.588317739617);
}

TEST(DragReference, KochHillOnBothSidesOfPhi04) {
  // phi = 1-eps; re = rho*eps*s*d/mu (the papers' Re on the radius is re/2);
  //   f0 = (1+3*sqrt(phi/2)+135/64*phi*log(phi)+16.14*phi)/(1+0.681*phi-8.48*phi**2+8.16*phi**3)
  //        if phi < 0.4 else 10*phi/(1-phi)**3   (1 at phi = 0)
  //   f3 = 0.0673+0.212*phi+0.0232/(1-phi)**5;  F = f0 + f3*re/2
  //   beta = 18*mu*eps**2*phi*F/d**2 (Benyahia et al. 2006), force beta*Vp/(1-eps)*s;
  //   at eps = 1, 3*pi*mu*d*F*s.
  // Points: ε = 1 (Re_p 1), 0.9 (90), 0.61, 0.6, 0.59 (φ = 0.39, 0.4, 0.41; Re_p ≈ 12), 0.45 (90).
  expect_reference_values(DragLaw::koch_hill, {{1.0, 0.001, 9.851249163494194e-09},
                                               {0.9, 0.1, 6.545262721694235e-06},
                                               {0.61, 0.02, 1.3782879431901824e-06},
                                               {0.6, 0.02, 1.4400395544171098e-06},
                                               {0.59, 0.02, 1.4952152348315387e-06},
                                               {0.45, 0.2, 4.77926741132494e-05}});
}

TEST(DragReference, Beetstra) {
  // phi = 1-eps; e = eps; re = rho*eps*s*d/mu;
  //   F = 10*phi/e**2 + e**2*(1+1.5*sqrt(phi)) + 0.413*re/(24*e**2)*(1/e+3*e*phi
  //       + 8.4*re**-0.343)/(1+10**(3*phi)*re**(-(1+4*phi)/2))
  //   force 3*pi*mu*d*(eps*s)*F (Stokes' drag at the superficial slip times F).
  // Re_p = 0.1, 9, 70, 250, 1000.
  expect_reference_values(DragLaw::beetstra, {{1.0, 0.0001, 9.500778302171394e-10},
                                              {0.9, 0.01, 2.665791887930093e-07},
                                              {0.7, 0.1, 1.0689624250400172e-05},
                                              {0.5, 0.5, 0.00020980294196537778},
                                              {0.4, 2.5, 0.004415092386684853}});
}

// ---- Limits -------------------------------------------------------------------------------

// β_p over Stokes' 3π μ d, at ε and slip.
double ratio_to_stokes(DragLaw law, double porosity, double slip) {
  const DragInput input = reference_input(porosity, slip);
  return drag_force(law, input).coefficient / (3.0 * kPi * input.fluid_viscosity * input.diameter);
}

TEST(DragLimits, StokesLimitAtEpsilon1AndItsOrderInRe) {
  // At ε = 1 and Re → 0, β_p / (3π μ d) = c0 (1 + c Re^p + …), from each formula's expansion:
  //   Stokes            1 exactly
  //   Schiller-Naumann  1 + 0.15 Re^0.687                                  (exact below 1000)
  //   Gidaspow          the same (Wen-Yu at ε = 1 is Schiller-Naumann)
  //   Koch-Hill         1 + ½ F3(0) Re = 1 + 0.04525 Re                    (exact, F0(0) = 1)
  //   Beetstra          1 + (0.413·8.4/24) Re^(1 + 0.5 − 0.343) = 1 + 0.14455 Re^1.157 + …
  //   Di Felice         0.96 (1 + 0.13125 √Re)² = 0.96 (1 + 0.2625 √Re + …): not Stokes,
  //                     Dallavalle's 4.8² = 23.04 is 96 % of 24.
  EXPECT_DOUBLE_EQ(ratio_to_stokes(DragLaw::stokes, 1.0, 1e-9), 1.0);
  const double re = 1e-6;    // Re at a slip of 1e-9 m/s
  const double slip = 1e-9;  // m/s
  EXPECT_NEAR(
      (ratio_to_stokes(DragLaw::schiller_naumann, 1.0, slip) - 1.0) / (0.15 * std::pow(re, 0.687)),
      1.0, 1e-9);
  EXPECT_NEAR((ratio_to_stokes(DragLaw::gidaspow, 1.0, slip) - 1.0) / (0.15 * std::pow(re, 0.687)),
              1.0, 1e-9);
  // Koch-Hill's excess is linear: at Re = 1e-3 the rounding is 1e-16 against 4.5e-5.
  EXPECT_NEAR((ratio_to_stokes(DragLaw::koch_hill, 1.0, 1e-6) - 1.0) / (0.04525 * 1e-3), 1.0, 1e-9);
  // Next terms of Beetstra's: relative Re^0.343/8.4 = 1.2e-3 and Re^0.5 = 1e-3.
  EXPECT_NEAR((ratio_to_stokes(DragLaw::beetstra, 1.0, slip) - 1.0) /
                  (0.413 * 8.4 / 24.0 * std::pow(re, 1.157)),
              1.0, 5e-3);
  // Next term of Di Felice's: relative 0.13125² Re / (0.2625 √Re) = 6.6e-5.
  EXPECT_NEAR(
      (ratio_to_stokes(DragLaw::di_felice, 1.0, slip) / 0.96 - 1.0) / (0.2625 * std::sqrt(re)), 1.0,
      1e-3);
}

TEST(DragLimits, ZeroSlipGivesZeroForceAndTheCreepingFlowCoefficient) {
  // u = v: the force is exactly zero (no 0/0), the coefficient is the law's Re → 0 limit,
  // from the formulas with Re = 0 (written out here, φ = 1 − ε, in units of 3π μ d):
  //   Stokes ε; Schiller-Naumann 1; Di Felice 0.96 ε^(1−3.7) (χ(0) = 3.7);
  //   Gidaspow: Ergun 150 (1 − ε)/(18 ε) for ε < 0.8 (V_p/(3π d³) = 1/18), ε^(−2.65) above;
  //   Koch-Hill ε² F0(φ); Beetstra ε (10 φ/ε² + ε² (1 + 1.5 √φ)).
  for (const double porosity : {0.45, 0.7, 0.8, 0.9, 1.0}) {
    DragInput input = reference_input(porosity, 0.0);
    input.fluid_velocity = Vec3{0.3, -0.1, 2.0};
    input.particle_velocity = input.fluid_velocity;
    const double phi = 1.0 - porosity;
    const double stokes = 3.0 * kPi * input.fluid_viscosity * input.diameter;  // kg/s
    double koch_hill_f0 = 1.0;                                                 // φ = 0
    if (phi > 0.0 && phi < 0.4)
      koch_hill_f0 =
          (1.0 + 3.0 * std::sqrt(phi / 2.0) + 135.0 / 64.0 * phi * std::log(phi) + 16.14 * phi) /
          (1.0 + 0.681 * phi - 8.48 * phi * phi + 8.16 * phi * phi * phi);
    else if (phi >= 0.4)
      koch_hill_f0 = 10.0 * phi / (porosity * porosity * porosity);
    const double expected[] = {
        porosity,
        1.0,
        0.96 * std::pow(porosity, -2.7),
        porosity < 0.8 ? 150.0 * phi / (18.0 * porosity) : std::pow(porosity, -2.65),
        porosity * porosity * koch_hill_f0,
        porosity * (10.0 * phi / (porosity * porosity) +
                    porosity * porosity * (1.0 + 1.5 * std::sqrt(phi))),
    };
    for (std::size_t i = 0; i < kAllLaws.size(); ++i) {
      SCOPED_TRACE(std::string(drag_law_name(kAllLaws[i])) + " at ε = " + std::to_string(porosity));
      const DragResult result = drag_force(kAllLaws[i], input);
      EXPECT_EQ(result.force, Vec3{});
      EXPECT_TRUE(std::isfinite(result.coefficient));
      EXPECT_NEAR(result.coefficient / stokes, expected[i], 1e-13 * expected[i]);
    }
  }
}

TEST(DragLimits, ApproachToEpsilon1InCreepingFlow) {
  // The order in φ = 1 − ε of each law's departure from its ε = 1 value, at zero slip (Re = 0):
  //   Stokes 1 − φ; Schiller-Naumann none; Di Felice ε^(−2.7) = 1 + 2.7 φ + …;
  //   Gidaspow ε^(−2.65) = 1 + 2.65 φ + …; Koch-Hill 1 + (3/√2) √φ + O(φ ln φ) (the Brinkman
  //   screening of dilute random arrays); Beetstra 1 + 1.5 √φ + O(φ).
  const double phi = 1e-10;
  const double porosity = 1.0 - phi;
  EXPECT_NEAR((1.0 - ratio_to_stokes(DragLaw::stokes, porosity, 0.0)) / phi, 1.0, 1e-5);
  EXPECT_EQ(ratio_to_stokes(DragLaw::schiller_naumann, porosity, 0.0), 1.0);
  // φ = 1e-10 leaves 1e-16/1e-10 = 1e-6 of rounding in a ratio's O(φ) part.
  EXPECT_NEAR((ratio_to_stokes(DragLaw::di_felice, porosity, 0.0) / 0.96 - 1.0) / phi, 2.7, 1e-4);
  EXPECT_NEAR((ratio_to_stokes(DragLaw::gidaspow, porosity, 0.0) - 1.0) / phi, 2.65, 1e-4);
  // √φ terms: the next terms are 5e-4 (Koch-Hill, φ ln φ / √φ) and 1e-4 (Beetstra) relative.
  EXPECT_NEAR((ratio_to_stokes(DragLaw::koch_hill, porosity, 0.0) - 1.0) / std::sqrt(phi),
              3.0 / std::sqrt(2.0), 2e-3);
  EXPECT_NEAR((ratio_to_stokes(DragLaw::beetstra, porosity, 0.0) - 1.0) / std::sqrt(phi), 1.5,
              1e-3);
}

TEST(DragLimits, DenseCreepingFlowAgainstCarmanKozeny) {
  // A check on the ε powers of the dense laws: Carman-Kozeny, −∇p = 180 μ φ² U_s / (ε³ d²)
  // with β = ε (−∇p)/(u − v), gives per particle β V_p/φ = 3π μ d · 10 φ/ε. At ε = 0.4, Re = 0:
  // Koch-Hill's ε² · 10φ/ε³ is it exactly; Beetstra's ε (10φ/ε² + ε²(1 + 1.5√φ)) is 0.9 % above;
  // Gidaspow's Ergun has 150 for 180: 5/6 of it. A wrong power of ε would be off by 2.5x.
  const double porosity = 0.4;
  const double carman_kozeny = 10.0 * (1.0 - porosity) / porosity;
  EXPECT_NEAR(ratio_to_stokes(DragLaw::koch_hill, porosity, 0.0) / carman_kozeny, 1.0, 1e-13);
  EXPECT_NEAR(ratio_to_stokes(DragLaw::beetstra, porosity, 0.0) / carman_kozeny, 1.0, 0.01);
  EXPECT_NEAR(ratio_to_stokes(DragLaw::gidaspow, porosity, 0.0) / carman_kozeny, 5.0 / 6.0, 1e-13);
}

// ---- Switches -----------------------------------------------------------------------------

TEST(DragSwitches, SchillerNaumannJumpsBy039PercentAtRe1000) {
  // cd_sn(math.nextafter(1000.0, 0.0)) = 0.43828814001999705; 0.44 / it = 1.003905786681622.
  const double below = std::nextafter(1000.0, 0.0);
  EXPECT_NEAR(schiller_naumann_drag_coefficient(below), 0.43828814001999705, 1e-15);
  EXPECT_EQ(schiller_naumann_drag_coefficient(1000.0), 0.44);
  EXPECT_EQ(schiller_naumann_drag_coefficient(1e5), 0.44);
  // The same jump in the force: with ρ_f = 1 kg/m³, μ = 1 Pa·s and d = 1 m, Re is the slip's
  // number of m/s exactly. F ∝ C_d |u − v|², so the ratio carries (1000/below)² = 1 + 2e-16.
  DragInput input;
  input.diameter = 1.0;
  input.fluid_density = 1.0;
  input.fluid_viscosity = 1.0;
  input.fluid_velocity = Vec3{0.0, 0.0, 1000.0};
  ASSERT_EQ(slip_reynolds_number(input), 1000.0);
  const double at = norm(schiller_naumann_drag(input).force);
  input.fluid_velocity = Vec3{0.0, 0.0, below};
  ASSERT_LT(slip_reynolds_number(input), 1000.0);
  const double just_below = norm(schiller_naumann_drag(input).force);
  EXPECT_NEAR(at / just_below, 1.003905786681622, 1e-12);
}

TEST(DragSwitches, GidaspowJumpsAtEpsilon08) {
  // Ergun below, Wen-Yu from ε = 0.8: not continuous (Gidaspow 1994; Lathouwers & Bellan's
  // blend exists to smooth it). With the formulas of DragReference.Gidaspow…, beta at
  // eps = nextafter(0.8, 0) and 0.8, s = 0.05 m/s (Re = 50): 25000.000000000015 and
  // 18800.608332570177, ratio 0.7520243333028066; at Re → 0 the ratio is 0.48 · 0.8^(−2.65)
  // = 0.8670672281425493.
  const double below = std::nextafter(0.8, 0.0);
  const double ergun = gidaspow_drag(reference_input(below, 0.05)).coefficient;
  const double wen_yu = gidaspow_drag(reference_input(0.8, 0.05)).coefficient;
  // β_p = β V_p/(1 − ε): the one-ulp change of 1 − ε is 5e-16 relative.
  EXPECT_NEAR(wen_yu / ergun, 0.7520243333028066, 1e-12);
  EXPECT_NEAR(
      ratio_to_stokes(DragLaw::gidaspow, 0.8, 0.0) / ratio_to_stokes(DragLaw::gidaspow, below, 0.0),
      0.8670672281425493, 1e-12);
}

TEST(DragSwitches, KochHillF0JumpsBy1PercentAtPhi04) {
  // f0 of DragReference.KochHill… at phi = nextafter(0.4, 0) and 0.4: 18.32751800082462 and
  // 18.518518518518523 (ratio 1.0104215157603613).
  const double below = std::nextafter(0.4, 0.0);
  EXPECT_NEAR(koch_hill_dimensionless_drag(below, 0.0), 18.32751800082462,
              1e-12 * 18.32751800082462);
  EXPECT_NEAR(koch_hill_dimensionless_drag(0.4, 0.0), 18.518518518518523,
              1e-12 * 18.518518518518523);
}

// ---- Direction, invariance, input ----------------------------------------------------------

TEST(DragDirection, ForceIsAlongTheSlipAndDependsOnlyOnIt) {
  const Vec3 slips[] = {{1e-3, 0.0, 0.0}, {0.0, -0.02, 0.0}, {0.3, -0.4, 1.2}, {-2.0, 1.0, -0.5}};
  const Vec3 frame{0.7, -1.3, 4.0};  // m/s added to both velocities
  for (const DragLaw law : kAllLaws) {
    for (const double porosity : {0.5, 0.85, 1.0}) {
      for (const Vec3& slip : slips) {
        SCOPED_TRACE(std::string(drag_law_name(law)) + " at ε = " + std::to_string(porosity));
        DragInput input = reference_input(porosity, 0.0);
        input.particle_velocity = Vec3{0.1, 0.2, -0.3};
        input.fluid_velocity = input.particle_velocity + slip;
        const Vec3 force = drag_force(law, input).force;
        const double scale = norm(force) * norm(slip);
        EXPECT_GT(dot(force, slip), (1.0 - 1e-12) * scale);  // parallel, not antiparallel
        EXPECT_LE(norm(cross(force, slip)), 1e-12 * scale);
        input.particle_velocity += frame;
        input.fluid_velocity += frame;
        const Vec3 moved = drag_force(law, input).force;
        // The slip is rebuilt from velocities 1e3 times its size: 1e-16 · 1e3 · 2 of rounding.
        EXPECT_NEAR(norm(moved - force), 0.0, 1e-11 * norm(force));
      }
    }
  }
}

// The message of the std::invalid_argument that `law` throws for `input` ("" if none).
std::string rejection(DragLaw law, const DragInput& input) {
  try {
    drag_force(law, input);
  } catch (const std::invalid_argument& error) {
    return error.what();
  }
  return "";
}

TEST(DragInputChecks, NonPhysicalOrNonFiniteInputIsRejectedWithTheValueNamed) {
  struct Case {
    void (*spoil)(DragInput&);
    const char* quantity;
    const char* value;
  };
  const Case cases[] = {
      {[](DragInput& in) { in.porosity = 0.0; }, "porosity", "got 0"},
      {[](DragInput& in) { in.porosity = -0.1; }, "porosity", "got -0.1"},
      {[](DragInput& in) { in.porosity = 1.2; }, "porosity", "got 1.2"},
      {[](DragInput& in) { in.porosity = std::numeric_limits<double>::quiet_NaN(); }, "porosity",
       "got nan"},
      {[](DragInput& in) { in.diameter = 0.0; }, "diameter", "got 0"},
      {[](DragInput& in) { in.diameter = -1e-3; }, "diameter", "got -0.001"},
      {[](DragInput& in) { in.diameter = std::numeric_limits<double>::infinity(); }, "diameter",
       "got inf"},
      {[](DragInput& in) { in.fluid_viscosity = 0.0; }, "viscosity", "got 0"},
      {[](DragInput& in) { in.fluid_viscosity = -1e-3; }, "viscosity", "got -0.001"},
      {[](DragInput& in) { in.fluid_density = 0.0; }, "density", "got 0"},
      {[](DragInput& in) { in.fluid_density = std::numeric_limits<double>::quiet_NaN(); },
       "density", "got nan"},
      {[](DragInput& in) { in.particle_velocity.y = std::numeric_limits<double>::quiet_NaN(); },
       "particle velocity", "(0, nan, 0)"},
      {[](DragInput& in) { in.fluid_velocity.z = -std::numeric_limits<double>::infinity(); },
       "fluid velocity", "-inf)"},
  };
  for (const DragLaw law : kAllLaws) {
    for (const Case& c : cases) {
      DragInput input = reference_input(0.7, 0.1);
      input.fluid_velocity = Vec3{0.0, 0.0, 0.1};
      c.spoil(input);
      const std::string message = rejection(law, input);
      SCOPED_TRACE(std::string(drag_law_name(law)) + ": " + message);
      EXPECT_NE(message.find(c.quantity), std::string::npos);
      EXPECT_NE(message.find(c.value), std::string::npos);
    }
  }
}

TEST(DragLawNames, EverySpellingRoundTripsAndUnknownOnesAreRefused) {
  for (const DragLaw law : kAllLaws) EXPECT_EQ(drag_law_from_name(drag_law_name(law)), law);
  EXPECT_EQ(drag_law_name(DragLaw::schiller_naumann), "schiller_naumann");
  EXPECT_EQ(drag_law_from_name("koch_hill"), DragLaw::koch_hill);
  EXPECT_FALSE(drag_law_from_name("Stokes").has_value());
  EXPECT_FALSE(drag_law_from_name("schiller-naumann").has_value());
  EXPECT_FALSE(drag_law_from_name("").has_value());
  const auto outside = static_cast<DragLaw>(99);
  EXPECT_THROW(drag_law_name(outside), std::invalid_argument);
  EXPECT_THROW(drag_force(outside, reference_input(1.0, 0.1)), std::invalid_argument);
}

// ---- The seed's settling particle -----------------------------------------------------------

// Terminal velocity (m/s) of the seed's particle (d = 0.1 mm, ρ_p = 1500 kg/m³) falling through
// still water (ρ_f = 1000 kg/m³, μ = 1e-3 Pa·s, ε = 1, g = 9.81 m/s²): the slip at which the drag
// balances weight minus buoyancy, (ρ_p − ρ_f) V_p g, found by bisection on [0, 0.01] m/s.
double terminal_velocity(DragLaw law) {
  DragInput input;
  input.diameter = 1e-4;
  input.fluid_density = 1000.0;
  input.fluid_viscosity = 1e-3;
  input.porosity = 1.0;
  const double net_weight = (1500.0 - 1000.0) * particle_volume(input) * 9.81;  // N
  double slow = 0.0, fast = 0.01;                                               // m/s
  for (int iteration = 0; iteration < 200 && fast - slow > 1e-17; ++iteration) {
    const double middle = 0.5 * (slow + fast);
    input.particle_velocity = Vec3{0.0, 0.0, -middle};  // falling; the drag points up
    if (drag_force(law, input).force.z < net_weight)
      slow = middle;
    else
      fast = middle;
  }
  return 0.5 * (slow + fast);
}

TEST(DragSettling, SeedParticleTerminalVelocities) {
  // Stokes: v_t = (ρ_p − ρ_f) g d² / (18 μ) = 500 · 9.81 · 1e-8 / 0.018 = 0.002725 m/s (seed 001,
  // analytic; EDEM gave 0.00274). Re = 0.2725.
  EXPECT_NEAR(terminal_velocity(DragLaw::stokes), 0.002725, 1e-6 * 0.002725);

  // The finite-Re laws settle slower, by the amounts their formulas give. References: the same
  // bisection in python3 on the formulas of DragReference.* (d = 1e-4, 200 halvings).
  //   Schiller-Naumann 0.0025731083085758473 (Re 0.2573, −5.57 %: v_t = v_Stokes / (1 + 0.15
  //     Re^0.687), 0.15 · 0.2573^0.687 = 0.0590); Gidaspow the same (Wen-Yu at ε = 1);
  //   Di Felice 0.0024997097137272432 (−8.27 %: the 0.96 and the √Re term);
  //   Koch-Hill 0.0026922029947340324 (−1.20 %, 1 + 0.04525 Re);
  //   Beetstra 0.00266578874372477 (−2.17 %).
  const double schiller_naumann = terminal_velocity(DragLaw::schiller_naumann);
  EXPECT_NEAR(schiller_naumann, 0.0025731083085758473, 1e-9 * 0.0025731083085758473);
  EXPECT_NEAR(terminal_velocity(DragLaw::gidaspow), 0.0025731083085758473,
              1e-9 * 0.0025731083085758473);
  EXPECT_NEAR(terminal_velocity(DragLaw::di_felice), 0.0024997097137272432,
              1e-9 * 0.0024997097137272432);
  EXPECT_NEAR(terminal_velocity(DragLaw::koch_hill), 0.0026922029947340324,
              1e-9 * 0.0026922029947340324);
  EXPECT_NEAR(terminal_velocity(DragLaw::beetstra), 0.00266578874372477,
              1e-9 * 0.00266578874372477);

  // Schiller-Naumann's value satisfies its own balance, v_t (1 + 0.15 Re^0.687) = v_Stokes with
  // Re = ρ_f v_t d / μ, and is about 6 % slower than Stokes.
  const double reynolds = 1000.0 * schiller_naumann * 1e-4 / 1e-3;
  EXPECT_NEAR(schiller_naumann * (1.0 + 0.15 * std::pow(reynolds, 0.687)), 0.002725, 1e-12);
  EXPECT_NEAR(schiller_naumann / 0.002725 - 1.0, -0.0557, 1e-4);
}

}  // namespace
}  // namespace quarry::cfd
