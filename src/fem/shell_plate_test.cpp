// Simply supported square plate under uniform pressure q: centre deflection against Kirchhoff
// plate theory, w = α q a⁴ / D with D = E t³/(12(1 − ν²)) and α = 0.00406 for ν = 0.3
// (Timoshenko & Woinowsky-Krieger, "Theory of Plates and Shells", 1959, Table 8; Navier's
// double series §30, evaluated here too). Quarter model with symmetry, quads and triangles.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <vector>

#include "fem/shell_solver.h"
#include "fem/shell_test_meshes.h"

namespace quarry::fem {
namespace {

using testing::near;

constexpr double kSide = 1.0, kThickness = 0.01, kPressure = 1000.0;
constexpr double kE = 210e9, kNu = 0.3, kDensity = 7850.0;

// Navier: w(a/2, a/2) = 16 q a⁴/(π⁶ D) Σ_{m,n odd} (−1)^((m+n)/2 − 1) / (m n (m² + n²)²).
double navier_coefficient() {
  double sum = 0.0;
  for (int m = 1; m < 400; m += 2) {
    for (int n = 1; n < 400; n += 2) {
      const double sign = ((m + n) / 2 - 1) % 2 == 0 ? 1.0 : -1.0;
      sum += sign / (m * n * std::pow(m * m + n * n, 2.0));
    }
  }
  return 16.0 / std::pow(std::numbers::pi, 6.0) * sum;
}

double centre_deflection(testing::MeshKind kind, int cells) {
  const double half = 0.5 * kSide;
  ShellModel model = testing::rectangle(cells, cells, half, half, kThickness, kind);
  auto where = [&](auto select) { return testing::nodes_where(model, select); };
  // Hard simple support on x = 0 and y = 0 (w = 0 and the rotation along the edge = 0);
  // symmetry on x = a/2 (u_x = θ_y = θ_z = 0) and y = a/2 (u_y = θ_x = θ_z = 0).
  model.boundary_conditions.push_back(
      {where([](const Vec3& p) { return near(p.x, 0.0); }), dof::uz | dof::rx, {}});
  model.boundary_conditions.push_back(
      {where([](const Vec3& p) { return near(p.y, 0.0); }), dof::uz | dof::ry, {}});
  model.boundary_conditions.push_back(
      {where([&](const Vec3& p) { return near(p.x, half); }), dof::ux | dof::ry | dof::rz, {}});
  model.boundary_conditions.push_back(
      {where([&](const Vec3& p) { return near(p.y, half); }), dof::uy | dof::rx | dof::rz, {}});
  const double rigidity = kE * std::pow(kThickness, 3.0) / (12.0 * (1.0 - kNu * kNu));
  // Fundamental frequency of the plate, ω = 2π²/a² √(D/(ρ t)); critical damping for it.
  const double omega = 2.0 * std::numbers::pi * std::numbers::pi / (kSide * kSide) *
                       std::sqrt(rigidity / (kDensity * kThickness));
  ShellSolverOptions options;
  options.damping = 2.0 * omega;
  ShellSolver solver(model, options);
  // Uniform pressure as consistent nodal forces: q A_e / n per node of each element.
  std::vector<NodalLoad> loads(model.nodes.size());
  for (const ShellElement& element : model.elements) {
    std::array<Vec3, 4> x{};
    for (int i = 0; i < element.node_count; ++i) x[i] = model.nodes[element.nodes[i]];
    const double share = kPressure * element_area(x, element.node_count) / element.node_count;
    for (int i = 0; i < element.node_count; ++i) loads[element.nodes[i]].force.z -= share;
  }
  solver.set_loads(loads);
  const double dt = 0.8 * solver.stable_time_step().time_step;
  const int steps = static_cast<int>(14.0 / omega / dt);
  for (int s = 0; s < steps; ++s) solver.step(dt);
  const auto centre = where([&](const Vec3& p) { return near(p.x, half) && near(p.y, half); });
  return -solver.positions()[centre.at(0)].z;
}

TEST(ShellPlate, NavierSeriesGivesTheTabulatedCoefficient) {
  EXPECT_NEAR(navier_coefficient(), 0.00406, 0.000005);
}

TEST(ShellPlate, SimplySupportedSquarePlateCentreDeflection) {
  const double rigidity = kE * std::pow(kThickness, 3.0) / (12.0 * (1.0 - kNu * kNu));
  const double kirchhoff = 0.00406 * kPressure * std::pow(kSide, 4.0) / rigidity;
  const double quads = centre_deflection(testing::MeshKind::quads, 8);
  const double triangles = centre_deflection(testing::MeshKind::triangles, 8);
  std::printf("plate: Kirchhoff %.6e m; 8x8 quarter quads %.6e m (%+.3f %%), triangles %.6e m "
              "(%+.3f %%)\n",
              kirchhoff, quads, 100.0 * (quads / kirchhoff - 1.0), triangles,
              100.0 * (triangles / kirchhoff - 1.0));
  EXPECT_NEAR(quads, kirchhoff, 0.02 * kirchhoff);
  EXPECT_NEAR(triangles, kirchhoff, 0.02 * kirchhoff);
}

}  // namespace
}  // namespace quarry::fem
