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
  const auto k = s.register_custom("charge", 1, 0.0, "C");
  const auto flow = s.register_custom("flow", 2, -1.0, "m/s");  // two components per particle
  for (int i = 0; i < 5; ++i) {
    s.add(static_cast<ParticleId>(i), 0, 0, {double(i), 0, 0}, {}, 0.001, 1000.0, 0.0);
    s.custom[k].values[i] = 10.0 * i;
    s.custom[flow].values[2 * i + 1] = 100.0 * i;
  }
  EXPECT_EQ(s.custom[flow].values[2], -1.0);  // a new particle's components start at `initial`
  const std::uint64_t epoch = s.layout_epoch;
  s.remove_flagged({0, 1, 0, 1, 0});
  EXPECT_GT(s.layout_epoch, epoch);
  ASSERT_EQ(s.size(), 3u);
  EXPECT_EQ(s.id[1], 2u);
  EXPECT_EQ(s.custom[k].values[2], 40.0);
  EXPECT_EQ(s.custom[flow].values.size(), 6u);
  EXPECT_EQ(s.custom[flow].values[5], 400.0);
  s.permute({2, 0, 1});
  EXPECT_EQ(s.id[0], 4u);
  EXPECT_EQ(s.position[1].x, 0.0);
  EXPECT_EQ(s.custom[flow].values[1], 400.0);  // particle id 4's second component moved with it
  EXPECT_EQ(s.custom[flow].values[3], 0.0);
  EXPECT_EQ(s.custom[k].values[0], 40.0);
}

// The removal moves the kept particles after the first removed one run by run; every pattern of
// runs (none removed, the first, the last, neighbours, all) must leave what one particle at a
// time would: the kept particles in order, every array and component with them.
TEST(ParticleStore, RemoveFlaggedMovesEveryRunOfKeptParticles) {
  const std::vector<std::vector<char>> patterns = {
      {0, 0, 0, 0, 0, 0, 0}, {1, 0, 0, 0, 0, 0, 0}, {0, 0, 0, 0, 0, 0, 1}, {0, 1, 1, 0, 0, 1, 0},
      {1, 1, 0, 1, 0, 1, 1}, {1, 1, 1, 1, 1, 1, 1}, {0, 0, 1, 0, 1, 0, 0}};
  for (const std::vector<char>& remove : patterns) {
    ParticleStore s;
    const auto flow = s.register_custom("flow", 3, 0.0, "m/s");
    s.enable_external_loads();
    for (int i = 0; i < 7; ++i) {
      s.add(static_cast<ParticleId>(100 + i), 0, 0, {double(i), 0, 0}, {0, double(i), 0}, 0.001,
            1000.0, 0.1 * i);
      s.external_force[i] = {0, 0, double(i)};
      for (int c = 0; c < 3; ++c) s.custom[flow].values[3 * i + c] = 10.0 * i + c;
    }
    s.remove_flagged(remove);
    std::size_t k = 0;
    for (int i = 0; i < 7; ++i) {
      if (remove[static_cast<std::size_t>(i)]) continue;
      ASSERT_LT(k, s.size());
      EXPECT_EQ(s.id[k], static_cast<ParticleId>(100 + i));
      EXPECT_EQ(s.position[k].x, double(i));
      EXPECT_EQ(s.velocity[k].y, double(i));
      EXPECT_EQ(s.creation_time[k], 0.1 * i);
      EXPECT_EQ(s.external_force[k].z, double(i));
      for (int c = 0; c < 3; ++c) EXPECT_EQ(s.custom[flow].values[3 * k + c], 10.0 * i + c);
      ++k;
    }
    EXPECT_EQ(s.size(), k);
    EXPECT_EQ(s.external_force.size(), k);
    EXPECT_EQ(s.custom[flow].values.size(), 3 * k);
  }
}

TEST(ParticleStore, RegisteringTwiceReturnsTheSameIndex) {
  ParticleStore s;
  s.add(1, 0, 0, {}, {}, 0.001, 1000.0, 0.0);
  const auto a = s.register_custom("heat", 1, 300.0, "K");
  EXPECT_EQ(s.register_custom("heat", 1, 0.0, "K"), a);
  EXPECT_EQ(s.custom[a].values[0], 300.0);  // the second call does not reset the values
  EXPECT_THROW(s.register_custom("heat", 3), std::invalid_argument);
  EXPECT_THROW(s.register_custom("none", 0), std::invalid_argument);
}

}  // namespace quarry
