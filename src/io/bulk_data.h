// Reader of OptiStruct/Nastran bulk data for coupled shell models: GRID, CQUAD4, CTRIA3,
// PSHELL, MAT1, MATS1, SPC, SPC1, SET, SURF, the OptiStruct EDEM card and the unit declaration
// (UNITS, DTI,UNITS), in fixed, large-field and free format, into a StructureModel in SI units.
// Cards, fields, units rule and refused cards: docs/fem.md, "Models in".
#pragma once

#include <optional>
#include <string>

#include "core/structure_model.h"

namespace quarry {

struct BulkDataOptions {
  // The unit system stated outside the model (the deck), for a model that does not declare
  // its own. A model that declares units must agree with it.
  std::optional<UnitSystem> units;
};

// Reads the model file at `path` and the files it INCLUDEs (relative to the including file's
// folder). Locations in errors and in the model name the files as `path` and the INCLUDE lines
// give them.
// Pre: none. Post: every supported card is in the returned model, converted to SI; every
// reference (element -> grid and property, property -> material, MATS1 -> MAT1, SET/SURF ->
// grids and elements, SPC -> grids, EDEM -> SURF) resolves; ignored cards are listed in
// model.notes. Throws UserError carrying every error found, in reading order (`file:line:col:
// error: ...`): unreadable fields, unsupported or unknown cards, duplicate ids, missing
// references, a model whose units are not known. Never returns a partial model.
// Cost: one pass over the text, O(n log n) in the number of cards for the id maps.
StructureModel read_bulk_data(const std::string& path, const BulkDataOptions& options = {});

// As read_bulk_data, for bulk data held in memory (tests): locations name `display_name`;
// INCLUDEd files are looked for relative to display_name's folder.
StructureModel read_bulk_data_string(const std::string& text, const std::string& display_name,
                                     const BulkDataOptions& options = {});

// Quarry's name for a coupling surface whose LABEL is blank (the EDEM card, seed 000, makes
// LABEL optional and gives no default): "coupling_<edem id>_interface_<surface id>".
std::string default_coupling_label(int edem_id, int surface_id);

}  // namespace quarry
