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

}  // namespace
}  // namespace quarry::fsi
