// Helpers of the C ABI tests that open a deck's handle and compare two handles: the last error's
// text, opening a deck (optionally with an output folder), a handle's saved state, and every
// particle's position and velocity by id (engine orders may differ between handles).
#pragma once

#include <gtest/gtest.h>
#include <quarry/quarry.h>

#include <array>
#include <cstdint>
#include <cstring>
#include <map>
#include <string>
#include <vector>

namespace quarry_test {

inline std::string error_of(quarry_sim sim) {
  char text[2048] = {0};
  quarry_last_error(sim, text, sizeof text, nullptr);
  return text;
}

inline quarry_sim open_deck(const std::string& deck, const std::string& output = {}) {
  quarry_open_info info = QUARRY_OPEN_INFO_INIT;
  info.deck_path = deck.c_str();
  if (!output.empty()) info.output_directory = output.c_str();
  quarry_sim sim{};
  EXPECT_EQ(quarry_open(&info, &sim), QUARRY_OK) << error_of(QUARRY_NO_SIM);
  return sim;
}

inline std::vector<char> saved_state(quarry_sim sim) {
  std::uint64_t needed = 0;
  EXPECT_EQ(quarry_save_state(sim, nullptr, 0, &needed), QUARRY_OK);
  std::vector<char> state(needed);
  EXPECT_EQ(quarry_save_state(sim, state.data(), state.size(), &needed), QUARRY_OK) << error_of(sim);
  return state;
}

// Position and velocity (x, y, z, vx, vy, vz) of every particle, by id.
inline std::map<std::uint64_t, std::array<double, 6>> particles_by_id(quarry_sim sim) {
  quarry_view ids{}, x{}, v{};
  EXPECT_EQ(quarry_view_particles(sim, QUARRY_FIELD_ID, &ids), QUARRY_OK);
  EXPECT_EQ(quarry_view_particles(sim, QUARRY_FIELD_POSITION, &x), QUARRY_OK);
  EXPECT_EQ(quarry_view_particles(sim, QUARRY_FIELD_VELOCITY, &v), QUARRY_OK);
  std::map<std::uint64_t, std::array<double, 6>> out;
  for (std::uint64_t k = 0; k < ids.count; ++k) {
    std::uint64_t id = 0;
    std::memcpy(&id, static_cast<const char*>(ids.data) + k * ids.stride, sizeof id);
    std::array<double, 6> s{};
    std::memcpy(s.data(), static_cast<const char*>(x.data) + k * x.stride, 3 * sizeof(double));
    std::memcpy(s.data() + 3, static_cast<const char*>(v.data) + k * v.stride, 3 * sizeof(double));
    out[id] = s;
  }
  return out;
}

}  // namespace quarry_test
