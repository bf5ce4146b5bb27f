// Rolling resistance: the constant directional torque decelerates a rolling sphere at the rate
// τ = μr Fn R implies; the EPSD spring loads with kr = 2.25 kn μr² R*² and caps at μr R* Fn.
#include "contact/rolling_resistance.h"

#include <gtest/gtest.h>

#include <cmath>

#include "contact/contact_law.h"
#include "contact/contact_test_bodies.h"

namespace quarry {
namespace {

using contact_test::Sphere;

InteractionParameters rolling_parameters(RollingModel model, double rolling_friction,
                                         double static_friction) {
  InteractionSpec spec;
  spec.restitution = 0.5;
  spec.static_friction = static_friction;
  spec.rolling_friction = rolling_friction;
  spec.rolling_model = model;
  return make_interaction(contact_test::glass_like_soft(), contact_test::glass_like_soft(), spec);
}

TEST(ConstantDirectionalTorque, OpposesOwnSpinAndVanishesWithoutSpin) {
  // τ = −μr |Fn| R ω̂ = −0.1 · 20 N · 0.01 m · (0, 0.6, −0.8) = (0, −0.012, 0.016) N·m.
  const Vec3 torque =
      contact::constant_directional_rolling_torque(0.1, 20.0, 0.01, Vec3{0.0, 3.0, -4.0});
  EXPECT_NEAR(torque.x, 0.0, 1e-18);
  EXPECT_NEAR(torque.y, -0.012, 1e-15);
  EXPECT_NEAR(torque.z, 0.016, 1e-15);
  EXPECT_EQ(contact::constant_directional_rolling_torque(0.1, 20.0, 0.01, Vec3{}), Vec3{});
}

// Rolling without slip on a floor under a resisting torque τr = μr Fn R with Fn = m g:
//   m dv/dt = Ft,  I dω/dt = −R Ft − τr,  v = ω R  ⇒  dv/dt = −τr R / (I + m R²) = −5/7 μr g
// for a solid sphere (I = 2/5 m R²). Equations of rigid-body rolling, e.g. Ai et al. 2011 §2.
TEST(ConstantDirectionalTorque, DeceleratesARollingSphereAtFiveSeventhsMuRG) {
  const double rolling_friction = 0.05;  // 1
  const InteractionParameters parameters =
      rolling_parameters(RollingModel::constant_torque, rolling_friction, 0.5);
  const Vec3 gravity{0.0, 0.0, -9.81};  // m/s²
  Sphere sphere;
  sphere.radius = 0.01;  // m
  sphere.mass = contact_test::sphere_mass(sphere.radius, contact_test::glass_like_soft().density);
  const double rest_overlap =
      std::pow(sphere.mass * 9.81 /
                   (4.0 / 3.0 * parameters.effective_youngs_modulus * std::sqrt(sphere.radius)),
               2.0 / 3.0);  // m, Hertz equilibrium under gravity
  sphere.position = Vec3{0.0, 0.0, sphere.radius - rest_overlap};
  sphere.force = Vec3{0.0, 0.0, sphere.mass * 9.81};
  sphere.velocity = Vec3{1.0, 0.0, 0.0};
  sphere.angular_velocity = Vec3{0.0, 1.0 / (sphere.radius - rest_overlap), 0.0};  // rolling

  // Least-squares slope of v(t) over 0.02 s … 0.3 s (the start has a short tangential transient).
  const double dt = 1.0e-5;  // s
  ContactHistory history;
  double sum_t = 0.0, sum_v = 0.0, sum_tt = 0.0, sum_tv = 0.0;
  int samples = 0;
  for (int step = 1; step <= 30000; ++step) {
    contact_test::step_on_floor(parameters, sphere, history, gravity, dt);
    const double time = step * dt;  // s
    if (time >= 0.02) {
      sum_t += time;
      sum_v += sphere.velocity.x;
      sum_tt += time * time;
      sum_tv += time * sphere.velocity.x;
      ++samples;
    }
  }
  const double deceleration =
      -(samples * sum_tv - sum_t * sum_v) / (samples * sum_tt - sum_t * sum_t);  // m/s²
  const double expected = 5.0 / 7.0 * rolling_friction * 9.81;                   // m/s²
  EXPECT_NEAR(deceleration, expected, 0.01 * expected);
  // Still rolling (the friction needed, 2/7 μr m g, is far below μs m g).
  EXPECT_NEAR(sphere.angular_velocity.y * (sphere.radius - rest_overlap), sphere.velocity.x, 1e-3);
}

TEST(EpsdRollingTorque, LoadsWithRollingStiffnessAndCapsAtMuRRFn) {
  const double rolling_friction = 0.2;  // 1
  // μs = 0 isolates the rolling torque: the tangential force (and its torque) is capped at 0.
  const InteractionParameters parameters =
      rolling_parameters(RollingModel::epsd, rolling_friction, 0.0);
  ContactKinematics kinematics;  // a sphere on the floor, spinning in place about y
  kinematics.normal = Vec3{0.0, 0.0, 1.0};
  kinematics.overlap = 1.0e-5;  // m
  kinematics.radius_i = 0.01;   // m
  kinematics.inv_mass_i = 1.0 / 0.01;     // 1/kg
  const double spin = 2.0;      // rad/s
  kinematics.angular_velocity_i = Vec3{0.0, spin, 0.0};
  const double dt = 1.0e-5;  // s

  // Hertz: Sn = 2 E* sqrt(R δ), Fn = 4/3 E* sqrt(R δ) δ (vn = 0); wall: R* = R.
  const double contact_radius = std::sqrt(0.01 * 1.0e-5);  // m
  const double normal_stiffness =
      2.0 * parameters.effective_youngs_modulus * contact_radius;     // N/m
  const double normal_force = normal_stiffness * 1.0e-5 * 2.0 / 3.0;  // N
  // kr = 2.25 kn μr² R*² (Ai et al. 2011 model C); limit μr R* Fn.
  const double rolling_stiffness =
      2.25 * normal_stiffness * rolling_friction * rolling_friction * 0.01 * 0.01;  // N·m/rad
  const double torque_limit = rolling_friction * 0.01 * normal_force;               // N·m

  ContactHistory history;
  const ContactResult first = evaluate_contact(parameters, kinematics, history, dt);
  EXPECT_NEAR(first.torque_i.y, -rolling_stiffness * spin * dt, 1e-12 * torque_limit);
  EXPECT_EQ(first.force_i.x, 0.0);
  ContactResult result = first;
  const int steps_to_cap = static_cast<int>(torque_limit / (rolling_stiffness * spin * dt));
  ASSERT_GT(steps_to_cap, 10);
  for (int step = 2; step <= steps_to_cap / 2; ++step) {
    result = evaluate_contact(parameters, kinematics, history, dt);
  }
  // Elastic phase: Mr = −kr θ with θ = ω t.
  EXPECT_NEAR(result.torque_i.y, -rolling_stiffness * spin * dt * (steps_to_cap / 2),
              1e-9 * torque_limit);
  for (int step = 0; step < steps_to_cap; ++step) {
    result = evaluate_contact(parameters, kinematics, history, dt);
  }
  // Fully mobilised: |Mr| = μr R* Fn, opposing the rotation.
  EXPECT_NEAR(result.torque_i.y, -torque_limit, 1e-12 * torque_limit);
  EXPECT_NEAR(norm(history.rolling_torque), torque_limit, 1e-12 * torque_limit);

  // A spin about the normal (twist) is not rolling and adds nothing.
  ContactHistory twist_history;
  kinematics.angular_velocity_i = Vec3{0.0, 0.0, spin};
  const ContactResult twist = evaluate_contact(parameters, kinematics, twist_history, dt);
  EXPECT_EQ(norm(twist.torque_i), 0.0);
}

TEST(EpsdRollingTorque, SphereSpherePairGetsEqualAndOppositeTorques) {
  const InteractionParameters parameters = rolling_parameters(RollingModel::epsd, 0.3, 0.0);
  ContactKinematics kinematics;
  kinematics.normal = Vec3{1.0, 0.0, 0.0};
  kinematics.overlap = 2.0e-5;  // m
  kinematics.radius_i = 0.01;   // m
  kinematics.radius_j = 0.02;   // m
  kinematics.inv_mass_i = 1.0 / 0.01;     // 1/kg
  kinematics.inv_mass_j = 1.0 / 0.08;     // 1/kg
  kinematics.angular_velocity_i = Vec3{0.0, 1.0, 0.5};
  kinematics.angular_velocity_j = Vec3{0.3, -1.0, 0.0};
  ContactHistory history;
  const ContactResult result = evaluate_contact(parameters, kinematics, history, 1.0e-5);
  EXPECT_EQ(result.torque_i, -result.torque_j);
  // Δθr = (ωi − ωj) dt without its normal (x) part: (0, 2, 0.5) · dt, so Mr ∥ −(0, 2, 0.5).
  EXPECT_NEAR(result.torque_i.x, 0.0, 1e-30);
  EXPECT_NEAR(result.torque_i.z / result.torque_i.y, 0.25, 1e-12);
  EXPECT_LT(result.torque_i.y, 0.0);
}

}  // namespace
}  // namespace quarry
