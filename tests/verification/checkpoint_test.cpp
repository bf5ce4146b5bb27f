// Checkpoints that are damaged never crash or restore a different state: a flipped bit anywhere
// or a truncation is caught by the header and the CRC-32 of the payload; a file whose checksum is
// right but whose content is inconsistent (written by a bug, or forged) is caught by the
// validation of every length, index and value — each an error that says what is wrong.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>
#include <random>
#include <string>

#include "geometry/primitives.h"
#include "geometry/stl_reader.h"
#include "sim/binary_stream.h"
#include "sim/run.h"
#include "verification/test_support.h"

namespace quarry {
namespace {

using testing_support::deck_path;
using testing_support::start_world;

World stepped_world() {
  const SimulationSpec spec = parse_deck(deck_path("tests/verification/05-determinism/deck.yaml"));
  World world = start_world(spec);
  for (int n = 0; n < 1500; ++n) sim::step(world);  // contacts, wall contacts and history exist
  return world;
}

// The restore of `bytes` must fail with a UserError whose text contains `expected`.
void expect_refused(const std::string& bytes, const std::string& expected, const std::string& what) {
  try {
    sim::read_checkpoint_bytes(bytes, "damaged.qck");
    ADD_FAILURE() << what << ": restored without a word";
  } catch (const UserError& e) {
    const std::string text = e.diagnostics().format();
    EXPECT_NE(text.find("damaged.qck"), std::string::npos) << what << ": " << text;
    EXPECT_NE(text.find(expected), std::string::npos) << what << ": " << text;
  }
}

TEST(CheckpointDamage, FlippedBitsAndTruncationsAreRefused) {
  const World world = stepped_world();
  const std::string bytes = sim::checkpoint_bytes(world, 3);
  ASSERT_GT(bytes.size(), 10000u);
  // The intact file restores the same state.
  EXPECT_EQ(sim::state_hash(sim::read_checkpoint_bytes(bytes, "intact.qck").world), sim::state_hash(world));
  std::mt19937_64 random(20261202);
  std::uniform_int_distribution<std::size_t> position(0, bytes.size() - 1);
  for (int k = 0; k < 300; ++k) {
    std::string damaged = bytes;
    const std::size_t at = k < 32 ? static_cast<std::size_t>(k) : position(random);  // every header byte too
    damaged[at] = static_cast<char>(damaged[at] ^ (1 << (k % 8)));
    try {
      sim::read_checkpoint_bytes(damaged, "damaged.qck");
      ADD_FAILURE() << "a flip of bit " << k % 8 << " of byte " << at << " restored";
    } catch (const UserError&) {
    }
  }
  for (const std::size_t keep : {std::size_t{0}, std::size_t{7}, std::size_t{31}, std::size_t{32}, bytes.size() / 2, bytes.size() - 1}) {
    expect_refused(bytes.substr(0, keep), "cannot restore checkpoint", "truncated to " + std::to_string(keep));
  }
  expect_refused(bytes + "x", "cannot restore checkpoint", "one byte appended");
  std::string other_format = bytes;
  other_format[6] = '9';  // "QURYCK09": another format of the same family
  expect_refused(other_format, "another version", "another format");
  expect_refused(std::string(200, 'x'), "not a Quarry checkpoint", "random bytes");
}

// Damage inside a correctly checksummed file: the writer does not check what it writes, so a
// world changed by hand gives such a file.
TEST(CheckpointDamage, InconsistentContentIsNamed) {
  const World original = stepped_world();
  ASSERT_GT(original.pairs.size(), 0u);
  ASSERT_FALSE(original.wall_contacts.empty());
  const std::vector<std::pair<std::string, std::function<void(World&)>>> cases = {
      {"neighbour pair 0 names particle", [](World& w) { w.pairs.partner[0] = 0xFFFFFFF0u; }},
      {"offsets", [](World& w) { w.pairs.offsets.pop_back(); }},
      {"time step", [](World& w) { w.dt = 0.0; }},
      {"the time", [](World& w) { w.time = std::nan(""); }},
      {"particle positions", [](World& w) { w.particles.position[5].y = INFINITY; }},
      {"particle radii", [](World& w) { w.particles.radius.pop_back(); }},
      {"has radius", [](World& w) { w.particles.radius[3] = -1.0; }},
      {"material index", [](World& w) { w.particles.material[2] = 40; }},
      {"has id", [](World& w) { w.particles.id[1] = w.next_id + 5; }},
      {"wall contact 0", [](World& w) { w.wall_contacts[0].triangle = 1u << 30; }},
      {"surface candidate", [](World& w) { w.candidates.particles[0] = 1u << 30; }},
      {"tangential history", [](World& w) { w.pairs.tangential_displacement.pop_back(); }},
  };
  for (const auto& [expected, damage] : cases) {
    World world = original;
    damage(world);
    expect_refused(sim::checkpoint_bytes(world, 0), expected, expected);
  }
}

// A checkpoint holds the effective deck and every mesh: with the deck and its STL file gone it
// restores and continues bit-identically, from any folder; an STL that is still there but
// changed is an error naming it (a restart continues the same simulation).
TEST(CheckpointDamage, RestoresWithoutTheDecksFilesAndRefusesAChangedMesh) {
  namespace fs = std::filesystem;
  const fs::path folder = fs::path(::testing::TempDir()) / "quarry_checkpoint_without_files";
  fs::remove_all(folder);
  fs::create_directories(folder);
  write_stl_binary((folder / "floor.stl").string(), make_plane({0, 0, 0}, {0, 0, 1}, 0.2, 4));
  std::ofstream(folder / "deck.yaml") << R"(simulation:
  end_time: 0.05
  time_step: 2.0e-6
  impact_speed: 1.0
  domain: {min: [-0.1, -0.1, -0.1], max: [0.1, 0.1, 0.2]}
materials:
  - {name: ball, density: 7800, youngs_modulus: 1.0e8, poisson_ratio: 0.3}
interactions:
  - {materials: [ball, ball], restitution: 0.5, static_friction: 0.3}
particle_types:
  - {name: sphere, material: ball, size: {distribution: fixed, radius: 0.004}}
surfaces:
  - {name: floor, type: stl, file: floor.stl, material: ball}
factories:
  - {name: drop, particle_type: sphere, region: {type: box, min: [-0.05, -0.05, 0.0041], max: [0.05, 0.05, 0.03]}, count: 40}
)";
  World world = testing_support::start_world(parse_deck((folder / "deck.yaml").string()));
  sim::advance(world, 30000);  // 60 ms: the spheres land on the floor, wall contacts with history
  ASSERT_FALSE(world.wall_contacts.empty());
  const std::string checkpoint = (folder / "state.qck").string();
  sim::write_checkpoint(world, checkpoint, 0);
  // A changed mesh where the file still is: refused, naming it.
  write_stl_binary((folder / "floor.stl").string(), make_plane({0, 0, 0.001}, {0, 0, 1}, 0.2, 4));
  try {
    sim::read_checkpoint(checkpoint);
    ADD_FAILURE() << "a changed STL was not noticed";
  } catch (const UserError& e) {
    EXPECT_NE(e.diagnostics().format().find("floor.stl"), std::string::npos) << e.diagnostics().format();
  }
  // Deck and mesh gone, the checkpoint alone in another folder: it restores and continues.
  fs::remove(folder / "floor.stl");
  fs::remove(folder / "deck.yaml");
  const fs::path moved = folder / "elsewhere" / "state.qck";
  fs::create_directories(moved.parent_path());
  fs::rename(checkpoint, moved);
  sim::RestoredWorld restored = sim::read_checkpoint(moved.string());
  EXPECT_EQ(sim::state_hash(restored.world), sim::state_hash(world));
  sim::advance(world, 500);
  sim::advance(restored.world, 500);
  EXPECT_EQ(sim::state_hash(restored.world), sim::state_hash(world));
}

// The named sections of what is attached to a world (World::checkpoint_sections; a CFD-DEM run's
// fluid): written after the core state, given back by name to the same attachments made again
// on the restored world. A section nothing takes, an attachment with no section, content its
// load refuses or leaves unread: each an error naming the file, never a crash.
TEST(CheckpointSections, AreHandedBackByNameAndMismatchesAreRefused) {
  const auto attach_counter = [](World& world, const std::shared_ptr<std::uint64_t>& value, const std::string& name) {
    CheckpointSection section;
    section.name = name;
    section.save = [value](const World&, BinaryWriter& out) { out.value(*value); };
    section.load = [value](World&, BinaryReader& in) {
      *value = in.value<std::uint64_t>();
      if (*value > 1000) throw std::runtime_error("the counter is implausible");
    };
    world.checkpoint_sections.push_back(std::move(section));
  };
  World world = start_world(parse_deck(deck_path("tests/verification/05-determinism/deck.yaml")));
  attach_counter(world, std::make_shared<std::uint64_t>(41), "counter");
  const std::string bytes = sim::checkpoint_bytes(world, 0);
  const std::vector<sim::SavedSection> saved = sim::read_checkpoint_bytes(bytes, "sections.qck").sections;
  ASSERT_EQ(saved.size(), 1u);
  EXPECT_EQ(saved[0].name, "counter");
  const auto restore = [&](const std::vector<sim::SavedSection>& sections, const std::vector<std::string>& takers) {
    sim::RestoredWorld restored = sim::read_checkpoint_bytes(bytes, "sections.qck");
    auto value = std::make_shared<std::uint64_t>(0);
    for (const std::string& name : takers) attach_counter(restored.world, value, name);
    sim::restore_sections(restored.world, sections, "sections.qck");
    return *value;
  };
  EXPECT_EQ(restore(saved, {"counter"}), 41u);
  const auto expect_refused = [&](const std::vector<sim::SavedSection>& sections,
                                  const std::vector<std::string>& takers, const std::string& expected) {
    try {
      restore(sections, takers);
      ADD_FAILURE() << expected << ": restored";
    } catch (const UserError& e) {
      const std::string text = e.diagnostics().format();
      EXPECT_NE(text.find("sections.qck: error: cannot restore checkpoint: "), std::string::npos) << text;
      EXPECT_NE(text.find(expected), std::string::npos) << text;
    }
  };
  expect_refused(saved, {}, "it holds 'counter' state that nothing in this restart takes");
  expect_refused(saved, {"counter", "other"}, "it holds no 'other' state, which this restart needs");
  std::vector<sim::SavedSection> damaged = saved;
  damaged[0].bytes.resize(3);
  expect_refused(damaged, {"counter"}, "its 'counter' section: the file ends early");
  damaged = saved;
  damaged[0].bytes += "x";
  expect_refused(damaged, {"counter"}, "its 'counter' section: bytes remain after its last field");
  damaged = saved;
  damaged[0].bytes[7] = static_cast<char>(0x7f);
  expect_refused(damaged, {"counter"}, "its 'counter' section: the counter is implausible");
  // A world with no sections writes none; a section with a name twice is a bug of the caller.
  World plain = start_world(parse_deck(deck_path("tests/verification/05-determinism/deck.yaml")));
  EXPECT_TRUE(sim::read_checkpoint_bytes(sim::checkpoint_bytes(plain, 0), "plain.qck").sections.empty());
  attach_counter(plain, std::make_shared<std::uint64_t>(1), "twice");
  attach_counter(plain, std::make_shared<std::uint64_t>(2), "twice");
  EXPECT_THROW(sim::checkpoint_bytes(plain, 0), std::logic_error);
}

}  // namespace
}  // namespace quarry
