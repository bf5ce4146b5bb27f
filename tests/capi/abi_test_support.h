// Helpers of the C ABI tests: the last-error text, and a small simulation built through the
// calls alone (no deck).
#pragma once

#include <gtest/gtest.h>

#include <string>

#include "quarry/quarry.h"

namespace quarry_test {

inline std::string error_of(quarry_sim sim) {
  char text[4096];
  quarry_last_error(sim, text, sizeof text, nullptr);
  return text;
}

// An empty simulation started with one material "ore" (2500 kg/m³, 10 MPa) and one particle type
// "grain" of `radius` (m) in the domain [−1, 1]³ m, dt = 1e-5 s, gravity along −z.
inline quarry_sim started_simulation(double radius = 1e-3) {
  quarry_open_info info = QUARRY_OPEN_INFO_INIT;
  quarry_sim sim{};
  EXPECT_EQ(quarry_open(&info, &sim), QUARRY_OK) << error_of(QUARRY_NO_SIM);
  quarry_settings settings = quarry_default_settings();
  for (int k = 0; k < 3; ++k) settings.domain_min[k] = -1.0, settings.domain_max[k] = 1.0;
  settings.time_step = 1e-5;
  settings.impact_speed = 0.1;
  EXPECT_EQ(quarry_set_settings(sim, &settings), QUARRY_OK) << error_of(sim);
  quarry_material material{sizeof(quarry_material), "ore", 2500.0, 1e7, 0.3};
  EXPECT_EQ(quarry_add_material(sim, &material, nullptr), QUARRY_OK) << error_of(sim);
  quarry_interaction interaction{sizeof(quarry_interaction), "ore", "ore", 0.5, 0.5, 0.0, QUARRY_ROLLING_NONE, 0.0};
  EXPECT_EQ(quarry_add_interaction(sim, &interaction), QUARRY_OK) << error_of(sim);
  quarry_particle_type type{sizeof(quarry_particle_type), "grain", "ore", radius, 0.0};
  EXPECT_EQ(quarry_add_particle_type(sim, &type, nullptr), QUARRY_OK) << error_of(sim);
  EXPECT_EQ(quarry_start(sim), QUARRY_OK) << error_of(sim);
  return sim;
}

// Adds `count` particles of type 0 at `positions` (3 × count, m); fails the test on an error.
inline void add_particles(quarry_sim sim, const double* positions, std::uint64_t count) {
  quarry_new_particles add{};
  add.struct_size = sizeof add;
  add.count = count;
  add.position = positions;
  EXPECT_EQ(quarry_add_particles(sim, &add), QUARRY_OK) << error_of(sim);
}

}  // namespace quarry_test
