// Linear spring-dashpot: contact time π / sqrt(kn/m* − (cn/2m*)²) and exact restitution of the
// damped linear oscillator (Cundall & Strack 1979; Ting et al. 1989).
#include "contact/normal_linear.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "contact/contact_law.h"
#include "contact/contact_test_bodies.h"

namespace quarry {
namespace {

using contact_test::Sphere;

class LinearSpringDashpot : public ::testing::TestWithParam<double> {};

// m* δ'' + cn δ' + kn δ = 0 from δ(0) = 0, δ'(0) = V: δ = (V/ωd) e^{−cn t/2m*} sin ωd t with
// ωd = sqrt(kn/m* − (cn/2m*)²); the contact ends at t = π/ωd with δ' = −V e^{−cn π/(2 m* ωd)},
// and cn = −2 β sqrt(kn m*) makes that ratio exactly e (damped harmonic oscillator).
TEST_P(LinearSpringDashpot, ContactTimeAndRestitutionOfTheDampedOscillator) {
  const double restitution = GetParam();
  InteractionSpec spec;
  spec.restitution = restitution;
  spec.static_friction = 0.5;
  spec.rolling_model = RollingModel::none;
  spec.normal_model = NormalModel::linear;
  spec.linear_stiffness = 1.0e4;  // N/m
  const InteractionParameters parameters =
      make_interaction(contact_test::glass_like_soft(), contact_test::glass_like_soft(), spec);

  Sphere i, j;
  i.radius = 0.01;  // m
  j.radius = 0.02;  // m
  i.mass = 0.01;    // kg
  j.mass = 0.03;    // kg
  i.position = Vec3{0.0, 0.0, 0.01};
  j.position = Vec3{0.0, 0.0, -0.02};
  i.velocity = Vec3{0.0, 0.0, -0.75};  // m/s; closing speed 1 m/s, zero total momentum
  j.velocity = Vec3{0.0, 0.0, 0.25};
  const double effective_mass = 0.01 * 0.03 / 0.04;  // kg
  const double damping =
      -2.0 * parameters.damping_ratio_beta * std::sqrt(1.0e4 * effective_mass);  // N·s/m, cn
  const double damped_frequency =
      std::sqrt(1.0e4 / effective_mass - std::pow(damping / (2.0 * effective_mass), 2));  // rad/s
  const double contact_time = std::numbers::pi / damped_frequency;                        // s

  const contact_test::CollisionRecord record =
      contact_test::collide(parameters, i, &j, contact_time / 200.0);
  EXPECT_NEAR(record.contact_duration, contact_time, 0.01 * contact_time);
  EXPECT_NEAR((i.velocity.z - j.velocity.z) / 1.0, restitution, 0.01 * restitution);
}

INSTANTIATE_TEST_SUITE_P(Restitutions, LinearSpringDashpot,
                         ::testing::Values(0.1, 0.3, 0.5, 0.7, 0.9, 1.0));

TEST(LinearSpringDashpot, TangentialStiffnessIsTheRatioTimesNormal) {
  InteractionSpec spec;
  spec.restitution = 1.0;
  spec.static_friction = 100.0;
  spec.rolling_model = RollingModel::none;
  spec.normal_model = NormalModel::linear;
  spec.linear_stiffness = 1.0e4;  // N/m
  spec.linear_tangential_ratio = 2.0 / 7.0;
  const MaterialProperties material{2500.0, 5.0e7, 0.25};
  const InteractionParameters parameters = make_interaction(material, material, spec);
  ContactKinematics kinematics;  // sphere on a wall, dragged along x for one step
  kinematics.normal = Vec3{0.0, 0.0, 1.0};
  kinematics.overlap = 1.0e-4;  // m
  kinematics.radius_i = 0.01;   // m
  kinematics.inv_mass_i = 1.0 / 0.01;     // 1/kg
  kinematics.velocity_i = Vec3{0.1, 0.0, 0.0};
  ContactHistory history;
  const ContactResult result = evaluate_contact(parameters, kinematics, history, 1.0e-4);
  // Fn = kn δ = 1e4 · 1e-4 = 1 N; Ft = −kt v dt = −(2/7 · 1e4) · 1e-5 = −0.0285714 N.
  EXPECT_NEAR(result.normal_force, 1.0, 1e-12);
  EXPECT_NEAR(result.force_i.x, -2.0 / 7.0 * 1.0e4 * 1.0e-5, 1e-14);
}

}  // namespace
}  // namespace quarry
