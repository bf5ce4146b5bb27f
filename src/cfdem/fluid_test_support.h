// Helpers shared by the fluid coupling's tests (test code only).
#pragma once

#include <string>

#include "cfdem/fluid_setup.h"
#include "core/diagnostics.h"
#include "io/deck.h"
#include "sim/world.h"

namespace quarry::cfdem::testing {

// The formatted errors of building the world and its fluid coupling from a deck held in memory
// (its locations name `file_name`), "" when both build.
inline std::string fluid_setup_errors(const std::string& deck, const std::string& file_name) {
  try {
    const World world = build_world(parse_deck_string(deck, file_name));
    coupling_options_from_spec(world);
  } catch (const UserError& e) {
    return e.diagnostics().format();
  }
  return {};
}

}  // namespace quarry::cfdem::testing
