// Patch tests (MacNeal & Harder 1985, Finite Elem. Anal. Des. 1:3, the distorted five-element
// patch on 0.24 × 0.12): the exact field of a constant membrane strain, or of a constant
// curvature, is imposed on the boundary nodes as velocities (the interior nodes start with the
// same field and are free); every element must then carry the exact uniform stress
// σ = C ε (membrane) or σ(z) = z C κ (bending; C the plane-stress matrix) and the interior nodes
// must follow the field. Quads and the same patch cut into triangles.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "fem/shell_solver.h"
#include "fem/shell_test_meshes.h"

namespace quarry::fem {
namespace {

constexpr double kThickness = 0.001;

ShellModel distorted_patch(testing::MeshKind kind) {
  ShellModel model;
  model.nodes = {{0.0, 0.0, 0.0},   {0.24, 0.0, 0.0},  {0.24, 0.12, 0.0}, {0.0, 0.12, 0.0},
                 {0.04, 0.02, 0.0}, {0.18, 0.03, 0.0}, {0.16, 0.08, 0.0}, {0.08, 0.08, 0.0}};
  const std::array<std::array<std::int32_t, 4>, 5> quads{
      {{0, 1, 5, 4}, {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}, {4, 5, 6, 7}}};
  for (const auto& q : quads) {
    if (kind == testing::MeshKind::quads) {
      model.elements.push_back({q, 4, 0});
    } else {
      model.elements.push_back({{q[0], q[1], q[2], 0}, 3, 0});
      model.elements.push_back({{q[0], q[2], q[3], 0}, 3, 0});
    }
  }
  model.sections.push_back({kThickness, 5, ThicknessRule::lobatto, 0});
  model.materials.push_back(testing::steel());
  return model;
}

bool on_boundary(const Vec3& p) {
  return testing::near(p.x, 0.0) || testing::near(p.x, 0.24) || testing::near(p.y, 0.0) ||
         testing::near(p.y, 0.12);
}

// Nodal velocity of a field: translation (m/s) and rotation rate (rad/s) at a point.
struct Field {
  Vec3 velocity;
  Vec3 angular_velocity;
};

// Runs the patch with `field` imposed on the boundary over `duration` (the interior starts with
// the field too), then, if `relax` > 0, holds the boundary still for `relax` seconds with
// mass-proportional damping `damping` so that the interior reaches its static equilibrium.
template <class FieldFunction>
ShellSolver run_patch(testing::MeshKind kind, FieldFunction field, double duration,
                      double relax = 0.0, double damping = 0.0, double thickness = kThickness) {
  ShellModel model = distorted_patch(kind);
  model.sections[0].thickness = thickness;
  for (std::size_t n = 0; n < model.nodes.size(); ++n) {
    if (!on_boundary(model.nodes[n])) continue;
    const Field f = field(model.nodes[n]);
    model.boundary_conditions.push_back(
        {{static_cast<std::int32_t>(n)},
         dof::all,
         {f.velocity.x, f.velocity.y, f.velocity.z, f.angular_velocity.x, f.angular_velocity.y,
          f.angular_velocity.z}});
  }
  ShellSolver solver(model);
  for (std::size_t n = 0; n < model.nodes.size(); ++n) {
    const Field f = field(model.nodes[n]);
    solver.set_velocity(static_cast<int>(n), f.velocity, f.angular_velocity);
  }
  const double dt = 0.5 * solver.stable_time_step().time_step;
  const int steps = static_cast<int>(std::ceil(duration / dt));
  for (int s = 0; s < steps; ++s) solver.step(duration / steps);
  if (relax > 0.0) {
    for (std::size_t n = 0; n < model.nodes.size(); ++n) {
      if (on_boundary(model.nodes[n])) solver.set_prescribed_velocity(static_cast<int>(n), {});
    }
    solver.set_damping(damping);
    const int relax_steps = static_cast<int>(std::ceil(relax / dt));
    for (int s = 0; s < relax_steps; ++s) solver.step(dt);
  }
  return solver;
}

class PatchTest : public ::testing::TestWithParam<testing::MeshKind> {};

TEST_P(PatchTest, ConstantMembraneStrainGivesTheExactUniformStress) {
  // ε = (1e-5, −4e-6, γ 6e-6) reached at t = T through v = D x with D = ε/T.
  const double duration = 2e-4;
  const Voigt3 strain{1e-5, -4e-6, 6e-6};
  auto field = [&](const Vec3& p) {
    return Field{{(strain[0] * p.x + 0.5 * strain[2] * p.y) / duration,
                  (0.5 * strain[2] * p.x + strain[1] * p.y) / duration, 0.0},
                 {}};
  };
  const ShellSolver solver = run_patch(GetParam(), field, duration);
  const Voigt3 exact = plane_stress_elastic({210e9, 0.3, 0.0, 0.0}, strain);
  const double exact_trace = exact[0] + exact[1], exact_mises = von_mises(exact);
  double worst = 0.0;
  for (int e = 0; e < solver.element_count(); ++e) {
    for (int p = 0; p < 5; ++p) {
      const Voigt3 s = solver.element_stress(e, p);
      worst = std::max({worst, std::abs(s[0] + s[1] - exact_trace) / exact_mises,
                        std::abs(von_mises(s) - exact_mises) / exact_mises});
    }
  }
  // Interior nodes follow x + ε x (to within the O(ε) difference between the rate-integrated
  // and the small strain).
  const ShellModel model = distorted_patch(GetParam());
  double worst_position = 0.0;
  for (int n = 4; n < 8; ++n) {
    const Vec3 x0 = model.nodes[n];
    const Vec3 expected = x0 + duration * field(x0).velocity;
    worst_position = std::max(worst_position, norm(solver.positions()[n] - expected) /
                                                  norm(expected - x0));
  }
  std::printf("membrane patch: worst stress error %.2e (relative to σ_vm), interior position "
              "%.2e (relative to the displacement), hourglass %.2e J of internal %.2e J\n",
              worst, worst_position, solver.energies().hourglass, solver.energies().internal);
  EXPECT_LT(worst, 1e-4);
  EXPECT_LT(worst_position, 1e-3);
  EXPECT_LT(std::abs(solver.energies().hourglass), 1e-6 * solver.energies().internal);
}

TEST_P(PatchTest, ConstantCurvatureGivesTheExactBendingStress) {
  // κ = (κxx, κyy, 2κxy) from θ_y = κxx x + κxy y, θ_x = −κyy y − κxy x and
  // w = −½(κxx x² + κyy y² + 2κxy x y), which make the transverse shear zero.
  const double duration = 2e-4;
  // Small enough that the membrane strain of the rotation, ~θ²/2 ~ (κ L)², stays far below the
  // bending strain κ t/2 (ratio κ L²/t ~ 1e-4): the test is of the linear kinematics.
  const Voigt3 curvature{2e-6, -1e-6, 1.2e-6};  // 1/m
  const double kxy = 0.5 * curvature[2];
  auto field = [&](const Vec3& p) {
    const double w = -0.5 * (curvature[0] * p.x * p.x + curvature[1] * p.y * p.y +
                             2.0 * kxy * p.x * p.y);
    return Field{{0.0, 0.0, w / duration},
                 {(-curvature[1] * p.y - kxy * p.x) / duration,
                  (curvature[0] * p.x + kxy * p.y) / duration, 0.0}};
  };
  // The interior must find its static equilibrium: t = 10 mm, lowest patch mode
  // ω ≈ (π/0.24 m)² √(D/(ρt)) ≈ 2.7e3 rad/s, relaxed with critical damping for 40/ω.
  const double thickness = 0.01, omega = 2.7e3;
  const ShellSolver solver =
      run_patch(GetParam(), field, duration, 40.0 / omega, 2.0 * omega, thickness);
  const double half = 0.5 * thickness;
  const Voigt3 top = plane_stress_elastic(
      {210e9, 0.3, 0.0, 0.0}, {half * curvature[0], half * curvature[1], half * curvature[2]});
  const double exact_trace = top[0] + top[1], exact_mises = von_mises(top);
  double worst = 0.0;
  for (int e = 0; e < solver.element_count(); ++e) {
    const Voigt3 s_top = solver.element_stress(e, 4), s_bottom = solver.element_stress(e, 0);
    const Voigt3 s_mid = solver.element_stress(e, 2);
    worst = std::max({worst, std::abs(s_top[0] + s_top[1] - exact_trace) / exact_mises,
                      std::abs(s_bottom[0] + s_bottom[1] + exact_trace) / exact_mises,
                      std::abs(von_mises(s_top) - exact_mises) / exact_mises,
                      von_mises(s_mid) / exact_mises});
  }
  std::printf("bending patch: worst surface stress error %.2e (relative to σ_vm at the surface)\n",
              worst);
  EXPECT_LT(worst, 1e-3);
}

INSTANTIATE_TEST_SUITE_P(Elements, PatchTest,
                         ::testing::Values(testing::MeshKind::quads, testing::MeshKind::triangles),
                         [](const auto& param_info) {
                           return param_info.param == testing::MeshKind::quads ? "quads" : "triangles";
                         });

}  // namespace
}  // namespace quarry::fem
