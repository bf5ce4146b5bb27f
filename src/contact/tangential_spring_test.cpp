// Tangential spring with Coulomb cap: stick stiffness, the cap while sliding, consistent history
// after the cap, history rotation, and a sliding sphere reaching pure rolling at 5/7 v0.
#include "contact/tangential_spring.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "contact/contact_law.h"
#include "contact/contact_test_bodies.h"

namespace quarry {
namespace {

using contact_test::Sphere;

// A sphere pressed into the floor by a fixed overlap and dragged sideways at constant speed.
struct DraggedSphere {
  ContactKinematics kinematics;
  InteractionParameters parameters;
};

DraggedSphere dragged_sphere(double restitution, double friction, double speed) {
  InteractionSpec spec;
  spec.restitution = restitution;
  spec.static_friction = friction;
  spec.rolling_model = RollingModel::none;
  DraggedSphere dragged;
  dragged.parameters =
      make_interaction(contact_test::glass_like_soft(), contact_test::glass_like_soft(), spec);
  dragged.kinematics.normal = Vec3{0.0, 0.0, 1.0};
  dragged.kinematics.overlap = 1.0e-5;  // m
  dragged.kinematics.radius_i = 0.01;   // m
  dragged.kinematics.inv_mass_i = 1.0 / 0.01;     // 1/kg
  dragged.kinematics.velocity_i = Vec3{speed, 0.0, 0.0};
  return dragged;
}

TEST(TangentialSpring, SticksWithMindlinStiffnessThenSlidesAtTheCoulombLimit) {
  const double speed = 0.01;                                // m/s
  const double dt = 1.0e-6;                                 // s
  DraggedSphere dragged = dragged_sphere(1.0, 0.3, speed);  // e = 1: no dashpot
  const InteractionParameters& parameters = dragged.parameters;
  // Hertz: Fn = 4/3 E* sqrt(R δ) δ; Mindlin: St = 8 G* sqrt(R δ) (EDEM guide).
  const double contact_radius = std::sqrt(0.01 * 1.0e-5);  // m
  const double normal_force =
      4.0 / 3.0 * parameters.effective_youngs_modulus * contact_radius * 1.0e-5;  // N
  const double tangential_stiffness =
      8.0 * parameters.effective_shear_modulus * contact_radius;  // N/m
  const double sliding_force = 0.3 * normal_force;                // N, Coulomb μs Fn

  ContactHistory history;
  int steps_to_slide = 0;
  for (int step = 1; step <= 100000; ++step) {
    const ContactResult result = evaluate_contact(parameters, dragged.kinematics, history, dt);
    EXPECT_NEAR(result.normal_force, normal_force, 1e-12 * normal_force);
    const double stick_force = tangential_stiffness * speed * dt * step;  // N, −St δt
    if (stick_force < sliding_force) {
      // Stick: Ft = −St δt with δt = v t (Cundall & Strack 1979).
      EXPECT_NEAR(result.force_i.x, -stick_force, 1e-9 * sliding_force);
    } else {
      // Slide: |Ft| = μs |Fn|, opposing the motion.
      EXPECT_NEAR(result.force_i.x, -sliding_force, 1e-12 * sliding_force);
      if (steps_to_slide == 0) steps_to_slide = step;
      if (step > steps_to_slide + 100) break;
    }
    EXPECT_EQ(result.force_i.y, 0.0);
  }
  ASSERT_GT(steps_to_slide, 10);
  // History consistent with the capped force: δt = μs Fn / St, so reversing the drag unloads
  // the spring elastically from the cap: Ft = −μs Fn + St v dt after one reversed step.
  EXPECT_NEAR(history.tangential_displacement.x, sliding_force / tangential_stiffness,
              1e-12 * sliding_force / tangential_stiffness);
  dragged.kinematics.velocity_i.x = -speed;
  const ContactResult reversed = evaluate_contact(parameters, dragged.kinematics, history, dt);
  EXPECT_NEAR(reversed.force_i.x, -sliding_force + tangential_stiffness * speed * dt,
              1e-9 * sliding_force);
}

TEST(TangentialSpring, DampedSlidingForceStaysAtTheCoulombLimit) {
  DraggedSphere dragged = dragged_sphere(0.4, 0.5, 0.05);
  ContactHistory history;
  ContactResult result;
  for (int step = 0; step < 20000; ++step) {
    result = evaluate_contact(dragged.parameters, dragged.kinematics, history, 1.0e-6);
  }
  // |Ft| = μs |Fn| with Fn the elastic + dashpot normal force (here vn = 0, so elastic).
  EXPECT_NEAR(std::hypot(result.force_i.x, result.force_i.y), 0.5 * result.normal_force,
              1e-12 * result.normal_force);
  // The history makes spring + dashpot equal the capped force: −St δt − ct vt = Ft.
  const double contact_radius = std::sqrt(0.01 * 1.0e-5);  // m
  const double tangential_stiffness =
      8.0 * dragged.parameters.effective_shear_modulus * contact_radius;  // N/m
  const double tangential_damping = contact::hertz_mindlin_damping_coefficient(
      dragged.parameters.damping_ratio_beta, tangential_stiffness, 0.01);  // N·s/m
  EXPECT_NEAR(-tangential_stiffness * history.tangential_displacement.x - tangential_damping * 0.05,
              result.force_i.x, 1e-9 * result.normal_force);
}

TEST(TangentialSpring, RotationIntoTheNewTangentPlaneKeepsTheMagnitude) {
  const Vec3 stored{3.0e-6, 4.0e-6, 0.0};  // m, magnitude 5e-6, tangent to n = z
  const double tilt = 0.3;                 // rad, the pair turned about the y axis
  const Vec3 normal{std::sin(tilt), 0.0, std::cos(tilt)};
  const Vec3 rotated = contact::rotate_into_tangent_plane(stored, normal);
  EXPECT_NEAR(norm(rotated), 5.0e-6, 1e-20);
  EXPECT_NEAR(dot(rotated, normal), 0.0, 1e-20);
  // Direction kept as far as the plane allows: the projection's direction.
  const Vec3 projection = stored - dot(stored, normal) * normal;
  EXPECT_NEAR(dot(normalized(rotated), normalized(projection)), 1.0, 1e-14);

  // Through the full law: no motion, so the force is the rotated spring −St δt.
  DraggedSphere dragged = dragged_sphere(1.0, 10.0, 0.0);
  dragged.kinematics.normal = normal;
  ContactHistory history{stored, Vec3{}};
  const ContactResult result =
      evaluate_contact(dragged.parameters, dragged.kinematics, history, 1.0e-6);
  EXPECT_NEAR(norm(history.tangential_displacement), 5.0e-6, 1e-20);
  const double tangential_stiffness =
      8.0 * dragged.parameters.effective_shear_modulus * std::sqrt(0.01 * 1.0e-5);  // N/m
  const Vec3 tangential_force = result.force_i - result.normal_force * normal;      // N
  EXPECT_NEAR(norm(tangential_force + tangential_stiffness * rotated), 0.0,
              1e-12 * tangential_stiffness * 5.0e-6);
}

// A sphere launched sliding without spin on a floor with friction slides, decelerating at μ g,
// until its contact point sticks at t = 2 v0 / (7 μ g); from then on it rolls at v = 5/7 v0
// (angular momentum about the contact line is conserved: m v0 R = m v R + 2/5 m R² v/R).
// Classic result, e.g. Brilliantov & Pöschel 2004, Kinetic Theory of Granular Gases.
TEST(TangentialSpring, SlidingSphereReachesPureRollingAtFiveSevenths) {
  InteractionSpec spec;
  spec.restitution = 0.5;
  spec.static_friction = 0.5;
  spec.rolling_model = RollingModel::none;
  const InteractionParameters parameters =
      make_interaction(contact_test::glass_like_soft(), contact_test::glass_like_soft(), spec);
  const Vec3 gravity{0.0, 0.0, -9.81};  // m/s²
  Sphere sphere;
  sphere.radius = 0.01;  // m
  sphere.mass = contact_test::sphere_mass(sphere.radius, contact_test::glass_like_soft().density);
  // Start at rest on the floor at the Hertz equilibrium overlap δ0 = (m g / (4/3 E*
  // sqrt(R)))^{2/3}.
  const double rest_overlap =
      std::pow(sphere.mass * 9.81 /
                   (4.0 / 3.0 * parameters.effective_youngs_modulus * std::sqrt(sphere.radius)),
               2.0 / 3.0);  // m
  sphere.position = Vec3{0.0, 0.0, sphere.radius - rest_overlap};
  sphere.force = Vec3{0.0, 0.0, sphere.mass * 9.81};
  const double launch_speed = 1.0;  // m/s
  sphere.velocity = Vec3{launch_speed, 0.0, 0.0};

  const double dt = 1.0e-5;  // s; ~300 steps per tangential and normal oscillation period
  const double sliding_time = 2.0 * launch_speed / (7.0 * 0.5 * 9.81);  // s
  ContactHistory history;
  double time = 0.0;  // s
  bool checked_half_way = false;
  while (time < 3.0 * sliding_time) {
    contact_test::step_on_floor(parameters, sphere, history, gravity, dt);
    time += dt;
    if (!checked_half_way && time >= 0.5 * sliding_time) {
      // While sliding: v = v0 − μ g t = 6/7 v0 half-way.
      EXPECT_NEAR(sphere.velocity.x, 6.0 / 7.0 * launch_speed, 0.01 * launch_speed);
      checked_half_way = true;
    }
  }
  EXPECT_NEAR(sphere.velocity.x, 5.0 / 7.0 * launch_speed, 0.01 * 5.0 / 7.0 * launch_speed);
  // Pure rolling: the contact point is at rest, v = ω_y (R − δ).
  EXPECT_NEAR(sphere.angular_velocity.y * (sphere.radius - rest_overlap), sphere.velocity.x,
              1e-3 * launch_speed);
}

}  // namespace
}  // namespace quarry
