// Nodal and coarse-grained surface pressure against closed forms: a uniform pressure is
// reproduced exactly, the nodal pressure conserves the total normal load, a point load gives
// the Gaussian's peak F / (2π w²), and a loaded floor is not averaged with the wall beside it;
// a smoother kept over a run's frames answers as a fresh one.
#include "geometry/surface_pressure.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace quarry {
namespace {

// Adds to `surface` the parallelogram origin + s·u + t·v (s, t ∈ [0, 1]) split into n×n
// squares of two triangles each, normal along u × v.
void add_grid(Surface& surface, Vec3 origin, Vec3 u, Vec3 v, int n) {
  const auto first = static_cast<std::uint32_t>(surface.vertices.size());
  const auto index = [&](int i, int j) {
    return first + static_cast<std::uint32_t>(i * (n + 1) + j);
  };
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j)
      surface.vertices.push_back(origin + u * (double(i) / n) + v * (double(j) / n));
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      surface.triangles.push_back({index(i, j), index(i + 1, j), index(i + 1, j + 1)});
      surface.triangles.push_back({index(i, j), index(i + 1, j + 1), index(i, j + 1)});
    }
}

Surface plate(double side, int n) {
  Surface s;
  s.name = "plate";
  add_grid(s, {0, 0, 0}, {side, 0, 0}, {0, side, 0}, n);
  s.update_normals_and_areas();
  s.reset_loads();
  return s;
}

// Consistent nodal forces of per-triangle pressures (Pa): a third of −p A n to each vertex.
std::vector<Vec3> nodal_forces_of(const Surface& s, const std::vector<double>& pressure) {
  std::vector<Vec3> forces(s.vertex_count());
  for (std::size_t t = 0; t < s.triangle_count(); ++t)
    for (const std::uint32_t v : s.triangles[t])
      forces[v] += s.triangle_normals[t] * (-pressure[t] * s.triangle_areas[t] / 3.0);
  return forces;
}

TEST(SurfacePressure, UniformPressureIsReproducedExactlyUpToTheEdges) {
  const Surface s = plate(0.3, 12);
  const std::vector<double> uniform(s.triangle_count(), 1234.0);  // Pa
  const std::vector<double> nodal = nodal_pressure(s, nodal_forces_of(s, uniform));
  const std::vector<double> smooth = coarse_grained_pressure(s, nodal, 0.02);
  for (std::size_t v = 0; v < s.vertex_count(); ++v) {
    EXPECT_NEAR(nodal[v], 1234.0, 1e-9) << v;
    EXPECT_NEAR(smooth[v], 1234.0, 1e-9) << v;
  }
}

// Σ p_v A_v = −(Σ F_v)·n on a flat surface, whatever the loads (here one contact-like
// vertex load in three and a tangential part).
TEST(SurfacePressure, NodalPressureConservesTheTotalNormalLoad) {
  const Surface s = plate(0.3, 9);
  std::vector<Vec3> forces(s.vertex_count());
  double total = 0.0;  // N, compressive
  for (std::size_t v = 0; v < forces.size(); v += 3) {
    forces[v] = {0.1 * v, -0.05, -1.0 - 0.01 * v};
    total += 1.0 + 0.01 * v;
  }
  const std::vector<double> pressure = nodal_pressure(s, forces);
  const std::vector<double> area = tributary_areas(s);
  double sum = 0.0, area_sum = 0.0;
  for (std::size_t v = 0; v < pressure.size(); ++v) {
    sum += pressure[v] * area[v];
    area_sum += area[v];
  }
  EXPECT_NEAR(sum, total, 1e-12 * total);
  EXPECT_NEAR(area_sum, 0.09, 1e-15);
}

// One loaded triangle (force F, consistent nodal forces F/3 at its corners) at the centre of a
// plate much larger than the kernel: the coarse-grained pressure at a vertex is
// Σ_corners (F/3) W(r_i) / Σ_v W A_v, and Σ_v W A_v → the Gaussian's integral inside the 3w
// cut-off, 2π w² (1 − e^(−9/2)) (a grid of spacing w/5 sums it to < 0.1 %).
TEST(SurfacePressure, PointLoadGivesTheGaussianPeak) {
  const double width = 0.01;          // m
  const Surface s = plate(0.2, 100);  // 2 mm squares
  std::vector<double> pressure(s.triangle_count(), 0.0);
  const std::size_t loaded = 2 * (50 * 100 + 50);  // lower triangle of square (50, 50)
  const double force = 3.0;                        // N
  pressure[loaded] = force / s.triangle_areas[loaded];
  const std::vector<double> smooth =
      coarse_grained_pressure(s, nodal_pressure(s, nodal_forces_of(s, pressure)), width);
  const auto& tri = s.triangles[loaded];
  const std::uint32_t v = tri[0];  // corner (50, 50) at (0.1, 0.1)
  double kernel_sum = 0.0;
  for (const std::uint32_t corner : tri)
    kernel_sum += std::exp(-0.5 * norm2(s.vertices[v] - s.vertices[corner]) / (width * width));
  const double expected =
      force / 3.0 * kernel_sum / (2.0 * std::numbers::pi * width * width * (1.0 - std::exp(-4.5)));
  EXPECT_NEAR(smooth[v] / expected, 1.0, 0.005) << smooth[v] << " Pa against " << expected;
  // Beyond the 3w cut-off nothing arrives.
  EXPECT_EQ(smooth[0], 0.0);
}

// A loaded floor meets an unloaded wall at a right angle: a floor vertex one width from the
// wall keeps the floor's pressure (the wall's triangles face 90° away and are left out).
TEST(SurfacePressure, FloorIsNotAveragedWithTheWallBesideIt) {
  Surface s;
  s.name = "corner";
  add_grid(s, {0, 0, 0}, {0.1, 0, 0}, {0, 0.1, 0}, 20);  // floor, normal +z
  const std::size_t floor_triangles = s.triangles.size();
  add_grid(s, {0, 0, 0}, {0, 0.1, 0}, {0, 0, 0.1}, 20);  // wall x = 0, normal +x
  s.update_normals_and_areas();
  std::vector<double> pressure(s.triangle_count(), 0.0);
  for (std::size_t t = 0; t < floor_triangles; ++t) pressure[t] = 500.0;  // Pa
  const std::vector<double> nodal = nodal_pressure(s, nodal_forces_of(s, pressure));
  const std::vector<double> smooth = coarse_grained_pressure(s, nodal, 0.01);
  const std::uint32_t floor_vertex = 2 * 21 + 10;  // (x, y) = (0.01, 0.05) m
  ASSERT_NEAR(s.vertices[floor_vertex].x, 0.01, 1e-12);
  EXPECT_NEAR(smooth[floor_vertex], 500.0, 1e-9);
  const std::uint32_t wall_vertex = 21 * 21 + 10 * 21 + 2;  // (y, z) = (0.05, 0.01) m
  ASSERT_NEAR(s.vertices[wall_vertex].z, 0.01, 1e-12);
  EXPECT_EQ(smooth[wall_vertex], 0.0);
  EXPECT_THROW(coarse_grained_pressure(s, nodal, 0.0), std::invalid_argument);
  EXPECT_THROW(coarse_grained_pressure(s, pressure, 0.01), std::invalid_argument);
  EXPECT_THROW(nodal_pressure(s, std::vector<Vec3>(3)), std::invalid_argument);
}

// A smoother kept over the frames of a run gives, frame after frame, what a fresh one gives,
// bit for bit; when the surface's vertices move (a moving wall, a deforming structure) or the
// width changes, it finds its neighbours and weights again instead of using the old ones.
TEST(SurfacePressure, AKeptSmootherAnswersAsAFreshOneAndFollowsTheSurface) {
  Surface s = plate(0.3, 12);
  PressureSmoother kept;
  const auto expect_fresh = [&](const std::vector<double>& nodal,
                                double width) -> std::vector<double> {
    const std::vector<double> again = kept.smooth(s, nodal, width);
    const std::vector<double> fresh = PressureSmoother().smooth(s, nodal, width);
    EXPECT_EQ(again.size(), fresh.size());
    for (std::size_t v = 0; v < again.size() && v < fresh.size(); ++v)
      EXPECT_EQ(again[v], fresh[v]) << v;
    return again;
  };
  std::vector<double> pressure(s.triangle_count());
  for (int frame = 0; frame < 3; ++frame) {  // loads that change from frame to frame
    for (std::size_t t = 0; t < pressure.size(); ++t)
      pressure[t] = 1000.0 * static_cast<double>((t * 7 + frame * 13) % 11);  // Pa
    expect_fresh(nodal_pressure(s, nodal_forces_of(s, pressure)), 0.02);
  }
  const std::vector<double> nodal = nodal_pressure(s, nodal_forces_of(s, pressure));
  const std::vector<double> before = expect_fresh(nodal, 0.02);
  for (Vec3& x : s.vertices) x = x * 1.5;  // the same loads on a larger plate
  s.update_normals_and_areas();
  const std::vector<double> moved = expect_fresh(nodal, 0.02);
  const std::vector<double> wider = expect_fresh(nodal, 0.03);
  std::size_t differ = 0, differ_wider = 0;
  for (std::size_t v = 0; v < nodal.size(); ++v) {
    differ += moved[v] != before[v];
    differ_wider += wider[v] != moved[v];
  }
  EXPECT_GT(differ, nodal.size() / 2);
  EXPECT_GT(differ_wider, nodal.size() / 2);
}

}  // namespace
}  // namespace quarry
