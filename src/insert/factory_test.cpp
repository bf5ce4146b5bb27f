// Tests for Factory: count and mass targets met (mass within one particle mass), no overlaps
// (brute force) among new particles and with existing ones, the mass-rate schedule, shortfall in
// a region too small, catching up once space frees, surfaces, determinism, checkpoint restart.
#include "insert/factory.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace quarry {

namespace {

constexpr double kDensity = 2600.0;  // kg/m³

ParticleTypeInfo uniform_type(double min_radius, double max_radius) {
  ParticleTypeInfo type;
  type.type_index = 3;
  type.material_index = 1;
  type.density = kDensity;
  type.size.kind = SizeDistributionKind::uniform;
  type.size.min_radius = min_radius;
  type.size.max_radius = max_radius;
  return type;
}

ParticleTypeInfo discrete_type() {
  ParticleTypeInfo type;
  type.density = kDensity;
  type.size.kind = SizeDistributionKind::discrete;
  type.size.discrete_radii = {Located<double>(2e-3), Located<double>(3e-3), Located<double>(5e-3)};
  type.size.discrete_mass_fractions = {Located<double>(0.3), Located<double>(0.3),
                                       Located<double>(0.4)};
  return type;
}

FactorySpec box_factory(const Vec3& lo, const Vec3& hi) {
  FactorySpec spec;
  spec.name = std::string("feed");
  spec.region.kind = RegionKind::box;
  spec.region.min = lo;
  spec.region.max = hi;
  return spec;
}

double sphere_mass(double radius) {
  return kDensity * 4.0 / 3.0 * std::numbers::pi * radius * radius * radius;
}

// Brute force over all pairs: the largest overlap (m) relative to nothing; 0 if none overlap.
double largest_overlap(const ParticleStore& p) {
  double largest = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i)
    for (std::size_t j = i + 1; j < p.size(); ++j)
      largest = std::max(largest, p.radius[i] + p.radius[j] - norm(p.position[i] - p.position[j]));
  return largest;
}

double total_mass(const ParticleStore& p, std::size_t from = 0) {
  double sum = 0.0;
  for (std::size_t i = from; i < p.size(); ++i) sum += p.mass(i);
  return sum;
}

const SurfaceOverlapQuery kNoSurfaces;

}  // namespace

TEST(Factory, CountTargetInsertsEverythingAtStartWithoutOverlap) {
  FactorySpec spec = box_factory({0, 0, 0}, {0.1, 0.1, 0.1});
  spec.target_count = Located<std::int64_t>(600);
  spec.start_time = 0.2;
  spec.initial_velocity = Vec3{0.0, 0.0, -1.5};
  Factory factory(spec, uniform_type(2e-3, 4e-3), 42);
  ParticleStore particles;
  ParticleId next_id = 100;
  EXPECT_EQ(factory.insert_due(0.1, particles, next_id, kNoSurfaces).inserted,
            0);  // before start_time
  EXPECT_FALSE(factory.finished());
  const InsertionReport report = factory.insert_due(0.2, particles, next_id, kNoSurfaces);
  EXPECT_EQ(report.inserted, 600);
  EXPECT_EQ(report.failed, 0);
  ASSERT_EQ(particles.size(), 600u);
  EXPECT_EQ(next_id, 700u);
  EXPECT_TRUE(factory.finished());
  EXPECT_EQ(factory.shortfall(), 0);
  EXPECT_NEAR(report.inserted_mass, total_mass(particles), 1e-12 * report.inserted_mass);
  EXPECT_LE(largest_overlap(particles), 0.0);
  const Region region(spec.region);
  for (std::size_t i = 0; i < particles.size(); ++i) {
    EXPECT_EQ(particles.id[i], 100 + i);
    EXPECT_EQ(particles.type[i], 3);
    EXPECT_EQ(particles.material[i], 1);
    EXPECT_EQ(particles.creation_time[i], 0.2);
    EXPECT_EQ(particles.velocity[i], (Vec3{0.0, 0.0, -1.5}));
    const Vec3& x = particles.position[i];
    const double r = particles.radius[i];
    EXPECT_TRUE(x.x >= r && x.x <= 0.1 - r && x.y >= r && x.y <= 0.1 - r && x.z >= r &&
                x.z <= 0.1 - r);
  }
  EXPECT_EQ(factory.insert_due(1.0, particles, next_id, kNoSurfaces).inserted,
            0);  // nothing more is due
}

// A stop asked for during a long insertion ends the call after the current block of 1024
// particles; the rest stay waiting and a later call places them (issue 19: SIGTERM was ignored
// until a two-million-particle insertion had finished).
TEST(Factory, StopRequestEndsTheInsertionEarlyAndTheRestIsPlacedLater) {
  FactorySpec spec = box_factory({0, 0, 0}, {0.4, 0.4, 0.4});
  spec.target_count = Located<std::int64_t>(5000);
  Factory factory(spec, uniform_type(2e-3, 3e-3), 42);
  ParticleStore particles;
  ParticleId next_id = 0;
  int asked = 0;
  const auto stop_at_second_question = [&asked] { return ++asked >= 2; };
  const InsertionReport first =
      factory.insert_due(0.0, particles, next_id, kNoSurfaces, stop_at_second_question);
  EXPECT_EQ(first.inserted, 2048);  // asked at 1024 (no) and 2048 (yes)
  EXPECT_EQ(factory.waiting_count(), 5000 - 2048);
  EXPECT_FALSE(factory.finished());
  const InsertionReport second = factory.insert_due(1e-5, particles, next_id, kNoSurfaces);
  EXPECT_EQ(second.inserted, 5000 - 2048);
  EXPECT_EQ(particles.size(), 5000u);
  EXPECT_TRUE(factory.finished());
  EXPECT_LE(largest_overlap(particles), 0.0);
}

TEST(Factory, NewParticlesAvoidExistingOnes) {
  // A lattice of large existing particles through the region and beyond its faces.
  ParticleStore particles;
  ParticleId next_id = 0;
  for (int i = -1; i <= 5; ++i)
    for (int j = -1; j <= 5; ++j)
      for (int k = -1; k <= 5; ++k)
        particles.add(next_id++, 0, 0, {0.02 * i + 0.005, 0.02 * j + 0.005, 0.02 * k + 0.005}, {},
                      0.006, kDensity, 0.0);
  const std::size_t existing = particles.size();
  FactorySpec spec = box_factory({0, 0, 0}, {0.1, 0.1, 0.1});
  spec.target_count = Located<std::int64_t>(800);
  Factory factory(spec, uniform_type(1.5e-3, 3e-3), 7);
  const InsertionReport report = factory.insert_due(0.0, particles, next_id, kNoSurfaces);
  EXPECT_EQ(report.inserted, 800);
  ASSERT_EQ(particles.size(), existing + 800);
  EXPECT_LE(largest_overlap(particles), 0.0);  // all pairs: new–new and new–existing
}

TEST(Factory, MassTargetIsMetWithinOneParticleMass) {
  // Rule: draw while drawn mass < target − ½ mean mass m̄, so
  // target − ½ m̄ ≤ M < target − ½ m̄ + m_max, i.e. within one particle mass of the target.
  FactorySpec spec = box_factory({0, 0, 0}, {0.2, 0.2, 0.2});
  spec.target_mass = 1.0;  // kg
  const ParticleTypeInfo type = discrete_type();
  Factory factory(spec, type, 3);
  ParticleStore particles;
  ParticleId next_id = 0;
  factory.insert_due(0.0, particles, next_id, kNoSurfaces);
  const double mean_mass = SizeSampler(type.size).mean_particle_mass(kDensity);
  const double inserted = total_mass(particles);
  EXPECT_NEAR(factory.inserted_mass(), inserted, 1e-12);
  EXPECT_GE(inserted, 1.0 - 0.5 * mean_mass);
  EXPECT_LE(std::abs(inserted - 1.0), sphere_mass(5e-3));
  EXPECT_TRUE(factory.finished());
  EXPECT_EQ(factory.shortfall(), 0);
  EXPECT_LE(largest_overlap(particles), 0.0);
  // The discrete mass fractions hold to within one particle mass of the largest class.
  std::vector<double> class_mass(3, 0.0);
  for (std::size_t i = 0; i < particles.size(); ++i)
    class_mass[particles.radius[i] == 2e-3 ? 0 : (particles.radius[i] == 3e-3 ? 1 : 2)] +=
        particles.mass(i);
  const std::vector<double> fractions = {0.3, 0.3, 0.4};
  for (int k = 0; k < 3; ++k)
    EXPECT_LE(std::abs(class_mass[k] - fractions[k] * inserted), sphere_mass(5e-3));
}

TEST(Factory, MassRateScheduleIsFollowedWithinOneParticleMass) {
  // Inserted mass at t ≈ mass_rate · (t − start) (within one particle mass) until the target.
  FactorySpec spec = box_factory({0, 0, 0}, {0.3, 0.3, 0.1});
  spec.target_mass = 2.0;  // kg
  spec.mass_rate = 5.0;    // kg/s → 0.4 s
  spec.start_time = 0.1;   // s
  Factory factory(spec, uniform_type(3e-3, 5e-3), 9);
  ParticleStore particles;
  ParticleId next_id = 0;
  const double largest_mass = sphere_mass(5e-3);
  double inserted = 0.0;  // kg, summed over the calls
  for (int call = 0; call <= 300; ++call) {
    const double time = 0.002 * call;  // s
    const InsertionReport report = factory.insert_due(time, particles, next_id, kNoSurfaces);
    ASSERT_NEAR(report.inserted_mass, total_mass(particles), 1e-12);  // the store was empty before
    inserted += report.inserted_mass;
    const double scheduled = std::clamp(5.0 * (time - 0.1), 0.0, 2.0);  // kg
    ASSERT_LE(std::abs(inserted - scheduled), largest_mass) << "t = " << time;
    // The region drains: particles leave it as if falling out, so nothing blocks the rate.
    particles.clear();
  }
  EXPECT_TRUE(factory.finished());
  EXPECT_LE(std::abs(factory.inserted_mass() - 2.0), largest_mass);
}

TEST(Factory, CountTargetWithRateFollowsTheMassScheduleAndEndsAtTheCount) {
  FactorySpec spec = box_factory({0, 0, 0}, {0.2, 0.2, 0.2});
  spec.target_count = Located<std::int64_t>(400);
  spec.mass_rate = 1.0;  // kg/s
  const ParticleTypeInfo type = uniform_type(2e-3, 4e-3);
  const double duration = 400 * SizeSampler(type.size).mean_particle_mass(kDensity) / 1.0;  // s
  Factory factory(spec, type, 10);
  ParticleStore particles;
  ParticleId next_id = 0;
  for (double time = 0.0; time < 0.9 * duration; time += 0.01 * duration) {
    factory.insert_due(time, particles, next_id, kNoSurfaces);
    ASSERT_LE(std::abs(total_mass(particles) - 1.0 * time), sphere_mass(4e-3)) << "t = " << time;
  }
  EXPECT_FALSE(factory.finished());
  factory.insert_due(duration, particles, next_id, kNoSurfaces);
  EXPECT_EQ(particles.size(), 400u);
  EXPECT_TRUE(factory.finished());
  EXPECT_LE(largest_overlap(particles), 0.0);
}

TEST(Factory, RegionTooSmallReportsShortfallInsteadOfOverlapping) {
  // A 2 cm cube holds at most (2 cm)³ · 0.74 / (4/3 π (2 mm)³) ≈ 177 spheres of radius 2 mm even
  // at densest packing (Kepler bound π/√18), random placement far fewer; 1000 are requested.
  FactorySpec spec = box_factory({0, 0, 0}, {0.02, 0.02, 0.02});
  spec.target_count = Located<std::int64_t>(1000);
  spec.stop_time = 0.5;
  ParticleTypeInfo type = uniform_type(2e-3, 2e-3);
  Factory factory(spec, type, 4);
  ParticleStore particles;
  ParticleId next_id = 0;
  const InsertionReport first = factory.insert_due(0.0, particles, next_id, kNoSurfaces);
  EXPECT_GT(first.inserted, 0);
  EXPECT_LT(first.inserted, 178);
  EXPECT_EQ(first.failed, 1000 - first.inserted);
  EXPECT_FALSE(factory.finished());
  EXPECT_EQ(factory.shortfall(), 1000 - first.inserted);
  EXPECT_LE(largest_overlap(particles), 0.0);

  // Space frees (the particles fall out): the waiting particles are placed at the next call.
  particles.clear();
  const InsertionReport second = factory.insert_due(0.25, particles, next_id, kNoSurfaces);
  EXPECT_GT(second.inserted, 0);
  EXPECT_EQ(factory.inserted_count(), first.inserted + second.inserted);
  EXPECT_EQ(factory.shortfall(), 1000 - factory.inserted_count());

  // The call at stop_time is the last one; the rest is reported, never silently dropped.
  factory.insert_due(0.6, particles, next_id, kNoSurfaces);
  EXPECT_TRUE(factory.finished());
  EXPECT_GT(factory.shortfall(), 0);
  EXPECT_EQ(factory.shortfall() + factory.inserted_count(), 1000);
  EXPECT_EQ(static_cast<std::int64_t>(next_id), factory.inserted_count());
  const std::int64_t before = factory.inserted_count();
  particles.clear();
  EXPECT_EQ(factory.insert_due(0.7, particles, next_id, kNoSurfaces).inserted, 0);
  EXPECT_EQ(factory.inserted_count(), before);
}

TEST(Factory, SurfaceQueryIsRespected) {
  // A plane z = 0.05 m through the middle of the region: no new sphere may cut it.
  FactorySpec spec = box_factory({0, 0, 0}, {0.1, 0.1, 0.1});
  spec.target_count = Located<std::int64_t>(500);
  Factory factory(spec, uniform_type(2e-3, 4e-3), 5);
  ParticleStore particles;
  ParticleId next_id = 0;
  int queries = 0;
  const SurfaceOverlapQuery plane = [&queries](const Vec3& centre, double radius) {
    ++queries;
    return std::abs(centre.z - 0.05) < radius;
  };
  EXPECT_EQ(factory.insert_due(0.0, particles, next_id, plane).inserted, 500);
  int above = 0;
  for (std::size_t i = 0; i < particles.size(); ++i) {
    EXPECT_GE(std::abs(particles.position[i].z - 0.05), particles.radius[i]);
    above += particles.position[i].z > 0.05;
  }
  EXPECT_GE(queries, 500);
  EXPECT_GT(above, 100);  // both halves filled
  EXPECT_LT(above, 400);
}

TEST(Factory, SameSeedGivesIdenticalParticlesAndOtherSeedsDiffer) {
  FactorySpec spec = box_factory({0, 0, 0}, {0.1, 0.1, 0.1});
  spec.target_mass = 0.3;
  spec.mass_rate = 3.0;
  const auto run = [&](std::uint64_t seed) {
    Factory factory(spec, discrete_type(), seed);
    ParticleStore particles;
    ParticleId next_id = 0;
    for (int call = 0; call < 20; ++call)
      factory.insert_due(0.01 * call, particles, next_id, kNoSurfaces);
    return particles;
  };
  const ParticleStore a = run(77), b = run(77), c = run(78);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a.position[i], b.position[i]);
    EXPECT_EQ(a.radius[i], b.radius[i]);
  }
  ASSERT_GT(c.size(), 0u);
  EXPECT_NE(a.position[0], c.position[0]);
}

TEST(Factory, SavedStateContinuesIdentically) {
  // Normal sizes and a tight region, so that at the save point some radii are still waiting.
  FactorySpec spec = box_factory({0, 0, 0}, {0.03, 0.03, 0.03});
  spec.target_count = Located<std::int64_t>(2000);
  spec.mass_rate = 0.5;  // kg/s, about 115 particles per call: more than the region holds
  ParticleTypeInfo type;
  type.density = kDensity;
  type.size.kind = SizeDistributionKind::normal;
  type.size.mean_radius = 2e-3;
  type.size.std_radius = 0.3e-3;
  Factory original(spec, type, 21);
  ParticleStore particles;
  ParticleId next_id = 0;
  const auto drain_bottom = [](ParticleStore& p) {  // particles below 1 cm "fall out"
    std::vector<char> gone(p.size());
    for (std::size_t i = 0; i < p.size(); ++i) gone[i] = p.position[i].z < 0.01;
    p.remove_flagged(gone);
  };
  for (int call = 0; call < 10; ++call) {
    original.insert_due(0.02 * call, particles, next_id, kNoSurfaces);
    drain_bottom(particles);
  }
  ASSERT_GT(original.waiting_count(), 0);  // the saved state includes radii not yet placed
  const std::vector<std::uint64_t> saved = original.save_state();
  ParticleStore particles_copy = particles;
  ParticleId next_id_copy = next_id;
  Factory restored(spec, type, 999);  // a different seed: the loaded state must override it
  restored.load_state(saved);
  EXPECT_EQ(restored.save_state(), saved);
  for (int call = 10; call < 40; ++call) {
    const InsertionReport a = original.insert_due(0.02 * call, particles, next_id, kNoSurfaces);
    const InsertionReport b =
        restored.insert_due(0.02 * call, particles_copy, next_id_copy, kNoSurfaces);
    EXPECT_EQ(a.inserted, b.inserted);
    EXPECT_EQ(a.failed, b.failed);
    drain_bottom(particles);
    drain_bottom(particles_copy);
  }
  ASSERT_EQ(particles.size(), particles_copy.size());
  for (std::size_t i = 0; i < particles.size(); ++i) {
    EXPECT_EQ(particles.id[i], particles_copy.id[i]);
    EXPECT_EQ(particles.position[i], particles_copy.position[i]);
    EXPECT_EQ(particles.radius[i], particles_copy.radius[i]);
  }
  EXPECT_EQ(next_id, next_id_copy);
  EXPECT_GT(original.inserted_count(), 100);
  EXPECT_EQ(original.save_state(), restored.save_state());

  std::vector<std::uint64_t> damaged = saved;
  damaged.pop_back();
  EXPECT_THROW(restored.load_state(damaged), UserError);
  EXPECT_THROW(restored.load_state({}), UserError);
}

TEST(Factory, InvalidSpecsAreUserErrors) {
  FactorySpec both = box_factory({0, 0, 0}, {0.1, 0.1, 0.1});
  both.target_count = Located<std::int64_t>(10);
  both.target_mass = 1.0;
  EXPECT_THROW(Factory(both, uniform_type(1e-3, 2e-3), 1), UserError);
  FactorySpec neither = box_factory({0, 0, 0}, {0.1, 0.1, 0.1});
  EXPECT_THROW(Factory(neither, uniform_type(1e-3, 2e-3), 1), UserError);
  FactorySpec thin = box_factory({0, 0, 0}, {0.1, 0.1, 0.003});  // holds radius ≤ 1.5 mm only
  thin.target_count = Located<std::int64_t>(10);
  EXPECT_THROW(Factory(thin, uniform_type(1e-3, 2e-3), 1), UserError);
  FactorySpec several = box_factory({0, 0, 0}, {0.1, 0.1, 0.1});
  several.target_mass = -1.0;
  several.mass_rate = 0.0;
  several.max_attempts = 0;
  try {
    Factory factory(several, uniform_type(1e-3, 2e-3), 1);
    ADD_FAILURE() << "invalid factory accepted";
  } catch (const UserError& error) {
    EXPECT_EQ(error.diagnostics().all().size(), 3u);  // every problem reported at once
  }
}

}  // namespace quarry
