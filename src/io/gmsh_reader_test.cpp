// Tests for the Gmsh MSH 4.1 reader: nodes, triangles and quadrangles in file order, 2-D
// physical groups as named element sets, parametric node coordinates, skipped curve elements,
// the length unit, and errors with line:column (the broken meshes are in tests/bad_models).
#include "io/gmsh_reader.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>

#include "io/bulk_data.h"

namespace quarry {
namespace {

std::filesystem::path source_dir() {
  const char* from_environment = std::getenv("QUARRY_SOURCE_DIR");
  return std::filesystem::path(from_environment ? from_environment : QUARRY_SOURCE_DIR);
}

// Two surfaces: surface 1 (physical "bed") holds a quadrangle; surface 2 (physical "lid" and
// also "bed") holds two triangles. Curve 1 (physical "edge") holds a line element. Coordinates
// in mm; the nodes of surface 2 are written with their parametric (u, v) coordinates.
const char* const kMesh = R"($MeshFormat
4.1 0 8
$EndMeshFormat
$Comments
made by hand for quarry's tests
$EndComments
$PhysicalNames
3
1 5 "edge"
2 1 "bed"
2 2 "lid"
$EndPhysicalNames
$Entities
0 1 2 0
1 0 0 0 100 0 0 1 5 2 1 -2
1 0 0 0 100 100 0 1 1 0
2 0 100 0 100 200 0 2 2 1 0
$EndEntities
$Nodes
2 6 1 6
2 1 0 4
1
2
3
4
0 0 0
100 0 0
100 100 0
0 100 0
2 2 1 2
5
6
100 200 0 0.5 1
0 200 0 0 1
$EndNodes
$Elements
3 4 1 12
1 1 1 1
10 1 2
2 1 3 1
1 1 2 3 4
2 2 2 2
11 4 3 5
12 4 5 6
$EndElements
)";

TEST(GmshReader, SurfaceMeshWithPhysicalGroups) {
  GmshReadOptions options;
  options.units = UnitSystem::mm_tonne_second;
  const StructureModel model = read_gmsh_string(kMesh, "plate.msh", options);
  EXPECT_EQ(model.declared_units, UnitSystem::mm_tonne_second);
  ASSERT_EQ(model.nodes.size(), 6u);
  EXPECT_EQ(model.nodes.at(3).position, (Vec3{0.1, 0.1, 0.0}));  // 100 mm
  EXPECT_EQ(model.nodes.at(5).position, (Vec3{0.1, 0.2, 0.0}));
  EXPECT_EQ(model.where(model.nodes.at(5).where).line, 33);

  ASSERT_EQ(model.shells.size(), 3u);  // the line element of the curve is skipped
  EXPECT_EQ(model.shells[0].id, 1);
  EXPECT_EQ(model.shells[0].shape, ShellShape::quad4);
  EXPECT_EQ(model.shells[0].nodes, (std::array<int, 4>{1, 2, 3, 4}));
  EXPECT_EQ(model.shells[0].property_id, 0);  // thickness and material come from the deck
  EXPECT_EQ(model.shells[2].id, 12);
  EXPECT_EQ(model.shells[2].shape, ShellShape::tria3);
  EXPECT_EQ(model.shells[2].nodes, (std::array<int, 4>{4, 5, 6, 0}));
  EXPECT_EQ(model.where(model.shells[2].where).line, 44);

  ASSERT_EQ(model.sets.size(), 2u);  // surface groups only
  EXPECT_EQ(model.sets.at(1).name, "bed");
  EXPECT_EQ(model.sets.at(1).kind, SetKind::element);
  EXPECT_EQ(model.sets.at(1).members, (std::vector<int>{1, 11, 12}));
  EXPECT_EQ(model.sets.at(2).name, "lid");
  EXPECT_EQ(model.sets.at(2).members, (std::vector<int>{11, 12}));

  const std::string notes = model.notes.format();
  EXPECT_NE(notes.find("plate.msh:39:1: note: 1 element of points and curves skipped"),
            std::string::npos)
      << notes;

  options.units = UnitSystem::si;
  EXPECT_EQ(read_gmsh_string(kMesh, "plate.msh", options).nodes.at(3).position,
            (Vec3{100.0, 100.0, 0.0}));
}

// tests/models/plate.msh is tests/models/plate_fixed.bdf meshed in Gmsh's words (coordinates in
// mm, the same node and element tags): both readers give the same nodes in m, the same shells,
// and the physical surface holds the elements of the bulk data's coupling SURF.
TEST(GmshReader, SameMeshAsTheBulkDataPlate) {
  GmshReadOptions options;
  options.units = UnitSystem::mm_tonne_second;
  const std::filesystem::path models = source_dir() / "tests" / "models";
  const StructureModel mesh = read_gmsh((models / "plate.msh").string(), options);
  const StructureModel bulk = read_bulk_data((models / "plate_fixed.bdf").string());

  ASSERT_EQ(mesh.nodes.size(), bulk.nodes.size());
  for (const auto& [id, node] : bulk.nodes) {
    ASSERT_TRUE(mesh.nodes.count(id)) << "node " << id;
    EXPECT_EQ(mesh.nodes.at(id).position, node.position) << "node " << id;
  }
  EXPECT_EQ(mesh.nodes.at(9).position, (Vec3{0.2, 0.2, 0.0}));  // 200 mm
  ASSERT_EQ(mesh.shells.size(), bulk.shells.size());
  for (std::size_t i = 0; i < bulk.shells.size(); ++i) {
    EXPECT_EQ(mesh.shells[i].id, bulk.shells[i].id);
    EXPECT_EQ(mesh.shells[i].shape, bulk.shells[i].shape);
    EXPECT_EQ(mesh.shells[i].nodes, bulk.shells[i].nodes);
  }
  ASSERT_EQ(mesh.sets.size(), 1u);  // the curve group "clamped" is not a surface
  const IdSet& coupling = mesh.sets.at(2);
  EXPECT_EQ(coupling.name, "coupling surface");  // a quoted name with a blank
  EXPECT_EQ(coupling.members, bulk.surfaces.at(2).elements);
  EXPECT_EQ(mesh.where(coupling.where).line, 7);
  EXPECT_NE(mesh.notes.format().find("plate.msh:40:1: note: 2 elements of points and curves "
                                     "skipped"),
            std::string::npos)
      << mesh.notes.format();
}

// A named physical group of points or curves is a node set (a deck's support names it): the
// plate's "clamped" edge, two lines along x = 0.
TEST(GmshReader, PhysicalGroupsOfCurvesAreNodeSets) {
  GmshReadOptions options;
  options.units = UnitSystem::mm_tonne_second;
  const StructureModel mesh =
      read_gmsh((source_dir() / "tests" / "models" / "plate.msh").string(), options);
  ASSERT_EQ(mesh.node_groups.size(), 1u);
  const IdSet& clamped = mesh.node_groups.front();
  EXPECT_EQ(clamped.name, "clamped");
  EXPECT_EQ(clamped.id, 7);
  EXPECT_EQ(clamped.kind, SetKind::grid);
  EXPECT_EQ(clamped.members, (std::vector<int>{1, 4, 7}));
  EXPECT_EQ(mesh.where(clamped.where).line, 6);
}

// A mesh cut after any character either reads or fails with a UserError; nothing else escapes.
TEST(GmshReader, EveryPrefixReadsOrFailsCleanly) {
  GmshReadOptions options;
  options.units = UnitSystem::si;
  const std::string text = kMesh;
  int refused = 0;
  for (std::size_t length = 0; length <= text.size(); ++length) {
    try {
      read_gmsh_string(text.substr(0, length), "cut.msh", options);
    } catch (const UserError& error) {
      ++refused;
      EXPECT_TRUE(error.diagnostics().has_errors()) << "cut at " << length;
    }
  }
  EXPECT_GT(refused, 0);
}

TEST(GmshReader, UnitsMustBeStated) {
  try {
    read_gmsh_string(kMesh, "plate.msh", GmshReadOptions{});
    FAIL() << "read";
  } catch (const UserError& error) {
    const std::string text = error.diagnostics().format();
    EXPECT_EQ(text.substr(0, text.find('\n')),
              "plate.msh:1:1: error: a Gmsh mesh does not say its length unit");
  }
}

TEST(GmshReader, ErrorsAtLineAndColumn) {
  GmshReadOptions options;
  options.units = UnitSystem::si;
  const auto first_error = [&](const std::string& text) {
    try {
      read_gmsh_string(text, "m.msh", options);
    } catch (const UserError& error) {
      const std::string all = error.diagnostics().format();
      return all.substr(0, all.find('\n'));
    }
    return std::string("no error");
  };
  std::string text = kMesh;
  EXPECT_EQ(first_error(text.replace(text.find("100 100 0\n0 100"), 3, "1OO")),
            "m.msh:28:1: error: expected a number (a node's x), got \"1OO\"");
  text = kMesh;
  EXPECT_EQ(first_error(text.replace(text.find("12 4 5 6"), 8, "11 4 5 6")),
            "m.msh:44:1: error: duplicate element tag 11");
  EXPECT_EQ(first_error("mesh"),
            "m.msh:1:1: error: expected a section such as $Nodes, got \"mesh\"");
  EXPECT_EQ(first_error("$Nodes\n0 0 0 0\n$EndNodes\n"),
            "m.msh:1:1: error: the file does not start with $MeshFormat");
}

}  // namespace
}  // namespace quarry
