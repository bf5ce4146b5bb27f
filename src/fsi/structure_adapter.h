// From the model an engineer wrote (StructureModel: bulk data or Gmsh, SI) to what the solvers
// take: the shell solver's ShellModel, and the EDEM coupling surface as a DEM mesh whose vertex k
// is one structural node (quads stay quads: the DEM contacts them as two triangles of one element
// and their loads go back to the quad's four nodes). Issue #17 §3.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/simulation_spec.h"
#include "core/structure_spec.h"
#include "fem/shell_model.h"

namespace quarry {
// core/structure_model.h; declared only, since its Surface (a SURF card) and geometry's Surface
// (a triangle mesh) share a name and cannot meet in one translation unit.
struct StructureModel;
}  // namespace quarry

namespace quarry::fsi {

struct AdapterOptions {
  // The SPC/SPC1 set id to apply; absent: the model's only set (none: no SPCs; several: an
  // error asking for one). GRID permanent constraints (PS) always apply.
  std::optional<int> constraint_set;
  int integration_points = 5;  // through the thickness (Lobatto), as fem::ShellSection
};

struct AdaptedStructure {
  fem::ShellModel model;
  std::vector<int> grid_id;     // per solver node: its GRID id (nodes sorted by id)
  std::vector<int> element_id;  // per solver element: its CQUAD4/CTRIA3 id (file order)
};

// Pre: `structure` came from a reader (references resolve). Throws UserError at the card for
// what the solver cannot represent: an element without a property (a Gmsh mesh needs the deck's
// thickness), a PSHELL that is a membrane (no MID2) or has a bending ratio 12I/T³ ≠ 1, a
// non-structural mass, different MID1/MID2/MID3 materials, a material with no density, a
// constraint set that does not exist or is ambiguous. Cost: O(model size · log).
AdaptedStructure adapt_structure(const StructureModel& structure, const AdapterOptions& options = {});

// The coupling surface's mesh in the DEM's terms: vertex k is solver node node_of_vertex[k]
// (ascending), triangles and quads in vertex indices, corners as the elements were written
// (their normals are the shells' normals).
struct CouplingMesh {
  std::vector<std::int32_t> node_of_vertex;
  std::vector<Vec3> vertices;  // m, the nodes' initial positions
  std::vector<std::array<std::uint32_t, 3>> triangles;
  std::vector<std::array<std::uint32_t, 4>> quads;
};

// The mesh of the SURFs `surface_ids` of `structure` together (their elements as adapted; an
// element in several of them once, in the order of the first; nodes they share once). Throws
// UserError for a surface id the model does not define.
CouplingMesh coupling_mesh(const StructureModel& structure, const AdaptedStructure& adapted,
                           const std::vector<int>& surface_ids);

// A DEM surface entry (type mesh, coupled) for `mesh`, named `name`, with DEM material
// `material` (the deck's equipment material: the seed's "first equipment material").
SurfaceSpec coupling_surface_spec(const CouplingMesh& mesh, const std::string& name,
                                  const std::string& material);

}  // namespace quarry::fsi

namespace quarry::fsi {

// What the coupling takes from a model file: the adapted structure, the mesh of the first EDEM
// card's COUPLING surfaces (the seed repeats the COUPLING line "to define multiple coupling
// surfaces", all of one DEM material: the DEM contacts them as one coupled surface), and that
// card's PERIOD and FILTER (absent: the seed's defaults, resolved against the run's end time by
// resolve_schedule).
struct CoupledStructure {
  AdaptedStructure adapted;
  CouplingMesh mesh;
  std::vector<int> surface_ids;     // the SURFs coupled, in the card's order
  std::vector<std::string> labels;  // their COUPLING lines' LABELs, or Quarry's default names
  std::optional<double> period, filter;  // s
};

// Pre: the model has an EDEM card (throws UserError otherwise). `surface_id`: the one SURF to
// couple (absent: every COUPLING surface of the card). Throws UserError as adapt_structure and
// coupling_mesh do.
CoupledStructure prepare_coupling(const StructureModel& structure, const AdapterOptions& options = {},
                                  std::optional<int> surface_id = std::nullopt);

// A Gmsh mesh (io/gmsh_reader.h) made the StructureModel that bulk data saying the same would
// give, from what its deck entry states (MeshStructureSpec): one section (PSHELL 1: thickness,
// MID1 = MID2 = MID3 = 1) and one material (MAT1 1, with MATS1 where yield_stress > 0) on
// every element, the supports as SPC set 1 (each box's nodes or each named group's of points
// or curves, DOFs 123456 clamped or 123 pinned), and an EDEM coupling (no PERIOD or FILTER:
// the deck's, or the seed's defaults) of the physical surface group `coupling_group`, labelled
// with its name. Throws UserError at the deck's key: a group the mesh has not (the hint lists
// those it has), a support holding no node; and read_gmsh's errors at the mesh's line and
// column. Cost: one read, O(nodes · supports).
StructureModel mesh_structure(const std::string& path, const MeshStructureSpec& spec);
// mesh_structure then prepare_coupling.
CoupledStructure read_coupled_mesh(const std::string& path, const MeshStructureSpec& spec,
                                   const AdapterOptions& options = {});

// read_bulk_data (io/bulk_data.h) then prepare_coupling: a file, or bulk data held in memory
// (tests) whose locations name `display_name`. Model units: the file's declaration.
CoupledStructure read_coupled_structure(const std::string& path, const AdapterOptions& options = {},
                                        std::optional<int> surface_id = std::nullopt);
CoupledStructure coupled_structure_from_text(const std::string& text, const std::string& display_name,
                                             const AdapterOptions& options = {});

}  // namespace quarry::fsi
