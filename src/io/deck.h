// Deck parser: reads a YAML simulation deck (docs/deck.md) into a SimulationSpec before any
// simulation exists. Every value keeps the line:column where the user wrote it, and every error
// of the deck is reported at once (unknown keys with "did you mean", ranges with units, names).
#pragma once

#include <string>

#include "core/simulation_spec.h"

namespace quarry {

// Reads the deck file at `path` and returns the complete specification.
// Locations in the spec and in errors name the file as `path` was given; STL files are
// resolved relative to the deck's folder and stored as absolute paths in SurfaceSpec::file.
// Throws UserError carrying every error found (syntax, unknown keys and enum values, wrong
// types, missing required keys, out-of-range values, unknown or duplicate names, missing
// material interactions, missing STL files); never returns a partially filled spec.
// Cost: one pass over the YAML tree plus one filesystem lookup per STL surface.
SimulationSpec parse_deck(const std::string& path);

// As parse_deck, for YAML held in memory (tests, the C ABI): locations name `display_name`,
// STL files are resolved relative to the current working directory.
SimulationSpec parse_deck_string(const std::string& yaml_text, const std::string& display_name);

// How a deck held in memory finds its STL files, e.g. when a checkpoint's deck text is read
// back far from where the deck once was.
struct DeckParseOptions {
  // Folder that relative STL paths start at; empty = the current working directory.
  std::string base_directory;
  // false: an STL file that does not exist is not an error (the caller supplies the meshes);
  // its path is still resolved and stored absolute.
  bool require_files = true;
};

// As parse_deck_string, with STL paths resolved and checked as `options` say.
SimulationSpec parse_deck_string(const std::string& yaml_text, const std::string& display_name,
                                 const DeckParseOptions& options);

// True if `name` can stand in a file name of the output folder (a surface's name names its output
// files): not empty, not starting with '.', and no '/', '\\' or control characters — so no name
// reaches outside the folder or hides its files.
bool usable_in_file_names(const std::string& name);

}  // namespace quarry
