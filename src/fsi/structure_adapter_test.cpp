// StructureModel → ShellModel and the coupling mesh: the repository's bulk-data plate (3 quads, 2
// triangles, mm–t–s) and a generated plate, read, adapted, solved; and the model errors.
#include "fsi/structure_adapter.h"

#include <gtest/gtest.h>

#include <string>

#include "core/structure_model.h"
#include "fem/shell_solver.h"
#include "fsi/plate_bulk_data.h"
#include "io/atomic_file.h"
#include "io/bulk_data.h"

namespace quarry::fsi {
namespace {

StructureModel read_test_plate() {
  return read_bulk_data(std::string(QUARRY_SOURCE_DIR) + "/tests/models/plate_free.bdf");
}

TEST(StructureAdapter, BulkDataPlateToShellModel) {
  const StructureModel structure = read_test_plate();
  const AdaptedStructure adapted = adapt_structure(structure);
  const fem::ShellModel& model = adapted.model;
  ASSERT_EQ(model.nodes.size(), 9u);
  EXPECT_EQ(adapted.grid_id, (std::vector<int>{1, 2, 3, 4, 5, 6, 7, 8, 9}));
  EXPECT_EQ(model.nodes[8], (Vec3{0.2, 0.2, 0.0}));  // mm → m by the reader
  ASSERT_EQ(model.elements.size(), 5u);
  EXPECT_EQ(model.elements[1].node_count, 4);  // CQUAD4 2: grids 2 3 6 5
  EXPECT_EQ(model.elements[1].nodes, (std::array<std::int32_t, 4>{1, 2, 5, 4}));
  EXPECT_EQ(model.elements[3].node_count, 3);  // CTRIA3 4: grids 4 5 8
  EXPECT_EQ((std::array<std::int32_t, 3>{model.elements[3].nodes[0], model.elements[3].nodes[1],
                                         model.elements[3].nodes[2]}),
            (std::array<std::int32_t, 3>{3, 4, 7}));
  ASSERT_EQ(model.sections.size(), 1u);
  EXPECT_DOUBLE_EQ(model.sections[0].thickness, 0.005);
  ASSERT_EQ(model.materials.size(), 1u);
  const fem::ShellMaterial& steel = model.materials[0];
  EXPECT_DOUBLE_EQ(steel.youngs_modulus, 2.1e11);  // 2.1e5 MPa
  EXPECT_DOUBLE_EQ(steel.poisson_ratio, 0.3);
  EXPECT_DOUBLE_EQ(steel.density, 7850.0);          // 7.85e-9 t/mm³
  EXPECT_DOUBLE_EQ(steel.yield_stress, 250e6);      // MATS1 LIMIT1 250 MPa
  EXPECT_DOUBLE_EQ(steel.hardening_modulus, 1e9);   // MATS1 H 1000 MPa
  // SPC1 set 1: grids 1, 4, 7 clamped; SPC set 1: grid 3 in z.
  ASSERT_EQ(model.boundary_conditions.size(), 2u);
  EXPECT_EQ(model.boundary_conditions[0].nodes, (std::vector<std::int32_t>{0, 3, 6}));
  EXPECT_EQ(model.boundary_conditions[0].dofs, fem::dof::all);
  EXPECT_EQ(model.boundary_conditions[1].nodes, (std::vector<std::int32_t>{2}));
  EXPECT_EQ(model.boundary_conditions[1].dofs, fem::dof::uz);
  // The solver accepts it as is.
  fem::ShellSolver solver(model);
  EXPECT_GT(solver.stable_time_step().time_step, 0.0);
}

TEST(StructureAdapter, CouplingSurfaceKeepsQuadsAndNodes) {
  StructureModel structure = read_test_plate();
  const AdaptedStructure adapted = adapt_structure(structure);
  const CouplingMesh all = coupling_mesh(structure, adapted, {2});
  EXPECT_EQ(all.node_of_vertex, (std::vector<std::int32_t>{0, 1, 2, 3, 4, 5, 6, 7, 8}));
  ASSERT_EQ(all.quads.size(), 3u);
  ASSERT_EQ(all.triangles.size(), 2u);
  EXPECT_EQ(all.quads[1], (std::array<std::uint32_t, 4>{1, 2, 5, 4}));
  // A part of the plate: CQUAD4 2 (nodes 1 2 5 4) and CTRIA3 4 (nodes 3 4 7): six vertices,
  // renumbered, each knowing its node.
  structure.surfaces.at(2).elements = {2, 4};
  const CouplingMesh part = coupling_mesh(structure, adapted, {2});
  EXPECT_EQ(part.node_of_vertex, (std::vector<std::int32_t>{1, 2, 3, 4, 5, 7}));
  ASSERT_EQ(part.quads.size(), 1u);
  EXPECT_EQ(part.quads[0], (std::array<std::uint32_t, 4>{0, 1, 4, 3}));
  ASSERT_EQ(part.triangles.size(), 1u);
  EXPECT_EQ(part.triangles[0], (std::array<std::uint32_t, 3>{2, 3, 5}));
  EXPECT_EQ(part.vertices[5], adapted.model.nodes[7]);
  const SurfaceSpec spec = coupling_surface_spec(part, "bed", "steel");
  EXPECT_TRUE(spec.coupled.value);
  EXPECT_EQ(spec.kind.value, SurfaceKind::mesh);
  EXPECT_EQ(spec.mesh_quads.size(), 1u);
  EXPECT_THROW(coupling_mesh(structure, adapted, {3}), UserError);
}

// The seed's EDEM card repeats its COUPLING line "to define multiple coupling surfaces"; they
// share the card's one DEM material, so the DEM contacts them as one coupled surface: the union
// of their elements (an element in two SURFs once) over their nodes (shared ones once). The
// test plate split into SURF 2 (CQUAD4 1, 2, CTRIA3 5) and SURF 3 (CQUAD4 2, 3, CTRIA3 4):
// CQUAD4 2 is in both. `surface:` (the deck's) still picks one.
TEST(StructureAdapter, EveryCouplingSurfaceOfTheCardIsCoupled) {
  std::string bulk = read_file(std::string(QUARRY_SOURCE_DIR) + "/tests/models/plate_free.bdf").value_or("");
  const auto replace = [&](const std::string& from, const std::string& to) {
    ASSERT_NE(bulk.find(from), std::string::npos) << from;
    bulk.replace(bulk.find(from), from.size(), to);
  };
  replace("SURF,2,ELFACE\n,1\n,2\n,3\n,4\n,5\n", "SURF,2,ELFACE\n,1\n,2\n,5\nSURF,3,ELFACE\n,2\n,3\n,4\n");
  replace("COUPLING,SURF,2,Surf_2\n", "COUPLING,SURF,2,floor\n,COUPLING,SURF,3\n");
  const StructureModel structure = read_bulk_data_string(bulk, "two_surfaces.bdf");
  const CoupledStructure both = prepare_coupling(structure);
  EXPECT_EQ(both.surface_ids, (std::vector<int>{2, 3}));
  EXPECT_EQ(both.labels, (std::vector<std::string>{"floor", default_coupling_label(100, 3)}));
  EXPECT_EQ(both.mesh.node_of_vertex, (std::vector<std::int32_t>{0, 1, 2, 3, 4, 5, 6, 7, 8}));
  ASSERT_EQ(both.mesh.quads.size(), 3u);      // CQUAD4 1, 2 (from SURF 2), 3
  ASSERT_EQ(both.mesh.triangles.size(), 2u);  // CTRIA3 5, 4
  EXPECT_EQ(both.mesh.quads[1], (std::array<std::uint32_t, 4>{1, 2, 5, 4}));
  EXPECT_EQ(both.mesh.triangles[0], (std::array<std::uint32_t, 3>{3, 7, 6}));  // CTRIA3 5: grids 4 8 7
  const CoupledStructure lid = prepare_coupling(structure, {}, 3);
  EXPECT_EQ(lid.surface_ids, (std::vector<int>{3}));
  EXPECT_EQ(lid.mesh.quads.size(), 2u);
  EXPECT_EQ(lid.mesh.triangles.size(), 1u);
  EXPECT_EQ(lid.mesh.node_of_vertex, (std::vector<std::int32_t>{1, 2, 3, 4, 5, 7, 8}));
}

std::string first_error(const std::string& bulk, const AdapterOptions& options = {}) {
  try {
    adapt_structure(read_bulk_data_string(bulk, "model.bdf"), options);
  } catch (const UserError& e) {
    return e.diagnostics().all().front().message;
  }
  return "no error";
}

TEST(StructureAdapter, ModelsTheSolverCannotRunAreRefused) {
  const std::string plate = testing::plate_bulk_data({.divisions = 2});
  EXPECT_EQ(first_error(plate), "no error");
  const auto replace = [&](const std::string& from, const std::string& to) {
    std::string s = plate;
    s.replace(s.find(from), from.size(), to);
    return s;
  };
  const std::string pshell = "PSHELL,1,1," + testing::bulk_real(0.001);
  EXPECT_NE(first_error(replace(pshell + ",1,,1", pshell)).find("no MID2"), std::string::npos);
  EXPECT_NE(first_error(testing::plate_bulk_data({.divisions = 2, .density = 0.0})).find("no density"),
            std::string::npos);
  EXPECT_NE(first_error(plate, {.constraint_set = 7}).find("constraint set 7 is not in the model"), std::string::npos);
  EXPECT_NE(first_error(replace("SPC1,1,123456,1\n", "SPC1,1,123456,1\nSPC1,2,3,5\n")).find("2 SPC sets"),
            std::string::npos);
  EXPECT_EQ(first_error(replace("SPC1,1,123456,1\n", "SPC1,1,123456,1\nSPC1,2,3,5\n"), {.constraint_set = 2}),
            "no error");
}

// The formatted diagnostics of the UserError that `read` throws ("no error" if none): the
// messages with their file:line:column.
template <class F>
std::string formatted_error(F read) {
  try {
    read();
  } catch (const UserError& e) {
    return e.diagnostics().format();
  }
  return "no error";
}

// An element the solver cannot integrate (a bow-tie quad, corners on one line) is a user error
// at its card, file:line:column with the card echoed, not the solver's internal check: the
// fuzzing of a plate's bulk data (2026-12-07) stopped `quarry check` with exit code 4 there.
TEST(StructureAdapter, MisshapenElementsAreReportedAtTheirCards) {
  const std::string plate = testing::plate_bulk_data({.divisions = 2});  // grid (i, j): 3j + i + 1
  const auto replace_line = [](std::string s, const std::string& start, const std::string& line) {
    const std::size_t at = s.find(start);
    s.replace(at, s.find('\n', at) - at, line);
    return s;
  };
  // Element 1 is grids 1, 2, 5, 4 around (0, 0)–(30, 30) mm; grid 5 pulled in to (6, 6) mm makes
  // it a dart, re-entrant there (its neighbours stay convex).
  const std::string dart = replace_line(plate, "GRID,5,", "GRID,5,,0.006,0.006,0.");
  EXPECT_EQ(first_error(dart).rfind("shell element 1 (quadrilateral) is not convex at grid 5", 0),
            0u)
      << first_error(dart);
  // Listed 1, 2, 4, 5 it crosses itself: a bow-tie, whose two halves' areas cancel.
  const std::string bow_tie = replace_line(plate, "CQUAD4,1,", "CQUAD4,1,1,1,2,4,5");
  EXPECT_EQ(first_error(bow_tie).rfind("shell element 1 (quadrilateral) is degenerate: area 0", 0),
            0u)
      << first_error(bow_tie);
  // Grids 4 and 5 moved onto the line y = 0 of grids 1 and 2: element 1 has no area.
  const std::string flat = replace_line(replace_line(plate, "GRID,5,", "GRID,5,,0.02,0.,0."),
                                        "GRID,4,", "GRID,4,,0.01,0.,0.");
  EXPECT_EQ(first_error(flat).rfind("shell element 1 (quadrilateral) is degenerate: area 0", 0), 0u)
      << first_error(flat);
  // Where: the card's first line, column 1 (its name).
  const std::string text =
      formatted_error([&] { adapt_structure(read_bulk_data_string(dart, "model.bdf"), {}); });
  EXPECT_EQ(text.rfind("model.bdf:12:1: error: shell element 1", 0), 0u) << text;
}

}  // namespace
}  // namespace quarry::fsi

namespace quarry::fsi {
namespace {

// tests/models/plate.msh is tests/models/plate_fixed.bdf's mesh (GmshReader.
// SameMeshAsTheBulkDataPlate); its deck entry states what the bulk data's cards say.
MeshStructureSpec plate_mesh_entry() {
  MeshStructureSpec entry;
  entry.units = MeshLengthUnit::millimetre;
  entry.thickness = 0.005;         // PSHELL T 5 mm
  entry.youngs_modulus = 2.1e11;   // MAT1 E 2.1e5 MPa
  entry.poisson_ratio = 0.3;
  entry.density = 7850.0;          // RHO 7.85e-9 t/mm³
  entry.yield_stress = 2.5e8;      // MATS1 LIMIT1 250 MPa
  entry.hardening_modulus = 1.0e9; // MATS1 H 1000 MPa
  entry.coupling_group = std::string("coupling surface");
  SupportSpec edge;                // SPC1 123456 on grids 1, 4, 7: the edge x = 0
  edge.name = std::string("edge");
  edge.min = Vec3{0.0, 0.0, 0.0};
  edge.max = Vec3{0.0, 0.2, 0.0};
  entry.supports.push_back(edge);
  return entry;
}

std::string models_dir() { return std::string(QUARRY_SOURCE_DIR) + "/tests/models/"; }


// A Gmsh mesh with its deck entry gives the solver the same model and coupling surface as the
// bulk data that says the same: the run is then the same run (one code path from here on).
TEST(StructureAdapter, GmshMeshAsTheBulkDataPlate) {
  std::string bulk = read_file(models_dir() + "plate_fixed.bdf").value();
  const std::string lone_spc = "SPC     1       3       3       0.\n";  // no box picks DOF 3 alone
  ASSERT_NE(bulk.find(lone_spc), std::string::npos);
  bulk.erase(bulk.find(lone_spc), lone_spc.size());
  const CoupledStructure from_bulk = coupled_structure_from_text(bulk, "plate_fixed.bdf");
  const CoupledStructure from_mesh =
      read_coupled_mesh(models_dir() + "plate.msh", plate_mesh_entry());

  const fem::ShellModel &a = from_bulk.adapted.model, &b = from_mesh.adapted.model;
  ASSERT_EQ(a.nodes.size(), b.nodes.size());
  for (std::size_t n = 0; n < a.nodes.size(); ++n) EXPECT_EQ(a.nodes[n], b.nodes[n]) << n;
  ASSERT_EQ(a.elements.size(), b.elements.size());
  for (std::size_t e = 0; e < a.elements.size(); ++e) {
    EXPECT_EQ(a.elements[e].nodes, b.elements[e].nodes) << e;
    EXPECT_EQ(a.elements[e].node_count, b.elements[e].node_count) << e;
    EXPECT_EQ(a.elements[e].section, b.elements[e].section) << e;
  }
  ASSERT_EQ(a.sections.size(), 1u);
  ASSERT_EQ(b.sections.size(), 1u);
  EXPECT_DOUBLE_EQ(a.sections[0].thickness, b.sections[0].thickness);
  EXPECT_EQ(a.sections[0].integration_points, b.sections[0].integration_points);
  ASSERT_EQ(a.materials.size(), 1u);
  ASSERT_EQ(b.materials.size(), 1u);
  // The bulk data's values pass through the mm–t–s conversion: equal to the last bits or so.
  EXPECT_DOUBLE_EQ(a.materials[0].youngs_modulus, b.materials[0].youngs_modulus);
  EXPECT_DOUBLE_EQ(a.materials[0].poisson_ratio, b.materials[0].poisson_ratio);
  EXPECT_DOUBLE_EQ(a.materials[0].density, b.materials[0].density);
  EXPECT_DOUBLE_EQ(a.materials[0].yield_stress, b.materials[0].yield_stress);
  EXPECT_DOUBLE_EQ(a.materials[0].hardening_modulus, b.materials[0].hardening_modulus);
  ASSERT_EQ(a.boundary_conditions.size(), b.boundary_conditions.size());
  for (std::size_t c = 0; c < a.boundary_conditions.size(); ++c) {
    EXPECT_EQ(a.boundary_conditions[c].nodes, b.boundary_conditions[c].nodes) << c;
    EXPECT_EQ(a.boundary_conditions[c].dofs, b.boundary_conditions[c].dofs) << c;
  }
  EXPECT_EQ(from_bulk.mesh.node_of_vertex, from_mesh.mesh.node_of_vertex);
  EXPECT_EQ(from_bulk.mesh.vertices, from_mesh.mesh.vertices);
  EXPECT_EQ(from_bulk.mesh.triangles, from_mesh.mesh.triangles);
  EXPECT_EQ(from_bulk.mesh.quads, from_mesh.mesh.quads);
  EXPECT_EQ(from_mesh.surface_ids, (std::vector<int>{2}));  // the group's physical tag
  EXPECT_EQ(from_mesh.labels, (std::vector<std::string>{"coupling surface"}));
  // No PERIOD or FILTER: the deck's, or the seed's defaults.
  EXPECT_FALSE(from_mesh.period || from_mesh.filter);
}

// A support naming the mesh's physical group of curves "clamped" (the edge x = 0) holds the
// same nodes as the box around that edge.
TEST(StructureAdapter, GmshSupportByGroupAsByBox) {
  MeshStructureSpec by_group = plate_mesh_entry();
  by_group.supports[0].group = std::string("clamped");
  const StructureModel group = mesh_structure(models_dir() + "plate.msh", by_group);
  const StructureModel box = mesh_structure(models_dir() + "plate.msh", plate_mesh_entry());
  ASSERT_EQ(group.constraints.size(), 1u);
  ASSERT_EQ(box.constraints.size(), 1u);
  EXPECT_EQ(group.constraints[0].nodes, (std::vector<int>{1, 4, 7}));
  EXPECT_EQ(group.constraints[0].nodes, box.constraints[0].nodes);
  EXPECT_EQ(group.constraints[0].dofs, box.constraints[0].dofs);
}

// What the entry names and the mesh has not is refused at the entry's key.
TEST(StructureAdapter, GmshEntryErrorsAtTheDecksKeys) {
  const std::string path = models_dir() + "plate.msh";
  MeshStructureSpec entry = plate_mesh_entry();
  entry.coupling_group = Located<std::string>{"floor", {"deck.yaml", 12, 21}};
  std::string text = formatted_error([&] { mesh_structure(path, entry); });
  EXPECT_EQ(text.rfind("deck.yaml:12:21: error: the mesh", 0), 0u) << text;
  EXPECT_NE(text.find("has no physical surface group \"floor\""), std::string::npos) << text;
  EXPECT_NE(text.find("its surface groups: \"coupling surface\""), std::string::npos) << text;
  entry = plate_mesh_entry();
  entry.supports[0].name.where = {"deck.yaml", 14, 9};
  entry.supports[0].min = Vec3{1.0, 0.0, 0.0};  // m: beyond the 0.2 m plate
  entry.supports[0].max = Vec3{1.0, 0.2, 0.0};
  text = formatted_error([&] { mesh_structure(path, entry); });
  EXPECT_EQ(text.rfind("deck.yaml:14:9: error: support \"edge\" holds no node", 0), 0u) << text;
  entry = plate_mesh_entry();
  entry.supports[0].group = Located<std::string>{"clamp", {"deck.yaml", 14, 30}};
  text = formatted_error([&] { mesh_structure(path, entry); });
  EXPECT_EQ(text.rfind("deck.yaml:14:30: error: the mesh", 0), 0u) << text;
  EXPECT_NE(text.find("its groups of points and curves: \"clamped\""), std::string::npos) << text;
  // Read as metres, the 200 mm plate is 200 m wide: the 0.2 m box holds only the node at 0.
  entry = plate_mesh_entry();
  entry.units = MeshLengthUnit::metre;
  const StructureModel metres = mesh_structure(path, entry);
  ASSERT_EQ(metres.constraints.size(), 1u);
  EXPECT_EQ(metres.constraints[0].nodes, (std::vector<int>{1}));
}

}  // namespace
}  // namespace quarry::fsi
