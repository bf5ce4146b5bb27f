// Deck parser: reads a YAML simulation deck (docs/deck.md) into a SimulationSpec before any
// simulation exists. Every value keeps the line:column where the user wrote it, and every error
// of the deck is reported at once (unknown keys with "did you mean", ranges with units, names).
#pragma once

#include <string>
#include <vector>

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

// The periodic axes of `settings` against its domain and the particle types' sizes, as a deck's
// are checked (docs/deck.md, "Periodic boundaries"); also for a definition built without a deck
// (the C ABI checks each call's settings with it). Along each periodic axis the domain needs
// max > min (its period), and the period must be at least 3 × (2 R_max + skin) so that the
// neighbour search meets one image of a particle only (core/periodic_box.h, shortest_period;
// R_max over `types`, not checked while there is none or a type's sizes are themselves wrong).
// Each problem is an error at settings.periodic.where, with a hint.
void check_periodic_domain(const SimulationSettings& settings, const std::vector<ParticleTypeSpec>& types,
                           Diagnostics& problems);

// True if `name` can stand in a file name of the output folder (a surface's name names its output
// files): not empty, not starting with '.', and no '/', '\\' or control characters — so no name
// reaches outside the folder or hides its files.
bool usable_in_file_names(const std::string& name);

}  // namespace quarry
