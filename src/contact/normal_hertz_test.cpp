// Hertz normal law: formulas, a head-on elastic impact against Hertz theory (Johnson 1985 §11.1)
// and the restitution reproduced by the Tsuji/EDEM dashpot, sphere–sphere and sphere–wall.
#include "contact/normal_hertz.h"

#include <gtest/gtest.h>

#include <cmath>

#include "contact/contact_law.h"
#include "contact/contact_test_bodies.h"

namespace quarry {
namespace {

using contact_test::collide;
using contact_test::Sphere;
using contact_test::sphere_mass;

TEST(HertzNormalSpring, MatchesHandComputedForceAndStiffness) {
  // E* = 1e9 Pa, R* = 0.004 m, δ = 1e-5 m: sqrt(R* δ) = sqrt(4e-8) = 2e-4 m;
  // Fn = 4/3 · 1e9 · 2e-4 · 1e-5 = 2.666666… N; Sn = 2 · 1e9 · 2e-4 = 4e5 N/m (Johnson eq. 4.23).
  const contact::NormalSpring spring = contact::hertz_normal_spring(1.0e9, 0.004, 1.0e-5);
  EXPECT_NEAR(spring.elastic_force, 8.0 / 3.0, 1e-12);
  EXPECT_NEAR(spring.stiffness, 4.0e5, 1e-7);
  // St = 8 G* sqrt(R* δ) = 8 · 5e8 · 2e-4 = 8e5 N/m (Mindlin & Deresiewicz 1953).
  EXPECT_NEAR(contact::mindlin_tangential_stiffness(5.0e8, 0.004, 1.0e-5), 8.0e5, 1e-7);
  // c = −2 sqrt(5/6) β sqrt(S m*): β = −0.5, S = 4e5 N/m, m* = 0.1 kg → sqrt(S m*) = 200,
  // c = sqrt(5/6) · 200 = 182.574… N·s/m (EDEM guide).
  EXPECT_NEAR(contact::hertz_mindlin_damping_coefficient(-0.5, 4.0e5, 0.1),
              std::sqrt(5.0 / 6.0) * 200.0, 1e-10);
}

InteractionParameters hertz_parameters(double restitution) {
  InteractionSpec spec;
  spec.restitution = restitution;
  spec.static_friction = 0.5;
  spec.rolling_model = RollingModel::none;
  return make_interaction(contact_test::glass_like_soft(), contact_test::glass_like_soft(), spec);
}

// Two identical spheres approaching head-on along x, just touching at t = 0.
struct HeadOn {
  Sphere i, j;
  double relative_speed;  // m/s
};

HeadOn head_on(double radius_i, double radius_j, double relative_speed) {
  const double density = contact_test::glass_like_soft().density;  // kg/m³
  HeadOn pair;
  pair.relative_speed = relative_speed;
  pair.i.radius = radius_i;
  pair.j.radius = radius_j;
  pair.i.mass = sphere_mass(radius_i, density);
  pair.j.mass = sphere_mass(radius_j, density);
  pair.i.position = Vec3{radius_i, 0.0, 0.0};
  pair.j.position = Vec3{-radius_j, 0.0, 0.0};
  // Zero total momentum, closing speed relative_speed.
  const double total_mass = pair.i.mass + pair.j.mass;  // kg
  pair.i.velocity = Vec3{-relative_speed * pair.j.mass / total_mass, 0.0, 0.0};
  pair.j.velocity = Vec3{relative_speed * pair.i.mass / total_mass, 0.0, 0.0};
  return pair;
}

TEST(HertzImpact, ElasticHeadOnMatchesHertzTheory) {
  const InteractionParameters parameters = hertz_parameters(1.0);
  ASSERT_EQ(parameters.damping_ratio_beta, 0.0);  // e = 1 → β = 0 exactly, no dashpot
  const double radius = 0.01;                     // m
  HeadOn pair = head_on(radius, radius, 2.0);
  const double effective_mass = pair.i.mass * pair.j.mass / (pair.i.mass + pair.j.mass);  // kg
  const double effective_radius = 0.5 * radius;                                           // m
  const double youngs = parameters.effective_youngs_modulus;                              // Pa
  const double speed = pair.relative_speed;                                               // m/s

  // Johnson 1985 §11.1, eqs. 11.21–11.24: δmax = (15 m* V² / (16 E* sqrt(R*)))^{2/5},
  // P0 = 4/3 E* sqrt(R*) δmax^{3/2}, T = 2 (δmax/V) ∫0¹ dx / sqrt(1 − x^{5/2}), and the
  // integral is (2/5) B(2/5, 1/2) = (2/5) Γ(2/5) Γ(1/2) / Γ(9/10) = 1.4716…, so T = 2.943 δmax/V
  // = 2.868 (m*² / (R* E*² V))^{1/5}.
  const double peak_overlap = std::pow(
      15.0 * effective_mass * speed * speed / (16.0 * youngs * std::sqrt(effective_radius)), 0.4);
  const double peak_force =
      4.0 / 3.0 * youngs * std::sqrt(effective_radius) * std::pow(peak_overlap, 1.5);
  const double duration_integral =
      0.4 * std::tgamma(0.4) * std::tgamma(0.5) / std::tgamma(0.9);            // 1
  const double contact_time = 2.0 * duration_integral * peak_overlap / speed;  // s
  EXPECT_NEAR(contact_time,
              2.868 * std::pow(effective_mass * effective_mass /
                                   (effective_radius * youngs * youngs * speed),
                               0.2),
              1e-3 * contact_time);

  const double dt = contact_time / 200.0;  // s: 200 steps per contact (≥ 50 asked)
  const double momentum_before = pair.i.mass * pair.i.velocity.x + pair.j.mass * pair.j.velocity.x;
  const double energy_before =
      0.5 * pair.i.mass * norm2(pair.i.velocity) + 0.5 * pair.j.mass * norm2(pair.j.velocity);  // J
  const contact_test::CollisionRecord record = collide(parameters, pair.i, &pair.j, dt);

  EXPECT_GE(record.steps_in_contact, 50);
  EXPECT_NEAR(record.contact_duration, contact_time, 0.01 * contact_time);
  EXPECT_NEAR(record.peak_overlap, peak_overlap, 0.01 * peak_overlap);
  EXPECT_NEAR(record.peak_normal_force, peak_force, 0.01 * peak_force);
  // Equal and opposite forces: momentum is conserved to round-off (relative to m V).
  const double momentum_after = pair.i.mass * pair.i.velocity.x + pair.j.mass * pair.j.velocity.x;
  EXPECT_NEAR(momentum_after, momentum_before, 1e-12 * pair.i.mass * speed);
  // A conservative elastic contact returns the kinetic energy.
  const double energy_after =
      0.5 * pair.i.mass * norm2(pair.i.velocity) + 0.5 * pair.j.mass * norm2(pair.j.velocity);  // J
  EXPECT_NEAR(energy_after / energy_before, 1.0, 1e-3);
  // No tangential motion was created in a central impact.
  EXPECT_EQ(norm2(pair.i.angular_velocity), 0.0);
}

// Contact duration of a Hertz contact at closing speed V (s), Johnson eq. 11.24 as above.
double hertz_contact_time_for_test(double effective_mass, double effective_radius, double youngs,
                                   double speed) {
  return 2.868 *
         std::pow(effective_mass * effective_mass / (effective_radius * youngs * youngs * speed),
                  0.2);
}

class HertzRestitution : public ::testing::TestWithParam<double> {};

// The dashpot −2 sqrt(5/6) β sqrt(Sn m*) v with β = ln e / sqrt(ln² e + π²) is built to give
// a rebound ratio e independent of the impact speed (Tsuji et al. 1992; EDEM guide), provided
// the attractive end of the contact is not clipped.
TEST_P(HertzRestitution, SphereSphereReboundRatioIsTheInputRestitution) {
  const double restitution = GetParam();
  const InteractionParameters parameters = hertz_parameters(restitution);
  HeadOn pair = head_on(0.01, 0.015, 1.5);  // unequal sizes exercise R* and m*
  const double effective_mass = pair.i.mass * pair.j.mass / (pair.i.mass + pair.j.mass);
  const double dt =
      hertz_contact_time_for_test(effective_mass, 0.006, parameters.effective_youngs_modulus, 1.5) /
      200.0;  // s; R* = 0.01 · 0.015 / 0.025 = 0.006 m
  const contact_test::CollisionRecord record = collide(parameters, pair.i, &pair.j, dt);
  ASSERT_GT(record.steps_in_contact, 50);
  const double rebound_speed = pair.i.velocity.x - pair.j.velocity.x;  // m/s, separating > 0
  EXPECT_NEAR(rebound_speed / pair.relative_speed, restitution, 0.01 * restitution);
}

TEST_P(HertzRestitution, SphereWallReboundRatioIsTheInputRestitution) {
  const double restitution = GetParam();
  const InteractionParameters parameters = hertz_parameters(restitution);
  Sphere sphere;
  sphere.radius = 0.01;  // m
  sphere.mass = sphere_mass(sphere.radius, contact_test::glass_like_soft().density);
  sphere.position = Vec3{0.0, 0.0, sphere.radius};
  const double impact_speed = 1.5;  // m/s
  sphere.velocity = Vec3{0.0, 0.0, -impact_speed};
  const double dt =
      hertz_contact_time_for_test(sphere.mass, sphere.radius, parameters.effective_youngs_modulus,
                                  impact_speed) /
      200.0;  // s; wall: m* = m, R* = R
  const contact_test::CollisionRecord record = collide(parameters, sphere, nullptr, dt);
  ASSERT_GT(record.steps_in_contact, 50);
  EXPECT_NEAR(sphere.velocity.z / impact_speed, restitution, 0.01 * restitution);
  // Without clipping the last part of a damped contact pulls (EDEM's choice, DESIGN §4).
  if (restitution < 0.9) {
    EXPECT_LT(record.least_normal_force, 0.0);
  }
}

INSTANTIATE_TEST_SUITE_P(Restitutions, HertzRestitution,
                         ::testing::Values(0.1, 0.3, 0.5, 0.7, 0.9));

TEST(HertzRestitution, ClippingRemovesTheAttractiveEndOfTheContact) {
  InteractionParameters parameters = hertz_parameters(0.3);
  parameters.clip_attraction = true;
  Sphere sphere;
  sphere.radius = 0.01;  // m
  sphere.mass = sphere_mass(sphere.radius, contact_test::glass_like_soft().density);
  sphere.position = Vec3{0.0, 0.0, sphere.radius};
  sphere.velocity = Vec3{0.0, 0.0, -1.5};
  const double dt = hertz_contact_time_for_test(sphere.mass, sphere.radius,
                                                parameters.effective_youngs_modulus, 1.5) /
                    200.0;
  const contact_test::CollisionRecord record = collide(parameters, sphere, nullptr, dt);
  EXPECT_EQ(record.least_normal_force, 0.0);
  // Removing the pull lets the sphere leave faster than the unclipped law's e (the known
  // drawback of clipping, e.g. Schwager & Pöschel 2007 on the dissipative Hertz contact).
  EXPECT_GT(sphere.velocity.z / 1.5, 0.3 * 1.01);
}

}  // namespace
}  // namespace quarry
