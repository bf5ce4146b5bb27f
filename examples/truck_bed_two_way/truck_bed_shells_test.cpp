// Checks examples/truck_bed_two_way/truck_bed_shells.bdf, the steel bed of the two-way
// flagship, against what its README and deck say: the same tipper body as the rigid flagship
// (panel areas in closed form, truck_bed_areas.h), one conforming shell mesh open only along the
// rims, normals into the bed, a 4 mm floor and 3 mm walls of S355 steel, the floor pinned over
// the two chassis rails, every element coupled by the EDEM card, and elements about a coarse
// particle's diameter with the stable step that follows from them.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "fem/shell_solver.h"
#include "fsi/structure_adapter.h"
#include "io/bulk_data.h"
#include "../truck_bed/truck_bed_areas.h"

namespace quarry::fsi {
namespace {

std::string model_path() {
  const char* source = std::getenv("QUARRY_SOURCE_DIR");
  return std::string(source ? source : QUARRY_SOURCE_DIR) + "/examples/truck_bed_two_way/truck_bed_shells.bdf";
}

double quad_area(const fem::ShellModel& model, const fem::ShellElement& e) {  // m², planar quad
  const auto x = [&](int i) { return model.nodes[static_cast<std::size_t>(e.nodes[static_cast<std::size_t>(i)])]; };
  return 0.5 * norm(cross(x(2) - x(0), x(3) - x(1)));
}

class TruckBedShells : public testing::Test {
 protected:
  static void SetUpTestSuite() { bed_ = new CoupledStructure(prepare_coupling(read_bulk_data(model_path()))); }
  static void TearDownTestSuite() { delete bed_; }
  static CoupledStructure* bed_;
  const fem::ShellModel& model() const { return bed_->adapted.model; }
};
CoupledStructure* TruckBedShells::bed_ = nullptr;

TEST_F(TruckBedShells, SteelSectionsAndTheEdemCard) {
  ASSERT_EQ(model().materials.size(), 1u);
  const fem::ShellMaterial& steel = model().materials[0];
  EXPECT_EQ(steel.youngs_modulus, 2.1e11);  // Pa: real steel, not the DEM's scaled contact stiffness
  EXPECT_EQ(steel.poisson_ratio, 0.3);
  EXPECT_EQ(steel.density, 7850.0);
  EXPECT_EQ(steel.yield_stress, 355e6);  // S355
  ASSERT_EQ(model().sections.size(), 2u);
  EXPECT_EQ(model().sections[0].thickness, 0.004);  // floor
  EXPECT_EQ(model().sections[1].thickness, 0.003);  // walls
  ASSERT_TRUE(bed_->period.has_value());
  EXPECT_EQ(*bed_->period, 2.0e-4);  // s, about two DEM steps of the flagship
  EXPECT_FALSE(bed_->filter.has_value());
  EXPECT_EQ(bed_->labels, (std::vector<std::string>{"truck_bed"}));
  // Every element is on the coupling surface, as quads (contacted as two triangles each).
  EXPECT_EQ(bed_->mesh.quads.size(), model().elements.size());
  EXPECT_TRUE(bed_->mesh.triangles.empty());
  EXPECT_EQ(bed_->mesh.vertices.size(), model().nodes.size());
}

TEST_F(TruckBedShells, TheRigidFlagshipsBodyInPanelsOfClosedFormArea) {
  double floor = 0.0, walls = 0.0;  // m²
  for (const fem::ShellElement& e : model().elements) {
    ASSERT_EQ(e.node_count, 4);
    (e.section == 0 ? floor : walls) += quad_area(model(), e);
  }
  const truck_bed::PanelAreas panels = truck_bed::panel_areas();
  EXPECT_NEAR(floor, panels.floor, 1e-9);
  EXPECT_NEAR(walls, 2 * panels.side + panels.front, 1e-9);
}

TEST_F(TruckBedShells, OneConformingMeshOpenAlongTheRimsWithNormalsIntoTheBed) {
  const Vec3 inside{0.6, 0.0, 0.2};  // the bed's inside is convex: every inward normal faces it
  std::map<std::pair<int, int>, int> uses;
  for (const fem::ShellElement& e : model().elements) {
    const auto x = [&](int i) { return model().nodes[static_cast<std::size_t>(e.nodes[static_cast<std::size_t>(i)])]; };
    const Vec3 normal = cross(x(2) - x(0), x(3) - x(1));
    EXPECT_GT(dot(normal, inside - (x(0) + x(1) + x(2) + x(3)) * 0.25), 0.0);
    for (int i = 0; i < 4; ++i) {
      const int a = e.nodes[static_cast<std::size_t>(i)], b = e.nodes[static_cast<std::size_t>((i + 1) % 4)];
      ++uses[{std::min(a, b), std::max(a, b)}];
    }
  }
  for (const auto& [edge, count] : uses) {
    ASSERT_LE(count, 2);
    if (count == 2) continue;
    // Open edges only on the side-wall tops (z = 0.35), the headboard above them and the open
    // rear (x = 1.2); every seam between floor, tail and walls shares its nodes.
    const Vec3 middle = (model().nodes[static_cast<std::size_t>(edge.first)] +
                         model().nodes[static_cast<std::size_t>(edge.second)]) * 0.5;
    EXPECT_TRUE(middle.z > 0.35 - 1e-9 || std::abs(middle.x - 1.2) < 1e-9)
        << "open edge at " << middle.x << " " << middle.y << " " << middle.z;
  }
}

TEST_F(TruckBedShells, FloorPinnedOverTheRails) {
  std::vector<std::int32_t> pinned_nodes;  // one SPC1 card per node
  for (const fem::BoundaryCondition& spc : model().boundary_conditions) {
    EXPECT_EQ(spc.dofs, fem::dof::translations);  // pinned: the floor may turn over a rail
    pinned_nodes.insert(pinned_nodes.end(), spc.nodes.begin(), spc.nodes.end());
  }
  std::size_t expected = 0;
  double shortest = 1.0, longest = 0.0;  // m, the rails' extent along x
  for (std::size_t n = 0; n < model().nodes.size(); ++n) {
    const Vec3& x = model().nodes[n];
    const bool over_rail = std::abs(x.z) < 1e-12 && std::abs(x.y) >= 0.14 && std::abs(x.y) <= 0.26;
    const bool pinned = std::count(pinned_nodes.begin(), pinned_nodes.end(), static_cast<std::int32_t>(n)) == 1;
    EXPECT_EQ(pinned, over_rail) << "node " << n;
    if (over_rail) {
      ++expected;
      shortest = std::min(shortest, x.x);
      longest = std::max(longest, x.x);
    }
  }
  EXPECT_EQ(pinned_nodes.size(), expected);
  // Two supports for the monitors' reactions: the left rail (y < 0, its nodes come first), then
  // the right, 3 lines of 27 nodes each.
  const std::vector<std::vector<std::int32_t>> rails = fem::support_groups(model());
  ASSERT_EQ(rails.size(), 2u);
  for (std::size_t k = 0; k < 2; ++k) {
    EXPECT_EQ(rails[k].size(), 81u);
    for (const std::int32_t n : rails[k]) EXPECT_EQ(model().nodes[static_cast<std::size_t>(n)].y < 0.0, k == 0);
  }
  EXPECT_EQ(shortest, 0.0);   // from the front wall
  EXPECT_EQ(longest, 0.95);   // to the start of the tail
}

TEST_F(TruckBedShells, ElementsAboutAParticleDiameterAndTheirStableStep) {
  // The coarse particles are 36 mm across (mean radius 18 mm); the cells are 35.7–36.8 mm in
  // plan and 50 mm up the walls. Stable step of the limiting element, L_c / c with
  // L_c = area / longest side and c = √(E / (ρ(1 − ν²))) the plate wave speed (research notes §1).
  const fem::ShellSolver solver(model());
  const fem::StableTimeStep stable = solver.stable_time_step();
  const double speed = std::sqrt(2.1e11 / (7850.0 * (1.0 - 0.3 * 0.3)));  // m/s
  EXPECT_NEAR(stable.wave_speed, speed, 1e-9 * speed);
  EXPECT_GT(stable.characteristic_length, 0.030);
  EXPECT_LT(stable.characteristic_length, 0.040);
  EXPECT_NEAR(stable.time_step, stable.characteristic_length / speed, 1e-15);
  for (const fem::ShellElement& e : model().elements) {
    const double area = quad_area(model(), e);
    EXPECT_GT(area, 0.030 * 0.030);
    EXPECT_LT(area, 0.050 * 0.050);  // the widest: 45 × 52 mm at the flared headboard's top
  }
}

}  // namespace
}  // namespace quarry::fsi
