// Readers of the deck's top-level sections (io/deck*.cpp only). Each checks its own keys,
// types and value ranges; names that refer across sections are checked in deck.cpp once
// every section has been read.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "core/simulation_spec.h"
#include "io/deck.h"
#include "io/deck_reader.h"

namespace quarry::deck_detail {

// deck_settings.cpp
void read_simulation_section(MapReader& root, SimulationSettings& settings);
void read_output_section(MapReader& root, OutputSpec& output);
void read_materials_section(MapReader& root, std::vector<MaterialSpec>& materials);
void read_interactions_section(MapReader& root, std::vector<InteractionSpec>& interactions);
void read_particle_types_section(MapReader& root, std::vector<ParticleTypeSpec>& particle_types);
// The optional `export:` section (FEM load export, issue 4).
void read_export_section(MapReader& root, ExportSpec& fem_export);

// deck_geometry.cpp; STL files are resolved against options.base_directory ("" = current
// folder) and must exist when options.require_files.
void read_surfaces_section(MapReader& root, const DeckParseOptions& options,
                           std::vector<SurfaceSpec>& surfaces);
void read_factories_section(MapReader& root, std::vector<FactorySpec>& factories);
void read_monitors_section(MapReader& root, std::vector<MonitorSpec>& monitors);

// deck_particles.cpp: the optional `particles:` section (issue #20); needs the particle types
// read before it. Files are resolved against options.base_directory and read (CSV or VTU
// frame) when options.require_files; their problems are reported at the file's line:col.
void read_particles_section(MapReader& root, const DeckParseOptions& options, SimulationSpec& spec);

// deck_settings.cpp: one support, {name, box: {min, max}, fix: clamped|pinned} (the CalculiX
// export's), or with `groups` (a Gmsh structure's) {name, group: NAME, fix} in place of the box.
SupportSpec read_support(MapReader& map, bool groups);

// deck_structures.cpp: the optional `structures:` section (two-way shell coupling, issue #17);
// needs the materials, surfaces and end time read before it (names and PERIOD are checked).
void read_structures_section(MapReader& root, const DeckParseOptions& options, const SimulationSpec& spec,
                             std::vector<StructureSpec>& structures);

// deck_fluid.cpp: the optional `fluid:` section (CFD-DEM, issue #18); a UDF library's path is
// resolved against options.base_directory.
void read_fluid_section(MapReader& root, const DeckParseOptions& options,
                        std::optional<FluidSpec>& fluid);
// The section as the deck writer writes it (every key, defaults included), ending in a newline.
std::string fluid_section_text(const FluidSpec& fluid);

// The map behind each element of a list-valued key: `what` names an element in messages.
// Null elements (a bare "-") are reported; their location falls back to the list's key.
std::vector<MapReader> list_of_maps(MapReader& parent, const std::string& key,
                                    const std::string& what);

}  // namespace quarry::deck_detail
