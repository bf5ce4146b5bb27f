// JKR adhesion (cohesion_jkr.h): the contact radius solver against the closed-form curve, the
// JKR 1971 pull-off force and equilibrium radius, the break at δ_c, the hysteresis through the
// contact law, and impacts that stick below and separate above the sticking velocity of the
// elastic JKR cycle.
#include "contact/cohesion_jkr.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "contact/contact_law.h"
#include "contact/contact_test_bodies.h"
#include "contact/hertz_mindlin_batch.h"
#include "core/diagnostics.h"

namespace quarry {
namespace {

using std::numbers::pi;

constexpr double kGamma = 0.2;      // J/m², γ
constexpr double kYoungs = 2.0e7;   // Pa, E*
constexpr double kRadius = 1.0e-3;  // m, R*

// δ(a) = a²/R* − sqrt(2π γ a/E*) (JKR 1971), m.
double jkr_overlap(double a) { return a * a / kRadius - std::sqrt(2.0 * pi * kGamma * a / kYoungs); }

double jkr_force(double a) { return contact::jkr_normal_force(kGamma, kYoungs, kRadius, a); }

TEST(JkrCohesion, ScalesAreTheBreakPointOfTheCurve) {
  const contact::JkrScales s = contact::jkr_scales(kGamma, kYoungs, kRadius);
  // a_c = (π γ R*²/(8 E*))^{1/3}; δ_c = −(3/4)(π² γ² R*/E*²)^{1/3} (Thornton & Yin 1991).
  EXPECT_NEAR(s.break_radius / std::cbrt(pi * kGamma * kRadius * kRadius / (8.0 * kYoungs)), 1.0, 1e-14);
  EXPECT_NEAR(s.break_overlap / (-0.75 * std::cbrt(pi * pi * kGamma * kGamma * kRadius / (kYoungs * kYoungs))),
              1.0, 1e-14);
  EXPECT_NEAR(jkr_overlap(s.break_radius) / s.break_overlap, 1.0, 1e-12);
  // The force at break is −5/6 π γ R* (5/9 of the pull-off force).
  EXPECT_NEAR(jkr_force(s.break_radius) / (pi * kGamma * kRadius), -5.0 / 6.0, 1e-12);
}

TEST(JkrCohesion, ContactRadiusInvertsTheCurveForEveryOverlap) {
  const contact::JkrScales s = contact::jkr_scales(kGamma, kYoungs, kRadius);
  const double scale = -s.break_overlap;  // m
  double previous = 0.0;
  for (int k = 0; k <= 4000; ++k) {
    // Δ from −1 to 10^4 (the break to deep contact), denser near the break.
    const double reduced = -1.0 + std::pow(k / 4000.0, 3.0) * 1.0e4;
    const double overlap = reduced * scale;  // m
    const double a = contact::jkr_contact_radius(s, overlap);
    ASSERT_TRUE(std::isfinite(a)) << overlap;
    EXPECT_GE(a, s.break_radius);
    EXPECT_GE(a, previous);  // the stable branch: a grows with δ
    // Near the double root (the break) δ(a) is flat, so compare δ, not a.
    EXPECT_NEAR(jkr_overlap(a), overlap, 1e-12 * (std::fabs(overlap) + scale)) << reduced;
    previous = a;
  }
  // Past the break, and for non-finite input, still finite: the radius at break.
  // (Newton converges only linearly onto that double root: to about sqrt(round-off).)
  EXPECT_NEAR(contact::jkr_contact_radius(s, 10.0 * s.break_overlap) / s.break_radius, 1.0, 1e-7);
  EXPECT_TRUE(std::isfinite(contact::jkr_contact_radius(s, 1.0)));  // δ ≫ |δ_c|
}

// Pull-off (JKR 1971): the least force of the curve is −3/2 π γ R*, at a = (9π γ R*²/(8E*))^{1/3}.
TEST(JkrCohesion, PullOffForceIsThreeHalvesPiGammaR) {
  const contact::JkrScales s = contact::jkr_scales(kGamma, kYoungs, kRadius);
  const double pull_off = 1.5 * pi * kGamma * kRadius;  // N
  const double a_pull_off = std::cbrt(9.0 * pi * kGamma * kRadius * kRadius / (8.0 * kYoungs));  // m
  const double at = contact::jkr_contact_radius(s, jkr_overlap(a_pull_off));
  EXPECT_NEAR(at / a_pull_off, 1.0, 1e-9);
  EXPECT_NEAR(jkr_force(at) / pull_off, -1.0, 1e-12);
  // Least over the curve from the break to δ = 0.
  double least = 0.0;
  for (int k = 0; k <= 20000; ++k) {
    const double overlap = s.break_overlap * (1.0 - k / 20000.0);
    least = std::min(least, jkr_force(contact::jkr_contact_radius(s, overlap)));
  }
  EXPECT_NEAR(least / pull_off, -1.0, 1e-6);
  EXPECT_GE(least / pull_off, -1.0 - 1e-12);
}

// Equilibrium (no load): a0 = (9π γ R*²/(2E*))^{1/3} (JKR 1971 with P = 0, K = 4E*/3), at the
// overlap δ0 = a0²/R* − sqrt(2π γ a0/E*) of the curve.
TEST(JkrCohesion, EquilibriumContactRadius) {
  const contact::JkrScales s = contact::jkr_scales(kGamma, kYoungs, kRadius);
  const double a0 = std::cbrt(9.0 * pi * kGamma * kRadius * kRadius / (2.0 * kYoungs));  // m
  const double a = contact::jkr_contact_radius(s, jkr_overlap(a0));
  EXPECT_NEAR(a / a0, 1.0, 1e-12);
  EXPECT_NEAR(jkr_force(a) / (pi * kGamma * kRadius), 0.0, 1e-11);
  // Either side of it the force restores: repulsive above, attractive below.
  EXPECT_GT(jkr_force(contact::jkr_contact_radius(s, jkr_overlap(a0) * 1.01)), 0.0);
  EXPECT_LT(jkr_force(contact::jkr_contact_radius(s, jkr_overlap(a0) * 0.99)), 0.0);
}

InteractionParameters jkr_interaction(double restitution) {
  InteractionSpec spec;
  spec.restitution = restitution;
  spec.static_friction = 0.5;
  spec.rolling_model = RollingModel::none;
  spec.cohesion_model = CohesionModel::jkr;
  spec.surface_energy = kGamma;
  const MaterialProperties material{2500.0, 5.0e7, 0.25};  // kg/m³, Pa, 1
  return make_interaction(material, material, spec);
}

// JKR needs the Hertzian contact radius, a positive γ and the attraction unclipped: each
// conflict is a user error at setup.
TEST(JkrCohesion, ConflictingSettingsAreUserErrors) {
  const MaterialProperties material{2500.0, 5.0e7, 0.25};
  const auto refused = [&](const InteractionSpec& spec, const std::string& expected) {
    try {
      make_interaction(material, material, spec);
      ADD_FAILURE() << "accepted: " << expected;
    } catch (const UserError& e) {
      EXPECT_NE(e.diagnostics().format().find(expected), std::string::npos) << e.diagnostics().format();
    }
  };
  InteractionSpec spec;
  spec.cohesion_model = CohesionModel::jkr;
  spec.surface_energy = kGamma;
  EXPECT_GT(make_interaction(material, material, spec).surface_energy, 0.0);
  InteractionSpec linear = spec;
  linear.normal_model = NormalModel::linear;
  linear.linear_stiffness = 1.0e4;
  refused(linear, "cohesion_model: jkr needs the Hertz-Mindlin contact model");
  InteractionSpec clipped = spec;
  clipped.clip_attraction = true;
  refused(clipped, "clip_attraction cannot be used with cohesion_model: jkr");
  InteractionSpec no_energy = spec;
  no_energy.surface_energy = 0.0;
  refused(no_energy, "needs a positive surface_energy");
}

// Through the contact law, sphere on a wall at rest: no force before the first touch whatever
// the gap; once touched, attached down to δ_c with the curve's force (continuous up to the
// break, −5/6 π γ R* there), then released, and not attached again until it touches.
TEST(JkrCohesion, ContactLawHysteresisAndBreak) {
  const InteractionParameters parameters = jkr_interaction(1.0);
  ASSERT_FALSE(batch_handles(parameters));  // JKR is never given to the batched kernel
  const double radius = 1.0e-3;  // m, R* against a wall
  const contact::JkrScales s =
      contact::jkr_scales(kGamma, parameters.effective_youngs_modulus, radius);
  const auto law_force = [&](double overlap, ContactHistory& history) {
    ContactKinematics k;
    k.normal = {0.0, 0.0, 1.0};
    k.overlap = overlap;
    k.radius_i = radius;
    k.inv_mass_i = 1.0 / 1.0e-5;
    return evaluate_contact(parameters, k, history, 1.0e-7).normal_force;
  };
  const auto curve = [&](double overlap) {
    return contact::jkr_normal_force(kGamma, parameters.effective_youngs_modulus, radius,
                                     contact::jkr_contact_radius(s, overlap));
  };
  ContactHistory history;
  EXPECT_EQ(law_force(0.5 * s.break_overlap, history), 0.0);  // approaching: not yet
  EXPECT_FALSE(history.jkr_attached);
  EXPECT_EQ(law_force(2.0 * -s.break_overlap, history), curve(2.0 * -s.break_overlap));
  EXPECT_TRUE(history.jkr_attached);
  // Snap-in at δ = 0: −4/3 π γ R* (u³ = 4 on the curve).
  EXPECT_NEAR(law_force(0.0, history) / (pi * kGamma * radius), -4.0 / 3.0, 1e-12);
  EXPECT_EQ(law_force(0.5 * s.break_overlap, history), curve(0.5 * s.break_overlap));
  EXPECT_LT(law_force(0.5 * s.break_overlap, history), 0.0);
  // Continuous into the break: just above δ_c the force is the break force.
  const double at_break = law_force(s.break_overlap * (1.0 - 1e-9), history);
  EXPECT_NEAR(at_break / (pi * kGamma * radius), -5.0 / 6.0, 1e-4);
  EXPECT_TRUE(history.jkr_attached);
  EXPECT_EQ(law_force(s.break_overlap * (1.0 + 1e-9), history), 0.0);  // past it: released
  EXPECT_FALSE(history.jkr_attached);
  EXPECT_EQ(law_force(0.5 * s.break_overlap, history), 0.0);  // and not caught again
  EXPECT_FALSE(history.jkr_attached);
}

// Sticking velocity of an undamped (e = 1) JKR impact, sphere on a wall: the curve is walked
// elastically in and out again down to δ = 0, where the sphere has its impact speed back; from
// there to the break it must pay W = ∫_{δ_c}^0 −F dδ (Thornton & Ning 1998 derive the sticking
// velocity from this energy balance). In the curve's units (cohesion_jkr.h) W = π γ R* |δ_c| I,
// I = −(1/3) [u^10/15 − 2u^7/3 + u^4] from u = 1 to 4^{1/3} (= 1.40325); the sphere sticks
// if ½ m V² < W and otherwise leaves at sqrt(V² − 2W/m).
TEST(JkrCohesion, ImpactSticksBelowAndSeparatesAboveTheStickingVelocity) {
  const InteractionParameters parameters = jkr_interaction(1.0);
  contact_test::Sphere sphere;
  sphere.radius = 1.0e-3;                               // m
  sphere.mass = contact_test::sphere_mass(1.0e-3, 2500.0);  // kg
  const contact::JkrScales s =
      contact::jkr_scales(kGamma, parameters.effective_youngs_modulus, sphere.radius);
  const auto bracket = [](double u) { return std::pow(u, 10) / 15.0 - 2.0 * std::pow(u, 7) / 3.0 + std::pow(u, 4); };
  const double integral = -(bracket(std::cbrt(4.0)) - bracket(1.0)) / 3.0;
  EXPECT_NEAR(integral, 1.40325, 1e-5);
  const double work = pi * kGamma * sphere.radius * -s.break_overlap * integral;  // J
  const double sticking = std::sqrt(2.0 * work / sphere.mass);                    // m/s
  const double dt = 2.0e-8;  // s, about 1/5000 of the contact
  const auto impact = [&](double speed, bool& stuck) {
    contact_test::Sphere body = sphere;
    body.position = {0.0, 0.0, sphere.radius};  // touching the floor z = 0
    body.velocity = {0.0, 0.0, -speed};
    ContactHistory history;
    const Vec3 no_gravity{};
    bool touched = false;
    for (int step = 0; step < 100000; ++step) {
      contact_test::step_on_floor(parameters, body, history, no_gravity, dt);
      touched |= history.jkr_attached;
      if (touched && !history.jkr_attached) {
        stuck = false;
        return body.velocity.z;
      }
    }
    stuck = true;
    return 0.0;
  };
  bool stuck = false;
  impact(0.9 * sticking, stuck);
  EXPECT_TRUE(stuck) << "V_s = " << sticking << " m/s";
  const double rebound = impact(1.2 * sticking, stuck);
  EXPECT_FALSE(stuck);
  EXPECT_NEAR(rebound / (sticking * std::sqrt(1.44 - 1.0)), 1.0, 0.01) << "V_s = " << sticking;
}

}  // namespace
}  // namespace quarry
