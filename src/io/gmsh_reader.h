// Reader of Gmsh MSH 4.1 ASCII surface meshes, the open alternative to bulk data for a shell
// model: nodes, 3-node triangles and 4-node quadrangles, and each 2-D physical group as a named
// element set. Material and thickness are not in a mesh: the deck gives them (docs/fem.md).
#pragma once

#include <optional>
#include <string>

#include "core/structure_model.h"

namespace quarry {

struct GmshReadOptions {
  // The unit system of the coordinates (only the length matters: m for SI, mm for
  // mm_tonne_second). A .msh file does not say it, so it must be stated.
  std::optional<UnitSystem> units;
};

// Reads the mesh at `path` into a StructureModel in SI: nodes; every triangle (Gmsh type 2)
// and quadrangle (type 3) as a CTRIA3/CQUAD4-like shell with property_id 0, in file order;
// every physical group of dimension 2 as an IdSet of elements (id = the physical tag, name =
// its $PhysicalNames name, or empty). Elements of points and curves are skipped (noted).
// Throws UserError with `file:line:col: error: ...`: a format other than 4.1 ASCII, malformed
// sections, volume or higher-order surface elements, unknown or duplicate node and element
// tags, duplicate physical names, units not stated. Cost: one pass over the text.
StructureModel read_gmsh(const std::string& path, const GmshReadOptions& options);

// As read_gmsh, for mesh text held in memory: locations name `display_name`.
StructureModel read_gmsh_string(const std::string& text, const std::string& display_name,
                                const GmshReadOptions& options);

}  // namespace quarry
