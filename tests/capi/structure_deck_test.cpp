// A deck with a structures: section through the C ABI (issue #17): quarry_open attaches the
// built-in shells as `quarry run` does (the two-way coupling runs in the handle's steps),
// quarry_save_state / quarry_restore_state carry their state (a second handle restored from the
// first one's state steps to the same bits and writes the same structure monitors and frames
// into its output folder), and a structures state is refused by a handle without those
// structures, which is left as it was (and a state without them by a handle with them). Nothing but quarry.h and libquarry.so.
#include <gtest/gtest.h>
#include <quarry/quarry.h>
#include <unistd.h>

#include <array>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "capi/deck_handles.h"

namespace {

namespace fs = std::filesystem;

const std::string kStructureDeck = std::string(QUARRY_SOURCE_DIR) + "/tests/fsi/plate_restart.yaml";

using quarry_test::error_of;
using quarry_test::open_deck;
using quarry_test::particles_by_id;
using quarry_test::saved_state;

std::string file_text(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

TEST(StructureDeckThroughTheAbi, RestoredStateStepsToTheSameBitsAsTheHandleItCameFrom) {
  const fs::path folder = fs::temp_directory_path() / ("quarry-structure-abi-" + std::to_string(::getpid()));
  fs::remove_all(folder);
  const std::string first_out = (folder / "first").string(), second_out = (folder / "second").string();
  quarry_sim first = open_deck(kStructureDeck, first_out);
  // 117 steps of 31.15 µs: between two synchronisations (steps 116 and 119), the beads on the plate.
  ASSERT_EQ(quarry_step(first, 117), QUARRY_OK) << error_of(first);
  const std::vector<char> state = saved_state(first);
  ASSERT_EQ(quarry_step(first, 150), QUARRY_OK) << error_of(first);

  quarry_sim second = open_deck(kStructureDeck, second_out);
  ASSERT_EQ(quarry_restore_state(second, state.data(), state.size()), QUARRY_OK) << error_of(second);
  ASSERT_EQ(quarry_step(second, 150), QUARRY_OK) << error_of(second);
  const auto a = particles_by_id(first), b = particles_by_id(second);
  ASSERT_EQ(a.size(), 60u);
  ASSERT_EQ(a.size(), b.size());
  for (const auto& [id, s] : a) {
    ASSERT_TRUE(b.count(id)) << id;
    EXPECT_EQ(std::memcmp(s.data(), b.at(id).data(), sizeof s), 0) << "particle " << id;
  }
  EXPECT_EQ(quarry_close(second), QUARRY_OK);
  EXPECT_EQ(quarry_close(first), QUARRY_OK);
  // The structure's monitors (carried in the state, the last row written at close), its series
  // and its frames after the state's time: the same files in both folders.
  for (const char* name : {"structure_plate.csv", "structure_plate.pvd", "structure_plate_0003.vtu",
                           "structure_plate_0005.vtu"}) {
    const std::string expected = file_text(fs::path(first_out) / name);
    EXPECT_FALSE(expected.empty()) << name;
    EXPECT_EQ(file_text(fs::path(second_out) / name), expected) << name;
  }

  // A handle whose deck has no structures refuses the state (its structures section is
  // nothing it can take) rather than run without them, and is left as it was.
  quarry_sim bare = open_deck(std::string(QUARRY_SOURCE_DIR) + "/tests/decks/minimal.yaml");
  std::uint64_t before = 0, after = 0;
  ASSERT_EQ(quarry_num_particles(bare, -1, &before), QUARRY_OK);
  EXPECT_NE(quarry_restore_state(bare, state.data(), state.size()), QUARRY_OK);
  EXPECT_NE(error_of(bare).find("'structures'"), std::string::npos) << error_of(bare);
  ASSERT_EQ(quarry_num_particles(bare, -1, &after), QUARRY_OK);
  EXPECT_EQ(after, before);
  EXPECT_EQ(quarry_step(bare, 1), QUARRY_OK) << error_of(bare);
  // The other way round: a state without structures is refused by a handle that has them.
  const std::vector<char> bare_state = saved_state(bare);
  quarry_sim plated = open_deck(kStructureDeck);
  EXPECT_NE(quarry_restore_state(plated, bare_state.data(), bare_state.size()), QUARRY_OK);
  EXPECT_NE(error_of(plated).find("no 'structures' state"), std::string::npos) << error_of(plated);
  EXPECT_EQ(quarry_step(plated, 1), QUARRY_OK) << error_of(plated);
  EXPECT_EQ(quarry_close(plated), QUARRY_OK);
  EXPECT_EQ(quarry_close(bare), QUARRY_OK);
  fs::remove_all(folder);
}

}  // namespace
