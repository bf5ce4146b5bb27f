// Helpers for the verification tests: locate decks in the source tree, build worlds, step.
#pragma once

#include <cstdlib>
#include <string>

#include "io/deck.h"
#include "sim/step.h"
#include "sim/world.h"

namespace quarry::testing_support {

inline std::string source_dir() {
  if (const char* env = std::getenv("QUARRY_SOURCE_DIR")) return env;
  return QUARRY_SOURCE_DIR;
}

inline std::string deck_path(const std::string& relative) { return source_dir() + "/" + relative; }

// Builds the world of a deck and brings it to its initial state (what sim::run does first).
// threads > 0: that many threads for every loop, however few particles (threshold 0), so that
// even a small scene exercises the threaded paths.
inline World start_world(const SimulationSpec& spec, int threads = 0) {
  World world = build_world(spec);
  if (threads > 0) world.threading = Threading{threads, 0};
  sim::initialize(world);
  return world;
}

inline double total_mass(const World& world) {
  double m = 0.0;  // kg
  for (std::size_t i = 0; i < world.particles.size(); ++i) m += 1.0 / world.particles.inv_mass[i];
  return m;
}

}  // namespace quarry::testing_support
