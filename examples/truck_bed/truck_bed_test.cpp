// Checks examples/truck_bed/truck_bed.stl against the geometry its README describes: the
// enclosed extents, the panel areas in closed form, normals into the bed, watertight seams
// (open only along the rims and the rear) and the ~25 mm triangle size.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <numbers>
#include <string>

#include "geometry/mesh_topology.h"
#include "geometry/stl_reader.h"
#include "truck_bed_areas.h"

namespace quarry {
namespace {

constexpr double degree = std::numbers::pi / 180.0;
const double tan_flare = std::tan(10 * degree), tan_lean = std::tan(15 * degree);
constexpr double float_tolerance = 1e-6;  // m, coordinates are float32 in the file

std::string stl_path() {
  const char* source = std::getenv("QUARRY_SOURCE_DIR");
  return std::string(source ? source : QUARRY_SOURCE_DIR) + "/examples/truck_bed/truck_bed.stl";
}

class TruckBed : public testing::Test {
 protected:
  static void SetUpTestSuite() { bed_ = new Surface(read_stl(stl_path(), 1.0, {})); }
  static void TearDownTestSuite() { delete bed_; }
  static Surface* bed_;
};
Surface* TruckBed::bed_ = nullptr;

TEST_F(TruckBed, SizeAndExtentsMatchTheReadme) {
  const Surface& bed = *bed_;
  EXPECT_GE(bed.triangle_count(), 2000u);
  EXPECT_LE(bed.triangle_count(), 6000u);
  const Aabb box = bed.bounds();
  EXPECT_NEAR(box.lo.x, -0.45 * tan_lean, float_tolerance);  // front wall top leans forward
  EXPECT_NEAR(box.hi.x, 1.2, float_tolerance);
  EXPECT_NEAR(box.hi.y, 0.35 + 0.45 * tan_flare, float_tolerance);  // front wall top corner
  EXPECT_NEAR(box.lo.y, -box.hi.y, float_tolerance);
  EXPECT_NEAR(box.lo.z, 0.0, float_tolerance);
  EXPECT_NEAR(box.hi.z, 0.45, float_tolerance);
}

TEST_F(TruckBed, TotalAreaIsTheSumOfThePlanarPanels) {
  const truck_bed::PanelAreas panels = truck_bed::panel_areas();
  double area = 0.0;
  for (const double a : bed_->triangle_areas) area += a;
  EXPECT_NEAR(area, panels.floor + 2 * panels.side + panels.front, 1e-5);  // m², float32 coordinates
}

TEST_F(TruckBed, NormalsPointIntoTheBed) {
  // The bed's inside is convex (every panel bends towards the load), so every inward normal
  // faces any interior point.
  const Vec3 inside{0.6, 0.0, 0.2};
  const Surface& bed = *bed_;
  for (std::size_t t = 0; t < bed.triangle_count(); ++t) {
    const auto& tri = bed.triangles[t];
    const Vec3 centroid = (bed.vertices[tri[0]] + bed.vertices[tri[1]] + bed.vertices[tri[2]]) / 3.0;
    ASSERT_GT(dot(bed.triangle_normals[t], inside - centroid), 0.0) << "triangle " << t;
  }
}

TEST_F(TruckBed, SeamsAreWatertightAndTrianglesAreAbout25mm) {
  const Surface& bed = *bed_;
  const MeshTopology topology = build_topology(bed);
  for (std::uint32_t e = 0; e < topology.edge_count(); ++e) {
    const Vec3& a = bed.vertices[topology.edges[e][0]];
    const Vec3& b = bed.vertices[topology.edges[e][1]];
    // Cells of 25–33 mm (widest at the flared front-wall top), so diagonals stay under 50 mm.
    EXPECT_LT(norm(b - a), 0.05) << "edge " << e;
    const std::size_t sharing = topology.triangles_of_edge(e).size();
    ASSERT_LE(sharing, 2u);
    if (sharing == 2) continue;
    // Open edges only on the rims: side-wall tops (z = 0.35), front-wall top (z = 0.45), the
    // front wall's free sides above the side walls, and the open rear (x = 1.2).
    const Vec3 middle = (a + b) * 0.5;
    const bool rim = std::abs(middle.z - 0.35) < float_tolerance || std::abs(middle.z - 0.45) < float_tolerance ||
                     middle.z > 0.35 || std::abs(middle.x - 1.2) < float_tolerance;
    EXPECT_TRUE(rim) << "open edge at " << middle.x << " " << middle.y << " " << middle.z;
  }
  // Roughly uniform: the largest triangle is at most 3× the smallest (half of a 25 mm square
  // is 3.1e-4 m²).
  const auto [smallest, largest] = std::minmax_element(bed.triangle_areas.begin(), bed.triangle_areas.end());
  EXPECT_GT(*smallest, 2.0e-4);
  EXPECT_LT(*largest, 3.0 * *smallest);
}

}  // namespace
}  // namespace quarry
