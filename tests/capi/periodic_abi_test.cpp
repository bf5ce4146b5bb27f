// Periodic axes through the C ABI (ABI 1.1, quarry_settings.periodic): a simulation built by
// calls and periodic in x and y wraps a particle leaving through a face (same velocity) and
// lets two particles touch through it (equal and opposite repulsion), stepping to the same bits
// as the deck with `periodic: [x, y]`; a caller built against ABI 1.0 (the struct ending at
// seed) is served and gets no periodic axes, a shorter struct_size is refused; bad entries and
// periods too short for the particles are refused with the deck's message and leave the handle
// as it was. Nothing but quarry.h and libquarry.so.
#include <dlfcn.h>
#include <gtest/gtest.h>
#include <quarry/quarry.h>
#include <unistd.h>

#include <array>
#include <cstddef>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

std::string error_of(quarry_sim sim) {
  char text[4096] = {0};
  quarry_last_error(sim, text, sizeof text, nullptr);
  return text;
}

// quarry_settings as a caller compiled against ABI 1.0's quarry.h has it: it ends at seed.
struct settings_1_0 {
  uint32_t struct_size;
  double time_step;
  double rayleigh_fraction;
  double gravity[3];
  double domain_min[3];
  double domain_max[3];
  double end_time;
  double impact_speed;
  double skin;
  int32_t integrator;
  int32_t sort_interval;
  double max_overlap_fraction;
  uint64_t seed;
};
static_assert(sizeof(settings_1_0) == offsetof(quarry_settings, periodic),
              "ABI 1.1 appended periodic right after 1.0's last field");

constexpr double kRadius = 0.005;   // m
constexpr double kTimeStep = 1e-5;  // s
constexpr double kSpeed = 1.0;      // m/s, of the particle that crosses the x face
constexpr double kBox = 0.1;        // m, the period along x and y

// The box [0, 0.1]² × [−0.05, 0.05] m, periodic or not in x and y, no gravity.
quarry_settings box_settings(bool periodic) {
  quarry_settings s = quarry_default_settings();
  s.time_step = kTimeStep;
  s.gravity[2] = 0.0;
  s.domain_min[0] = 0.0, s.domain_min[1] = 0.0, s.domain_min[2] = -0.05;
  s.domain_max[0] = kBox, s.domain_max[1] = kBox, s.domain_max[2] = 0.05;
  s.impact_speed = kSpeed;
  s.periodic[0] = s.periodic[1] = periodic ? 1 : 0;
  return s;
}

// The same simulation as a deck (the ABI's defaults are the deck's).
const char* const kDeck = R"(simulation:
  end_time: 1.0
  time_step: 1.0e-5
  impact_speed: 1.0
  gravity: [0, 0, 0]
  domain: {min: [0, 0, -0.05], max: [0.1, 0.1, 0.05], periodic: [x, y]}
materials:
  - {name: glass, density: 2500, youngs_modulus: 1.0e7, poisson_ratio: 0.3}
interactions:
  - {materials: [glass, glass], restitution: 0.5, static_friction: 0.5}
particle_types:
  - {name: bead, material: glass, size: {distribution: fixed, radius: 0.005}}
)";

quarry_sim open_empty() {
  quarry_open_info info = QUARRY_OPEN_INFO_INIT;
  quarry_sim sim{};
  EXPECT_EQ(quarry_open(&info, &sim), QUARRY_OK) << error_of(QUARRY_NO_SIM);
  return sim;
}

void add_material_and_interaction(quarry_sim sim) {
  quarry_material glass{sizeof(quarry_material), "glass", 2500.0, 1e7, 0.3};
  ASSERT_EQ(quarry_add_material(sim, &glass, nullptr), QUARRY_OK) << error_of(sim);
  quarry_interaction contact{sizeof(quarry_interaction), "glass", "glass", 0.5, 0.5, 0.0,
                             QUARRY_ROLLING_NONE,        0.0};
  ASSERT_EQ(quarry_add_interaction(sim, &contact), QUARRY_OK) << error_of(sim);
}

quarry_status add_bead(quarry_sim sim, double radius = kRadius) {
  quarry_particle_type bead{sizeof(quarry_particle_type), "bead", "glass", radius, 0.0};
  return quarry_add_particle_type(sim, &bead, nullptr);
}

// Particle 1 at x = 0.098 m moving +x (it crosses the x = 0.1 face after 2 ms); particles 2
// and 3 at rest on either side of the x faces, 9.9 mm apart through them (0.1 mm overlap) and
// 0.09 m apart inside the box; y keeps 1 away from 2 and 3.
void add_three(quarry_sim sim) {
  const double position[9] = {0.098, 0.05, 0.0, 0.004, 0.02, 0.0, kBox - 0.0059, 0.02, 0.0};
  const double velocity[9] = {kSpeed, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
  quarry_new_particles add{};
  add.struct_size = sizeof add;
  add.count = 3;
  add.position = position;
  add.velocity = velocity;
  ASSERT_EQ(quarry_add_particles(sim, &add), QUARRY_OK) << error_of(sim);
}

// The box built by calls from `settings` (any struct_size the caller's quarry.h gave it), started,
// with the three particles.
quarry_sim built(const quarry_settings* settings) {
  quarry_sim sim = open_empty();
  EXPECT_EQ(quarry_set_settings(sim, settings), QUARRY_OK) << error_of(sim);
  add_material_and_interaction(sim);
  EXPECT_EQ(add_bead(sim), QUARRY_OK) << error_of(sim);
  EXPECT_EQ(quarry_start(sim), QUARRY_OK) << error_of(sim);
  add_three(sim);
  return sim;
}

struct State {
  std::array<double, 3> x, v, f;
};

// Every particle's position, velocity and force by id.
std::map<std::uint64_t, State> particles(quarry_sim sim) {
  std::uint64_t ids[8];
  double x[24], v[24], f[24];
  quarry_particle_data data{};
  data.struct_size = sizeof data;
  data.capacity = 8;
  data.id = ids, data.position = x, data.velocity = v, data.force = f;
  EXPECT_EQ(quarry_get_particles(sim, &data), QUARRY_OK) << error_of(sim);
  std::map<std::uint64_t, State> out;
  for (std::uint64_t k = 0; k < data.count; ++k) {
    State s;
    for (int a = 0; a < 3; ++a) s.x[a] = x[3 * k + a], s.v[a] = v[3 * k + a], s.f[a] = f[3 * k + a];
    out[ids[k]] = s;
  }
  return out;
}

TEST(PeriodicAbi, AParticleLeavingReentersAndAPairTouchesThroughTheFaces) {
  const quarry_settings settings = box_settings(true);
  quarry_sim sim = built(&settings);
  ASSERT_EQ(quarry_step(sim, 1), QUARRY_OK) << error_of(sim);
  // 2 and 3 touch through the x faces: 2 is pushed to +x (3's image is at x = −0.0059 m), 3 to
  // −x, equal and opposite (the pair's one force); nothing else acts on them.
  auto p = particles(sim);
  ASSERT_EQ(p.size(), 3u);
  EXPECT_GT(p[2].f[0], 0.0);
  EXPECT_EQ(p[3].f[0], -p[2].f[0]);
  for (int a = 1; a < 3; ++a) {
    EXPECT_EQ(p[2].f[a], 0.0);
    EXPECT_EQ(p[3].f[a], 0.0);
  }
  EXPECT_EQ(p[1].f, (std::array<double, 3>{0.0, 0.0, 0.0}));

  // 500 steps (5 ms): particle 1 has travelled 5 mm from x = 0.098 m, through the face at 0.1 m:
  // it is at 0.003 m, not removed, its velocity exactly what it was.
  ASSERT_EQ(quarry_step(sim, 499), QUARRY_OK) << error_of(sim);
  p = particles(sim);
  ASSERT_EQ(p.size(), 3u) << "a particle leaving through a periodic face is not removed";
  EXPECT_NEAR(p[1].x[0], 0.098 + 500 * kTimeStep * kSpeed - kBox, 1e-12);
  EXPECT_GE(p[1].x[0], 0.0);
  EXPECT_EQ(p[1].v, (std::array<double, 3>{kSpeed, 0.0, 0.0}));
  // The pair pushed itself apart through the faces: 2 moves +x, 3 moves −x, momentum kept.
  EXPECT_GT(p[2].v[0], 0.0);
  EXPECT_EQ(p[3].v[0], -p[2].v[0]);
  EXPECT_EQ(quarry_close(sim), QUARRY_OK);
}

TEST(PeriodicAbi, StepsToTheSameBitsAsTheDeckWithPeriodicXY) {
  const fs::path deck =
      fs::current_path() / ("periodic_abi_test_" + std::to_string(::getpid()) + ".yaml");
  std::ofstream(deck) << kDeck;
  quarry_open_info info = QUARRY_OPEN_INFO_INIT;
  info.deck_path = deck.c_str();
  quarry_sim from_deck{};
  ASSERT_EQ(quarry_open(&info, &from_deck), QUARRY_OK) << error_of(QUARRY_NO_SIM);
  fs::remove(deck);
  add_three(from_deck);
  const quarry_settings settings = box_settings(true);
  quarry_sim by_calls = built(&settings);

  double dt_deck = 0.0, dt_calls = 0.0;
  ASSERT_EQ(quarry_get_time(from_deck, nullptr, &dt_deck, nullptr), QUARRY_OK);
  ASSERT_EQ(quarry_get_time(by_calls, nullptr, &dt_calls, nullptr), QUARRY_OK);
  EXPECT_EQ(dt_deck, dt_calls);
  ASSERT_EQ(quarry_step(from_deck, 800), QUARRY_OK) << error_of(from_deck);
  ASSERT_EQ(quarry_step(by_calls, 800), QUARRY_OK) << error_of(by_calls);
  const auto a = particles(from_deck), b = particles(by_calls);
  ASSERT_EQ(a.size(), 3u);
  ASSERT_EQ(b.size(), 3u);
  for (const auto& [id, s] : a) {
    ASSERT_TRUE(b.count(id)) << id;
    EXPECT_EQ(std::memcmp(&s, &b.at(id), sizeof s), 0) << "particle " << id;
  }
  EXPECT_LT(a.at(1).x[0], 0.01) << "particle 1 crossed the face and re-entered";
  EXPECT_EQ(quarry_close(from_deck), QUARRY_OK);
  EXPECT_EQ(quarry_close(by_calls), QUARRY_OK);
}

TEST(PeriodicAbi, ACallerBuiltAgainstAbi10IsServedWithoutPeriodicAxes) {
  // The 1.0 struct, as an old caller fills it, at the start of a buffer whose later bytes are
  // not zero: read as periodic entries they would be refused (0x01010101), so a success shows
  // the library read no byte past the caller's struct_size.
  const quarry_settings current = box_settings(false);
  settings_1_0 old{};
  std::memcpy(&old, &current, sizeof old);
  old.struct_size = sizeof old;
  static_assert(sizeof old == 144, "ABI 1.0's quarry_settings is 144 bytes on LP64");
  alignas(quarry_settings) unsigned char buffer[sizeof(quarry_settings)];
  std::memset(buffer, 0x01, sizeof buffer);
  std::memcpy(buffer, &old, sizeof old);
  quarry_sim sim = built(reinterpret_cast<const quarry_settings*>(buffer));
  ASSERT_EQ(quarry_step(sim, 1), QUARRY_OK) << error_of(sim);
  auto p = particles(sim);
  ASSERT_EQ(p.size(), 3u);
  EXPECT_EQ(p[2].f, (std::array<double, 3>{0.0, 0.0, 0.0}))
      << "0.09 m apart: no contact without periodic x";
  EXPECT_EQ(p[3].f, (std::array<double, 3>{0.0, 0.0, 0.0}));
  ASSERT_EQ(quarry_step(sim, 499), QUARRY_OK) << error_of(sim);
  p = particles(sim);
  EXPECT_EQ(p.size(), 2u) << "particle 1 left the box through x = 0.1 m and is removed";
  EXPECT_EQ(p.count(1), 0u);
  EXPECT_EQ(quarry_close(sim), QUARRY_OK);

  // Exactly 1.0's size on the heap (a sanitizer sees any read past it).
  auto exact = std::make_unique<settings_1_0>(old);
  sim = open_empty();
  EXPECT_EQ(quarry_set_settings(sim, reinterpret_cast<const quarry_settings*>(exact.get())),
            QUARRY_OK)
      << error_of(sim);
  // Shorter than any version: refused, naming the sizes.
  exact->struct_size = sizeof old - 8;
  EXPECT_EQ(quarry_set_settings(sim, reinterpret_cast<const quarry_settings*>(exact.get())),
            QUARRY_ERROR_BAD_VALUE);
  const std::string text = error_of(sim);
  EXPECT_NE(text.find("struct_size is 136"), std::string::npos) << text;
  EXPECT_NE(text.find("144"), std::string::npos) << text;
  EXPECT_EQ(quarry_close(sim), QUARRY_OK);
}

// quarry_default_settings returns its struct by value into room the caller sized: a binary
// linked before ABI 1.1 binds to the symbol's QUARRY_1.0 version (libquarry.map), which writes
// 1.0's 144 bytes, not 1.1's 160; a binary linked now gets QUARRY_1.1.
TEST(PeriodicAbi, TheDefaultSettingsKeepTheirAbi10FormForCallersLinkedBefore) {
  using Old = settings_1_0 (*)();
  using Now = quarry_settings (*)();
  const auto old =
      reinterpret_cast<Old>(dlvsym(RTLD_DEFAULT, "quarry_default_settings", "QUARRY_1.0"));
  const auto now =
      reinterpret_cast<Now>(dlvsym(RTLD_DEFAULT, "quarry_default_settings", "QUARRY_1.1"));
  ASSERT_NE(old, nullptr) << dlerror();
  ASSERT_NE(now, nullptr) << dlerror();
  const settings_1_0 s = old();
  const quarry_settings current = now();
  EXPECT_EQ(s.struct_size, sizeof(settings_1_0));
  EXPECT_EQ(current.struct_size, sizeof(quarry_settings));
  EXPECT_EQ(quarry_default_settings().struct_size, sizeof(quarry_settings));
  EXPECT_EQ(
      std::memcmp(&s.time_step, &current.time_step, sizeof s - offsetof(settings_1_0, time_step)),
      0);
  EXPECT_EQ(s.seed, 12345u);
  EXPECT_EQ(current.periodic[0] | current.periodic[1] | current.periodic[2], 0);
}

TEST(PeriodicAbi, BadEntriesAndShortPeriodsAreRefusedAndChangeNothing) {
  quarry_sim sim = open_empty();
  add_material_and_interaction(sim);
  ASSERT_EQ(add_bead(sim), QUARRY_OK) << error_of(sim);
  const quarry_settings good = box_settings(true);
  ASSERT_EQ(quarry_set_settings(sim, &good), QUARRY_OK) << error_of(sim);

  // Each refused with BAD_VALUE and a text that says what and how to fix it.
  struct Case {
    const char* what;
    quarry_settings settings;
    std::vector<std::string> words;
  };
  std::vector<Case> cases;
  quarry_settings s = good;
  s.periodic[1] = 2;
  cases.push_back({"an entry of 2", s, {"quarry_set_settings", "periodic[1]", "is 2", "give 1"}});
  s = good;
  s.periodic[0] = -1;
  cases.push_back({"an entry of −1", s, {"periodic[0]", "is -1"}});
  s = good;
  s.periodic[2] = 1;
  s.domain_min[2] = s.domain_max[2] = 0.0;
  cases.push_back(
      {"z periodic, no extent along z", s, {"no finite extent along z", "hint:", "max > min"}});
  s = good;
  s.domain_max[0] = 0.03;  // 3 × (2 × 5 mm + 1 mm) = 33 mm needed
  cases.push_back(
      {"a period too short along x",
       s,
       {"the period along x (0.03 m) is shorter than the neighbour search needs", "0.033 m",
        "hint: make the domain at least 0.033 m long along x, or leave x out of periodic"}});
  for (const Case& c : cases) {
    EXPECT_EQ(quarry_set_settings(sim, &c.settings), QUARRY_ERROR_BAD_VALUE) << c.what;
    const std::string text = error_of(sim);
    for (const std::string& word : c.words)
      EXPECT_NE(text.find(word), std::string::npos) << c.what << ": " << text;
  }
  // A type too large for the period (3 × (2 × 20 mm + 4 mm) > 0.1 m) is not added.
  EXPECT_EQ(add_bead(sim, 0.02), QUARRY_ERROR_BAD_VALUE);
  EXPECT_NE(error_of(sim).find("quarry_add_particle_type: the period along x"), std::string::npos)
      << error_of(sim);
  std::uint32_t types = 0;
  ASSERT_EQ(quarry_num_types(sim, &types), QUARRY_OK);
  EXPECT_EQ(types, 1u);

  // The handle has the good settings still: the box is periodic, particle 1 wraps.
  ASSERT_EQ(quarry_start(sim), QUARRY_OK) << error_of(sim);
  add_three(sim);
  ASSERT_EQ(quarry_step(sim, 500), QUARRY_OK) << error_of(sim);
  const auto p = particles(sim);
  ASSERT_EQ(p.size(), 3u);
  EXPECT_NEAR(p.at(1).x[0], 0.003, 1e-9);
  EXPECT_EQ(quarry_close(sim), QUARRY_OK);
}

}  // namespace
