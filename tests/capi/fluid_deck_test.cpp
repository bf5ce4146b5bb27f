// A deck with a fluid: section through the C ABI (issue #16/#18): quarry_open attaches the
// built-in fluid as `quarry run` does, quarry_save_state / quarry_restore_state carry its state
// (a second handle restored from the first one's state steps to the same bits), a fluid state
// is refused by a handle without that fluid (a deck's structures: the same way:
// structure_deck_test.cpp). Nothing but quarry.h and libquarry.so.
#include <gtest/gtest.h>
#include <quarry/quarry.h>

#include <array>
#include <cstring>
#include <map>
#include <string>
#include <vector>

#include "capi/deck_handles.h"

namespace {

const std::string kFluidDeck = std::string(QUARRY_SOURCE_DIR) + "/tests/decks/fluid_restart.yaml";

using quarry_test::error_of;
using quarry_test::open_deck;
using quarry_test::particles_by_id;
using quarry_test::saved_state;

TEST(FluidDeckThroughTheAbi, RestoredStateStepsToTheSameBitsAsTheHandleItCameFrom) {
  quarry_sim first = open_deck(kFluidDeck);
  // 228 steps of 8 µs: inside a coupling interval of 5 steps, the particles in the fluid.
  ASSERT_EQ(quarry_advance(first, 228 * 8.0e-6, nullptr), QUARRY_OK) << error_of(first);
  const std::vector<char> state = saved_state(first);
  ASSERT_EQ(quarry_advance(first, 100 * 8.0e-6, nullptr), QUARRY_OK) << error_of(first);

  quarry_sim second = open_deck(kFluidDeck);
  ASSERT_EQ(quarry_restore_state(second, state.data(), state.size()), QUARRY_OK) << error_of(second);
  ASSERT_EQ(quarry_advance(second, 100 * 8.0e-6, nullptr), QUARRY_OK) << error_of(second);
  const auto a = particles_by_id(first), b = particles_by_id(second);
  ASSERT_EQ(a.size(), 40u);
  ASSERT_EQ(a.size(), b.size());
  for (const auto& [id, s] : a) {
    ASSERT_TRUE(b.count(id)) << id;
    EXPECT_EQ(std::memcmp(s.data(), b.at(id).data(), sizeof s), 0) << "particle " << id;
  }
  EXPECT_EQ(quarry_close(second), QUARRY_OK);

  // The fluid acts: the same state stepped by a handle whose deck has no fluid is refused
  // rather than run without it (its checkpoint holds the fluid's section, which nothing takes).
  quarry_sim dry = open_deck(std::string(QUARRY_SOURCE_DIR) + "/tests/decks/minimal.yaml");
  EXPECT_NE(quarry_restore_state(dry, state.data(), state.size()), QUARRY_OK);
  EXPECT_NE(error_of(dry).find("fluid"), std::string::npos) << error_of(dry);
  std::uint64_t count = 0;
  ASSERT_EQ(quarry_num_particles(dry, -1, &count), QUARRY_OK);  // left as it was
  EXPECT_EQ(quarry_close(dry), QUARRY_OK);
  EXPECT_EQ(quarry_close(first), QUARRY_OK);
}

}  // namespace
