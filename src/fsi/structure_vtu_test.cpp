// The structure's VTU frame: cells, types and arrays of the repository's bulk-data plate (3
// quads, 2 triangles), and a displacement that is the nodes' motion.
#include "fsi/structure_vtu.h"

#include <gtest/gtest.h>

#include <sstream>
#include <string>
#include <vector>

#include "fsi/structure_adapter.h"

namespace quarry::fsi {
namespace {

std::size_t count(const std::string& text, const std::string& word) {
  std::size_t n = 0;
  for (std::size_t at = text.find(word); at != std::string::npos; at = text.find(word, at + 1)) ++n;
  return n;
}

TEST(StructureVtu, CellsArraysAndDisplacement) {
  const CoupledStructure plate =
      read_coupled_structure(std::string(QUARRY_SOURCE_DIR) + "/tests/models/plate_free.bdf");
  fem::ShellSolver solver(plate.adapted.model);
  solver.set_velocity(8, Vec3{0, 0, 0.5}, Vec3{});  // grid 9, a free corner, moving up
  const double dt = 1e-7;                           // s, far below the stable step
  solver.step(dt);
  const std::string vtu = structure_vtu(solver, plate.adapted.model, {});
  EXPECT_NE(vtu.find("NumberOfPoints=\"9\" NumberOfCells=\"5\""), std::string::npos);
  EXPECT_EQ(count(vtu, "          9\n"), 3u);  // VTK_QUAD per CQUAD4
  EXPECT_EQ(count(vtu, "          5\n"), 2u);  // VTK_TRIANGLE per CTRIA3 (and no offset 5)
  EXPECT_NE(vtu.find("          18\n        </DataArray>"), std::string::npos);  // 3·4 + 2·3 corners
  for (const char* name : {"displacement", "velocity", "load", "von_mises_top", "von_mises_mid",
                           "von_mises_bottom", "plastic_strain"})
    EXPECT_EQ(count(vtu, std::string("Name=\"") + name + "\""), 1u) << name;
  // The corner moved up by about v·dt; the displacement array's last entry is that node's.
  const std::size_t start = vtu.find("Name=\"displacement\"");
  const std::size_t end = vtu.find("</DataArray>", start);
  const std::size_t body = vtu.find('\n', start) + 1;
  std::istringstream numbers(vtu.substr(body, end - body));
  std::vector<double> values;
  for (double v = 0.0; numbers >> v;) values.push_back(v);
  ASSERT_EQ(values.size(), 27u);
  const double uz = values.back();
  EXPECT_NEAR(uz, 0.5 * dt, 0.01 * 0.5 * dt);
}

}  // namespace
}  // namespace quarry::fsi
