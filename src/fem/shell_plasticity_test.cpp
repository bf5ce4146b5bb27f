// Plasticity of the shell: (1) one element pulled in uniaxial stress follows the bilinear
// curve σ = σ_y0 + E H/(E + H)(ε − σ_y0/E) in true stress and logarithmic strain, with
// ε̄_p = (σ − σ_y0)/H; (2) a perfectly plastic cantilever pushed at the tip carries at most
// the limit load P_c = M_p / L with M_p = σ_y b t²/4, the fully plastic moment of a rectangle
// (e.g. Neal, "The Plastic Methods of Structural Analysis", 1977, §1.3; Lubliner,
// "Plasticity Theory", §4.5).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "fem/shell_solver.h"
#include "fem/shell_test_meshes.h"

namespace quarry::fem {
namespace {

using testing::near;

constexpr double kE = 210e9, kYield = 250e6;

TEST(ShellPlasticity, UniaxialMembraneStressFollowsTheBilinearCurve) {
  const double hardening = 2.1e9, side = 0.01, thickness = 0.001;
  ShellModel model = testing::rectangle(1, 1, side, side, thickness, testing::MeshKind::quads, 5,
                                        ThicknessRule::lobatto, testing::steel(kYield, hardening));
  // Node 0 (0,0) holds x and y, node 2 (0,L) holds x; nodes 1 and 3 (x = L) move at speed v
  // along x; y of nodes 1-3 is free, so σ_yy = 0. Bending DOFs held.
  const double speed = 0.01;  // m/s: strain rate 1 /s, slow against the element's 5e5 rad/s
  const std::uint8_t bending = dof::uz | dof::rotations;
  model.boundary_conditions = {{{0}, static_cast<std::uint8_t>(dof::ux | dof::uy | bending), {}},
                               {{2}, static_cast<std::uint8_t>(dof::ux | bending), {}},
                               {{1, 3}, static_cast<std::uint8_t>(dof::ux | bending), {speed}}};
  ShellSolver solver(model);
  const double dt = 0.8 * solver.stable_time_step().time_step;
  const double tangent = kE * hardening / (kE + hardening);
  double worst = 0.0, worst_plastic = 0.0;
  int checked = 0;
  while (solver.positions()[1].x < side * 1.02) {
    solver.step(dt);
    if (solver.step_count() % 500 != 0) continue;
    const double strain = std::log(solver.positions()[1].x / side);  // logarithmic
    const double stress = solver.element_stress(0, 2)[0];
    const double expected = strain < kYield / kE ? kE * strain
                                                 : kYield + tangent * (strain - kYield / kE);
    worst = std::max(worst, std::abs(stress - expected) / kYield);
    const double plastic = solver.element_plastic_strain(0, 2);
    const double expected_plastic = std::max(0.0, (stress - kYield) / hardening);
    worst_plastic = std::max(worst_plastic, std::abs(plastic - expected_plastic));
    ++checked;
  }
  std::printf("uniaxial: %d points to 2 %% strain, worst |σ − bilinear| = %.2e σ_y0, worst ε̄_p "
              "error %.2e, final σ %.4e Pa, lateral stress %.2e Pa\n",
              checked, worst, worst_plastic, solver.element_stress(0, 2)[0],
              solver.element_stress(0, 2)[1]);
  // Energy bookkeeping with prescribed motion: the reactions' work is what the element stored
  // and dissipated (internal energy, elastic + plastic) plus the small kinetic energy.
  const ShellEnergies& e = solver.energies();
  const double imbalance = e.kinetic + e.internal + e.hourglass - e.constraint_work;
  std::printf("uniaxial energy: constraint work %.6e J, internal %.6e J, imbalance %.2e J\n",
              e.constraint_work, e.internal, imbalance);
  EXPECT_LT(std::abs(imbalance), 1e-3 * e.internal);
  EXPECT_GT(checked, 10);
  EXPECT_LT(worst, 0.005);
  EXPECT_LT(worst_plastic, 1e-4);
  EXPECT_GT(solver.element_result(0).plastic_strain_max, 0.015);
}

TEST(ShellPlasticity, CantileverCollapseLoadMatchesLimitAnalysis) {
  // L 0.1 m, b 10 mm, t 10 mm, 20 × 1 quads, 9 Gauss points through the thickness (5 points
  // would integrate the fully plastic stress block 5-9 % low: through_thickness_test.cpp).
  const double length = 0.1, width = 0.01, thickness = 0.01;
  ShellModel model = testing::rectangle(20, 1, length, width, thickness, testing::MeshKind::quads,
                                        9, ThicknessRule::gauss, testing::steel(kYield, 0.0));
  const auto root = testing::nodes_where(model, [](const Vec3& p) { return near(p.x, 0.0); });
  const auto tip = testing::nodes_where(model, [&](const Vec3& p) { return near(p.x, length); });
  const double inertia = width * thickness * thickness * thickness / 12.0;
  const double yield_load = kYield * width * thickness * thickness / 6.0 / length;  // M_y/L
  const double yield_deflection = yield_load * length * length * length / (3.0 * kE * inertia);
  // Tip pushed down over 20 ms (the first mode is ~0.8 kHz: quasi-static) to 5 δ_y.
  const double duration = 0.02;
  const double speed = -5.0 * yield_deflection / duration;
  // Beam clamp: u_x, u_z, θ_y (and the drilling θ_z) held along the root, u_y at one root node;
  // θ_x stays free so that the section contracts laterally (anticlastic curvature) as beam
  // theory's uniaxial stress assumes; a full clamp would add a plane-strain zone at the root.
  const std::uint8_t clamp = dof::ux | dof::uz | dof::ry | dof::rz;
  model.boundary_conditions = {{root, clamp, {}},
                               {{root.front()}, dof::uy, {}},
                               {tip, dof::uz, {0.0, 0.0, speed}}};
  ShellSolverOptions options;
  options.damping = 200.0;  // 1/s, ~4 % of critical for the first mode: quiets the reaction
  ShellSolver solver(model, options);
  const double dt = 0.8 * solver.stable_time_step().time_step;
  const int steps = static_cast<int>(duration / dt);
  double plateau = 0.0;
  int plateau_samples = 0;
  for (int s = 0; s < steps; ++s) {
    solver.step(dt);
    if (s > steps * 4 / 5) {  // mean over the last fifth (4-5 δ_y)
      double load = 0.0;
      for (const std::int32_t n : tip) load -= solver.reactions()[n][2];
      plateau += load;
      ++plateau_samples;
    }
  }
  plateau /= plateau_samples;
  const double plastic_moment = kYield * width * thickness * thickness / 4.0;
  const double collapse = plastic_moment / length;
  std::printf("cantilever collapse: plateau load %.2f N, M_p/L %.2f N (%+.2f %%), first-yield "
              "load %.2f N\n",
              plateau, collapse, 100.0 * (plateau / collapse - 1.0), yield_load);
  EXPECT_NEAR(plateau, collapse, 0.05 * collapse);
}

}  // namespace
}  // namespace quarry::fem
