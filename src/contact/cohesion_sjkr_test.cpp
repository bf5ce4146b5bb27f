// SJKR cohesion: contact area of the sphere–sphere lens and the sphere–wall cap against hand
// computation, and the force k·A pulling i towards j through the full contact law.
#include "contact/cohesion_sjkr.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "contact/contact_law.h"

namespace quarry {
namespace {

TEST(SjkrCohesion, SphereSphereLensAreaMatchesHandComputation) {
  // Ri = 0.01 m, Rj = 0.02 m, δ = 0.001 m → d = 0.029 m (LIGGGHTS sjkr lens formula):
  // 4 d² Ri² = 4 · 8.41e-4 · 1e-4 = 3.364e-7 m⁴;  d² − Rj² + Ri² = 8.41e-4 − 4e-4 + 1e-4
  // = 5.41e-4 m²,  squared 2.92681e-7 m⁴;  a² = (3.364e-7 − 2.92681e-7) / (4 · 8.41e-4)
  // = 4.3719e-8 / 3.364e-3 = 1.299614e-5 m²;  A = π a² = 4.082856e-5 m².
  EXPECT_NEAR(contact::sphere_sphere_contact_area(0.01, 0.02, 0.001), 4.082856e-5, 1e-11);
  // Symmetric in the two spheres.
  EXPECT_NEAR(contact::sphere_sphere_contact_area(0.02, 0.01, 0.001), 4.082856e-5, 1e-11);
  // Small overlap: a² → 2 R* δ (Hertz geometry), R* = 0.02/3 m, δ = 1e-9 m → 1.3333e-11 m²;
  // the factored form keeps full precision here where the textbook form cancels.
  EXPECT_NEAR(contact::sphere_sphere_contact_area(0.01, 0.02, 1.0e-9) / std::numbers::pi,
              2.0 * 0.02 / 3.0 * 1.0e-9, 1e-6 * 2.0 * 0.02 / 3.0 * 1.0e-9);
}

TEST(SjkrCohesion, SphereWallCapAreaMatchesHandComputation) {
  // A = π (2 Ri δ − δ²) = π (2e-5 − 1e-6) = π · 1.9e-5 = 5.969026e-5 m².
  EXPECT_NEAR(contact::sphere_wall_contact_area(0.01, 0.001), 5.969026e-5, 1e-11);
}

TEST(SjkrCohesion, ContactLawAddsAttractionKTimesArea) {
  InteractionSpec spec;
  spec.restitution = 1.0;
  spec.static_friction = 0.5;
  spec.rolling_model = RollingModel::none;
  spec.cohesion_energy_density = 2.0e5;  // J/m³
  const MaterialProperties material{2500.0, 5.0e7, 0.25};
  const InteractionParameters parameters = make_interaction(material, material, spec);

  ContactKinematics kinematics;  // at rest: only elastic and cohesive normal forces
  kinematics.normal = Vec3{0.0, 1.0, 0.0};
  kinematics.overlap = 0.001;  // m
  kinematics.radius_i = 0.01;  // m
  kinematics.radius_j = 0.02;  // m
  kinematics.inv_mass_i = 1.0 / 0.01;    // 1/kg
  kinematics.inv_mass_j = 1.0 / 0.08;    // 1/kg
  ContactHistory history;
  const ContactResult pair = evaluate_contact(parameters, kinematics, history, 1.0e-6);
  // Hertz elastic part with R* = 0.02/3 m, minus k A = 2e5 · 4.082856e-5 = 8.165713 N.
  const double hertz =
      4.0 / 3.0 * parameters.effective_youngs_modulus * std::sqrt(0.02 / 3.0 * 0.001) * 0.001;  // N
  EXPECT_NEAR(pair.normal_force, hertz - 8.165713, 1e-5);
  EXPECT_NEAR(pair.force_i.y, hertz - 8.165713, 1e-5);

  kinematics.radius_j = 0.0;  // the same sphere against a wall
  kinematics.inv_mass_j = 0.0;  // a wall
  const ContactResult wall = evaluate_contact(parameters, kinematics, history, 1.0e-6);
  // k A = 2e5 · 5.969026e-5 = 11.938052 N, Hertz with R* = Ri.
  const double wall_hertz =
      4.0 / 3.0 * parameters.effective_youngs_modulus * std::sqrt(0.01 * 0.001) * 0.001;  // N
  EXPECT_NEAR(wall.normal_force, wall_hertz - 11.938052, 1e-5);
}

}  // namespace
}  // namespace quarry
