// Steel cantilever strip L 0.5 m, b 50 mm, t 5 mm, 10 × 1 Belytschko–Tsay quads, clamped at
// x = 0: Euler–Bernoulli tip deflection δ = P L³/(3 E I) and first natural frequency
// f₁ = (1.875²/2π) √(E I/(ρ A L⁴)) = 16.71 Hz (I = b t³/12, A = b t; e.g. Timoshenko, Young &
// Weaver, "Vibration Problems in Engineering", §5.3); energy balance of the free vibration.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "fem/shell_solver.h"
#include "fem/shell_test_meshes.h"

namespace quarry::fem {
namespace {

using testing::near;

constexpr double kLength = 0.5, kWidth = 0.05, kThickness = 0.005;
constexpr double kE = 210e9, kNu = 0.3, kDensity = 7850.0;
constexpr double kInertia = kWidth * kThickness * kThickness * kThickness / 12.0;  // I (m⁴)

ShellModel cantilever(testing::MeshKind kind = testing::MeshKind::quads) {
  ShellModel model = testing::rectangle(10, 1, kLength, kWidth, kThickness, kind);
  model.boundary_conditions.push_back(
      {testing::nodes_where(model, [](const Vec3& p) { return near(p.x, 0.0); }), dof::all, {}});
  return model;
}

double tip_deflection(const ShellSolver& solver, const std::vector<std::int32_t>& tip) {
  double sum = 0.0;
  for (const std::int32_t n : tip) sum += solver.positions()[n].z;
  return sum / static_cast<double>(tip.size());
}

TEST(ShellCantilever, StaticTipDeflectionAndFirstFrequency) {
  const ShellModel model = cantilever();
  const auto tip = testing::nodes_where(model, [](const Vec3& p) { return near(p.x, kLength); });
  const double omega1 = 1.875104 * 1.875104 *
                        std::sqrt(kE * kInertia / (kDensity * kWidth * kThickness)) /
                        (kLength * kLength);  // rad/s
  ShellSolverOptions options;
  options.damping = 2.0 * omega1;  // critical for the first mode: dynamic relaxation
  ShellSolver solver(model, options);
  const double dt = 0.8 * solver.stable_time_step().time_step;

  // Static: tip load P = 1 N shared by the two tip nodes, relaxed to rest.
  const double load = 1.0;
  std::vector<NodalLoad> loads(model.nodes.size());
  for (const std::int32_t n : tip) loads[n].force = {0.0, 0.0, load / tip.size()};
  solver.set_loads(loads);
  const int relax_steps = static_cast<int>(12.0 / omega1 / dt);
  for (int s = 0; s < relax_steps; ++s) solver.step(dt);
  const double deflection = tip_deflection(solver, tip);
  const double beam = load * kLength * kLength * kLength / (3.0 * kE * kInertia);
  std::printf("cantilever: tip deflection %.6e m, P L^3/(3EI) %.6e m (%+.3f %%)\n", deflection,
              beam, 100.0 * (deflection / beam - 1.0));
  EXPECT_NEAR(deflection, beam, 0.02 * beam);

  // Free vibration: remove load and damping, count upward zero crossings of the tip.
  solver.set_loads(std::vector<NodalLoad>(model.nodes.size()));
  solver.set_damping(0.0);
  const double period_guess = 2.0 * std::numbers::pi / omega1;
  std::vector<double> crossings;
  double previous = tip_deflection(solver, tip);
  const double energy0 = solver.energies().kinetic + solver.energies().internal +
                         solver.energies().hourglass - solver.energies().external_work;
  // Energy balance of the undamped free vibration (test 4 of issue #17 §1): the total
  // kinetic + internal + hourglass − external work stays within 1e-3 of the vibration energy.
  const double vibration_energy = solver.energies().internal;
  double worst_drift = 0.0, worst_hourglass_ratio = 0.0;
  while (solver.time() < 0.15 + 3.2 * period_guess) {
    solver.step(dt);
    const double now = tip_deflection(solver, tip);
    if (previous < 0.0 && now >= 0.0) {
      crossings.push_back(solver.time() - dt * now / (now - previous));
    }
    previous = now;
    const ShellEnergies& e = solver.energies();
    worst_drift = std::max(
        worst_drift, std::abs(e.kinetic + e.internal + e.hourglass - e.external_work - energy0));
    if (e.internal > 0.0) worst_hourglass_ratio = std::max(worst_hourglass_ratio, e.hourglass / e.internal);
  }
  ASSERT_GE(crossings.size(), 3u);
  const double period = (crossings.back() - crossings.front()) / (crossings.size() - 1.0);
  const double frequency = 1.0 / period;
  const double beam_frequency = omega1 / (2.0 * std::numbers::pi);
  std::printf("cantilever: f1 %.4f Hz, beam %.4f Hz (%+.3f %%); energy drift %.3e of %.3e J, "
              "hourglass/internal ≤ %.2e\n",
              frequency, beam_frequency, 100.0 * (frequency / beam_frequency - 1.0), worst_drift,
              vibration_energy, worst_hourglass_ratio);
  EXPECT_LT(worst_drift, 1e-3 * vibration_energy);
  EXPECT_LT(worst_hourglass_ratio, 0.05);
  EXPECT_FALSE(solver.energies().hourglass_warning);
  EXPECT_NEAR(beam_frequency, 16.71, 0.01);
  EXPECT_NEAR(frequency, beam_frequency, 0.03 * beam_frequency);
}

}  // namespace
}  // namespace quarry::fem
