// Tests for ParticleStore: mass/inertia of a sphere, order-preserving removal, permutation.
#include "core/particle_store.h"

#include <gtest/gtest.h>

#include <numbers>

namespace quarry {

TEST(ParticleStore, AddComputesSphereMassAndInertia) {
  ParticleStore s;
  s.add(7, 0, 0, {1, 2, 3}, {0, 0, -1}, 0.01, 2500.0, 0.5);
  const double m = 2500.0 * 4.0 / 3.0 * std::numbers::pi * 1e-6;  // ρ·4/3·π·R³ (kg)
  EXPECT_NEAR(s.mass(0), m, 1e-15);
  EXPECT_NEAR(1.0 / s.inv_inertia(0), 0.4 * m * 1e-4, 1e-18);  // I = 2/5 m R²
  EXPECT_EQ(s.id[0], 7u);
}

TEST(ParticleStore, RemoveFlaggedKeepsOrderAndCustomProperties) {
  ParticleStore s;
  const auto k = s.register_custom("charge", 0.0);
  for (int i = 0; i < 5; ++i) {
    s.add(static_cast<ParticleId>(i), 0, 0, {double(i), 0, 0}, {}, 0.001, 1000.0, 0.0);
    s.custom_values[k][i] = 10.0 * i;
  }
  s.remove_flagged({0, 1, 0, 1, 0});
  ASSERT_EQ(s.size(), 3u);
  EXPECT_EQ(s.id[1], 2u);
  EXPECT_EQ(s.custom_values[k][2], 40.0);
  s.permute({2, 0, 1});
  EXPECT_EQ(s.id[0], 4u);
  EXPECT_EQ(s.position[1].x, 0.0);
}

}  // namespace quarry
