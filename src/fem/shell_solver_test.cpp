// Solver mechanics: the stable step L_c/c (c = √(E/(ρ(1 − ν²))), L_c = A/max edge for quads,
// 2A/max edge for triangles: LS-DYNA's shell rule, research note §1.2) and its limiting
// element; mass scaling to a target step with the added mass reported; the critical step of
// the one-point quad measured against its highest eigenvalue (regular mesh ω = 2c/L, a lone
// element's dilatational mode ω = 2c√(1 + ν)/L; docs/fem.md); bit-identical results with 1
// and 2 threads; energy balance of a triangle mesh; model validation errors.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <numbers>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "core/diagnostics.h"
#include "core/shared_loop.h"
#include "fem/shell_solver.h"
#include "fem/shell_test_meshes.h"

namespace quarry::fem {
namespace {

using testing::near;

const double kPlateSpeed = std::sqrt(210e9 / (7850.0 * (1.0 - 0.09)));  // c (m/s)

TEST(ShellStableStep, IsTheCharacteristicLengthOverThePlateWaveSpeed) {
  // 4 × 3 quads of 20 mm × 10 mm: L_c = A / max edge = 2e-4 / 0.02 = 0.01 m.
  ShellModel model = testing::rectangle(4, 3, 0.08, 0.03, 0.002);
  const StableTimeStep quads = ShellSolver(model).stable_time_step();
  EXPECT_NEAR(quads.characteristic_length, 0.01, 1e-15);
  EXPECT_NEAR(quads.wave_speed, kPlateSpeed, 1e-9 * kPlateSpeed);
  EXPECT_NEAR(quads.time_step, 0.01 / kPlateSpeed, 1e-12 * quads.time_step);
  // Triangles: right triangles with legs 20 mm and 10 mm, smallest altitude 2A/hypotenuse.
  ShellModel triangles = testing::rectangle(4, 3, 0.08, 0.03, 0.002, testing::MeshKind::triangles);
  const double altitude = 0.02 * 0.01 / std::sqrt(0.02 * 0.02 + 0.01 * 0.01);
  EXPECT_NEAR(ShellSolver(triangles).stable_time_step().time_step, altitude / kPlateSpeed,
              1e-12 * altitude / kPlateSpeed);
  // Shrink the cells of column 2 (element 6 in row 1, ...) in x: the first of them limits.
  ShellModel narrow = testing::rectangle(4, 3, 0.08, 0.03, 0.002);
  for (int j = 0; j <= 3; ++j) narrow.nodes[j * 5 + 3].x = 0.045;  // column 2 is 5 mm wide
  const StableTimeStep limited = ShellSolver(narrow).stable_time_step();
  EXPECT_EQ(limited.element, 2);
  EXPECT_NEAR(limited.characteristic_length, 0.005 * 0.01 / 0.01, 1e-15);
}

// stable_time_step screens the elements by a cheaper form of the same step (the area from the
// diagonals' cross product) and estimates exactly only those near the least: it must name the
// element and the step that estimating every element in order gives, to the bit, also where
// several elements tie within round-off (a narrow column of equal cells) and on warped, jittered
// quads and triangles of two materials.
TEST(ShellStableStep, TheScreenedSearchGivesTheExhaustiveAnswerToTheBit) {
  const auto exhaustive = [](const ShellModel& model, std::span<const Vec3> x) {
    StableTimeStep best;
    best.time_step = INFINITY;
    for (std::size_t e = 0; e < model.elements.size(); ++e) {
      const ShellElement& element = model.elements[e];
      std::array<Vec3, 4> corners{};
      for (int i = 0; i < element.node_count; ++i) corners[i] = x[element.nodes[i]];
      const ShellMaterial& m = model.materials[model.sections[element.section].material];
      const double speed =
          std::sqrt(m.youngs_modulus / (m.density * (1.0 - m.poisson_ratio * m.poisson_ratio)));
      const double length = characteristic_length(corners, element.node_count);
      if (length / speed < best.time_step) best = {length / speed, static_cast<int>(e), length, speed};
    }
    return best;
  };
  const auto expect_same = [&](const ShellModel& model, const char* what) {
    ShellSolver solver(model);
    const StableTimeStep screened = solver.stable_time_step();
    const StableTimeStep all = exhaustive(model, solver.positions());
    EXPECT_EQ(screened.element, all.element) << what;
    EXPECT_EQ(screened.time_step, all.time_step) << what;
    EXPECT_EQ(screened.characteristic_length, all.characteristic_length) << what;
  };
  // Ties: column 3 of 12 × 8 cells shrunk to 2 mm, its eight cells equal but for round-off.
  ShellModel narrow = testing::rectangle(12, 8, 0.12, 0.08, 0.002);
  for (int j = 0; j <= 8; ++j) narrow.nodes[j * 13 + 4].x = 0.032;
  expect_same(narrow, "narrow column");
  // Jittered and warped: every node moved by up to 2 mm in plane and 1 mm out of it.
  std::uint64_t seed = 12345;
  const auto uniform = [&seed] {  // in [−1, 1)
    seed = seed * 6364136223846793005ULL + 1442695040888963407ULL;
    return static_cast<double>(seed >> 11) / 4503599627370496.0 - 1.0;
  };
  for (const testing::MeshKind kind : {testing::MeshKind::quads, testing::MeshKind::triangles}) {
    ShellModel mesh = testing::rectangle(12, 8, 0.12, 0.08, 0.002, kind);
    for (Vec3& node : mesh.nodes) node += Vec3{2e-3 * uniform(), 2e-3 * uniform(), 1e-3 * uniform()};
    // A second, lighter material on every third element.
    mesh.materials.push_back({70e9, 0.33, 2700.0, 0.0, 0.0});
    mesh.sections.push_back({0.003, 5, ThicknessRule::lobatto, 1});
    for (std::size_t e = 0; e < mesh.elements.size(); e += 3) mesh.elements[e].section = 1;
    expect_same(mesh, kind == testing::MeshKind::quads ? "jittered quads" : "jittered triangles");
  }
}

TEST(ShellStableStep, MassScalingReachesTheTargetAndReportsTheAddedMass) {
  ShellModel model = testing::rectangle(4, 3, 0.08, 0.03, 0.002);
  for (int j = 0; j <= 3; ++j) model.nodes[j * 5 + 3].x = 0.045;
  const ShellSolver plain(model);
  const double target = 0.008 / kPlateSpeed;  // between the narrow column's and the others' step
  ShellSolverOptions options;
  options.mass_scaling_time_step = target;
  const ShellSolver scaled(model, options);
  EXPECT_NEAR(scaled.stable_time_step().time_step, target, 1e-12 * target);
  // Only the three narrow cells (L_c 5 mm) are scaled: ρ' = ρ (8/5)², added (ρ' − ρ) t A each.
  const double added = 3.0 * 7850.0 * (1.6 * 1.6 - 1.0) * 0.002 * (0.005 * 0.01);
  EXPECT_NEAR(scaled.added_mass(), added, 1e-12 * added);
  EXPECT_NEAR(scaled.total_mass() - plain.total_mass(), added, 1e-9 * added);
  EXPECT_EQ(plain.added_mass(), 0.0);
  std::printf("mass scaling: step %.4e s -> %.4e s (target %.4e s), added mass %.4e kg of %.4e\n",
              plain.stable_time_step().time_step, scaled.stable_time_step().time_step, target,
              scaled.added_mass(), plain.total_mass());
}

// Largest kinetic energy over 3000 steps relative to the initial total, for a free mesh started
// with a velocity pattern (∞ if the run diverged).
template <class Pattern>
double growth(const ShellModel& model, Pattern pattern, double fraction_of_stable_step) {
  ShellSolver solver(model);
  for (int n = 0; n < solver.node_count(); ++n) solver.set_velocity(n, pattern(n), {});
  const double dt = fraction_of_stable_step * solver.stable_time_step().time_step;
  solver.step(dt);
  const double initial = solver.energies().kinetic + solver.energies().internal;
  double largest = initial;
  try {
    for (int s = 0; s < 3000; ++s) {
      solver.step(dt);
      largest = std::max(largest, solver.energies().kinetic);
    }
  } catch (const PhysicsError&) {
    return INFINITY;
  }
  return largest / initial;
}

TEST(ShellStableStep, CriticalStepOfTheOnePointQuadMatchesTheory) {
  // Regular mesh of squares L: the highest mode is v_x = (−1)^i (each element stretched by
  // 2/L, ω² = 4 c²/L² with row-sum mass), so the critical step is exactly L/c = L_c/c.
  const ShellModel mesh = testing::rectangle(6, 6, 0.06, 0.06, 0.001);
  auto stretch = [](int n) { return Vec3{(n % 7) % 2 ? 1e-3 : -1e-3, 0.0, 0.0}; };
  const double mesh_below = growth(mesh, stretch, 0.97), mesh_above = growth(mesh, stretch, 1.03);
  // A lone element has the dilatational mode v = ±(x, y) (ε_xx = ε_yy = 2/L), ω² = 4 c² (1 + ν)/L²:
  // critical at L/(c √(1 + ν)) = 0.877 L_c/c. Neighbours cannot all share it, so meshes don't.
  const ShellModel single = testing::rectangle(1, 1, 0.01, 0.01, 0.001);
  auto dilate = [](int n) {
    return Vec3{n % 2 ? 1e-3 : -1e-3, n / 2 ? 1e-3 : -1e-3, 0.0};
  };
  const double bound = 1.0 / std::sqrt(1.3);
  const double single_below = growth(single, dilate, 0.97 * bound);
  const double single_above = growth(single, dilate, 1.03 * bound);
  std::printf("critical step: mesh energy ratio %.3g at 0.97 L_c/c, %.3g at 1.03; lone element "
              "%.3g at 0.97·0.877 L_c/c, %.3g at 1.03·0.877\n",
              mesh_below, mesh_above, single_below, single_above);
  EXPECT_LT(mesh_below, 2.0);
  EXPECT_GT(mesh_above, 1e6);
  EXPECT_LT(single_below, 2.0);
  EXPECT_GT(single_above, 1e6);
}

TEST(ShellEnergy, TriangleMeshFreeVibrationConservesEnergy) {
  // Clamped triangle strip started with the velocity of a smooth bending shape, undamped:
  // kinetic + internal + hourglass stays within 1e-3 of the initial kinetic energy.
  ShellModel model = testing::rectangle(10, 2, 0.5, 0.05, 0.005, testing::MeshKind::triangles);
  model.boundary_conditions.push_back(
      {testing::nodes_where(model, [](const Vec3& p) { return near(p.x, 0.0); }), dof::all, {}});
  ShellSolver solver(model);
  for (int n = 0; n < solver.node_count(); ++n) {
    const double s = model.nodes[n].x / 0.5;
    solver.set_velocity(n, {0.0, 0.0, 0.1 * s * s}, {0.0, -0.1 * 2.0 * s / 0.5, 0.0});
  }
  const double dt = 0.8 * solver.stable_time_step().time_step;
  solver.step(dt);
  const double start = solver.energies().kinetic + solver.energies().internal;
  double drift = 0.0;
  for (int s = 0; s < 8000; ++s) {
    solver.step(dt);
    const ShellEnergies& e = solver.energies();
    drift = std::max(drift, std::abs(e.kinetic + e.internal + e.hourglass - start));
  }
  std::printf("triangle strip: energy drift %.3e of %.3e J over 8000 steps\n", drift, start);
  EXPECT_GT(start, 0.0);
  EXPECT_LT(drift, 1e-3 * start);
}

// A clamped 60 mm plate, 5 mm thick, 8 × 8 quads, hammered by transverse point loads (one
// node in twenty, random in [0, 750] N, redrawn every 48 steps — a coupled surface's loads
// under a pour), mass-proportional damping 20 1/s: the loads' work W must equal kinetic +
// internal + hourglass energy + damping loss. The element kernel works in the mid-step
// configuration x(t + dt/2): there a rigid rotation has no strain rate (Hughes & Winget, IJNME
// 15, 1980, incremental objectivity). On x(t + dt), as before, each step added a stretch
// ½(Ω dt)² at an element rotating at Ω, whatever the sign of Ω, so vibration ratcheted
// membrane stress: here 6.5 J of strain energy from 1.7 J of work by 0.05 s (3.7 GPa mid-plane
// stress by 0.2 s), and the coupled truck bed pumped itself to kJ. Now the balance holds to
// 0.3 % (the central difference's first-order error for loads switched every 48 steps: it
// halves with the step); bound 2 %.
TEST(ShellEnergy, TransverseImpulsesCreateNoEnergy) {
  ShellModel model = testing::rectangle(8, 8, 0.06, 0.06, 0.005);
  model.boundary_conditions.push_back({testing::nodes_where(model, [](const Vec3& p) {
                                         return near(p.x, 0.0) || near(p.x, 0.06) || near(p.y, 0.0) || near(p.y, 0.06);
                                       }),
                                       dof::all, {}});
  ShellSolverOptions options;
  options.damping = 20.0;  // 1/s
  ShellSolver solver(model, options);
  const double dt = 0.9 * solver.stable_time_step().time_step;
  std::uint64_t state = 88172645463325252ull;  // xorshift64: the same loads on every platform
  const auto uniform = [&state] {             // in [0, 1)
    state ^= state << 13;
    state ^= state >> 7;
    state ^= state << 17;
    return static_cast<double>(state >> 11) * 0x1.0p-53;
  };
  std::vector<NodalLoad> loads(static_cast<std::size_t>(solver.node_count()));
  double deepest = 0.0;  // m
  for (int s = 0; s < 40000; ++s) {
    if (s % 48 == 0) {
      for (NodalLoad& load : loads) load.force = uniform() < 0.05 ? Vec3{0.0, 0.0, -750.0 * uniform()} : Vec3{};
      solver.set_loads(loads);
    }
    solver.step(dt);
    for (const Vec3& x : solver.positions()) deepest = std::max(deepest, std::abs(x.z));
  }
  const ShellEnergies& e = solver.energies();
  const double held = e.kinetic + e.internal + e.hourglass + e.damping;  // J
  std::printf("hammered plate: work %.4e J, kinetic %.3e + internal %.3e + hourglass %.3e + damping %.3e = %.4e J "
              "(%+.3f %%); deepest %.3e m\n",
              e.external_work, e.kinetic, e.internal, e.hourglass, e.damping, held,
              100.0 * (held / e.external_work - 1.0), deepest);
  EXPECT_GT(deepest, 1e-5);  // the loads bent the plate (5 mm thick: w/t ≈ 1 %)
  EXPECT_NEAR(held, e.external_work, 0.02 * e.external_work);
}

// Supports are the constrained nodes joined by element edges: two clamped opposite edges are
// two supports (in the order of their smallest node), a lone pinned node its own, a clamped
// ring one with every constrained node an element edge joins to it; nodes without a
// constraint belong to none.
TEST(ShellModelSupports, ConstrainedNodesJoinedByElementEdges) {
  ShellModel model = testing::rectangle(4, 2, 0.4, 0.2, 0.005);  // node (i, j) = 5 j + i
  EXPECT_TRUE(support_groups(model).empty());
  model.boundary_conditions.push_back({testing::nodes_where(model, [](const Vec3& p) { return near(p.x, 0.4); }), dof::all, {}});
  model.boundary_conditions.push_back({testing::nodes_where(model, [](const Vec3& p) { return near(p.x, 0.0); }), dof::translations, {}});
  model.boundary_conditions.push_back({{7}, dof::translations, {}});  // (2, 1), the middle
  const std::vector<std::vector<std::int32_t>> groups = support_groups(model);
  ASSERT_EQ(groups.size(), 3u);
  EXPECT_EQ(groups[0], (std::vector<std::int32_t>{0, 5, 10}));  // x = 0
  EXPECT_EQ(groups[1], (std::vector<std::int32_t>{4, 9, 14}));  // x = 0.4
  EXPECT_EQ(groups[2], (std::vector<std::int32_t>{7}));
  model.boundary_conditions.push_back({testing::nodes_where(model, [](const Vec3& p) { return near(p.y, 0.0) || near(p.y, 0.2); }), dof::all, {}});
  // The whole edge clamped: one ring of 12 nodes, and the middle node joins it along the
  // element edges (2, 0)–(2, 1)–(2, 2): one support of 13.
  const std::vector<std::vector<std::int32_t>> ring = support_groups(model);
  ASSERT_EQ(ring.size(), 1u);
  EXPECT_EQ(ring[0].size(), 13u);
}

TEST(ShellCorotation, RigidSpinAboutAnInPlaneAxisStrainsNothing) {
  // A free 2 × 2 plate (quads, or triangles) spun at 10 rad/s about the x axis through its
  // centre for a quarter turn: the co-rotational frames must see no strain. The only physical
  // strain is the centrifugal stretch, stress ~ ρ ω² r² ≈ 8e3 Pa, energy ~1e-9 of the kinetic.
  for (const testing::MeshKind kind : {testing::MeshKind::quads, testing::MeshKind::triangles}) {
    const ShellModel model = testing::rectangle(2, 2, 0.1, 0.1, 0.002, kind);
    ShellSolver solver(model);
    const Vec3 spin{10.0, 0.0, 0.0}, centre{0.05, 0.05, 0.0};
    for (int n = 0; n < solver.node_count(); ++n) {
      solver.set_velocity(n, cross(spin, model.nodes[n] - centre), spin);
    }
    const double dt = 0.8 * solver.stable_time_step().time_step;
    const int steps = static_cast<int>(0.5 * std::numbers::pi / norm(spin) / dt);
    double largest_internal = 0.0;
    for (int s = 0; s < steps; ++s) {
      solver.step(dt);
      largest_internal = std::max(largest_internal, std::abs(solver.energies().internal) +
                                                        std::abs(solver.energies().hourglass));
    }
    // After a quarter turn the plate stands in the x-z plane: node (x, 0.1) is at z ≈ +0.05.
    const Vec3 corner = solver.positions()[solver.node_count() - 1];
    std::printf("rigid spin (%s): strain energy ≤ %.2e J against kinetic %.2e J; far corner at "
                "(%.5f, %.5f, %.5f) m\n",
                kind == testing::MeshKind::quads ? "quads" : "triangles", largest_internal,
                solver.energies().kinetic, corner.x, corner.y, corner.z);
    EXPECT_LT(largest_internal, 1e-6 * solver.energies().kinetic);
    EXPECT_NEAR(corner.y, 0.05, 1e-4);
    EXPECT_NEAR(corner.z, 0.05, 1e-4);
  }
}

TEST(ShellEnergy, HourglassWarningRisesForAnHourglassMotion) {
  // One free quad with the w-hourglass pattern v_z = ±(1, −1, 1, −1) mm/s: only the hourglass
  // control resists it, so the hourglass energy exceeds 5 % of the internal energy.
  const ShellModel model = testing::rectangle(1, 1, 0.02, 0.02, 0.002);
  ShellSolver solver(model);
  const double pattern[4] = {1e-3, -1e-3, -1e-3, 1e-3};  // nodes (0,0), (L,0), (0,L), (L,L)
  for (int n = 0; n < 4; ++n) solver.set_velocity(n, {0.0, 0.0, pattern[n]}, {});
  const double dt = 0.8 * solver.stable_time_step().time_step;
  for (int s = 0; s < 50; ++s) solver.step(dt);
  EXPECT_GT(solver.energies().hourglass, 0.05 * solver.energies().internal);
  EXPECT_TRUE(solver.energies().hourglass_warning);
}

// A mixed quad/triangle plate with plasticity, loads and damping, stepped with 1 and 2 threads,
// and on one thread whose loops another thread joins (SharedLoop, as the structure beside the
// DEM): positions, velocities, energies and stresses must be the same bits.
TEST(ShellDeterminism, OneAndTwoThreadsGiveIdenticalBits) {
  auto run = [](int threads, SharedLoop* shared = nullptr) {
    ShellModel model = testing::rectangle(8, 8, 0.2, 0.2, 0.003, testing::MeshKind::quads, 5,
                                          ThicknessRule::lobatto, testing::steel(250e6, 1e9));
    // Cut the last row of cells into triangles.
    std::vector<ShellElement> elements;
    for (const ShellElement& e : model.elements) {
      if (model.nodes[e.nodes[0]].y > 0.17) {
        elements.push_back({{e.nodes[0], e.nodes[1], e.nodes[2], 0}, 3, 0});
        elements.push_back({{e.nodes[0], e.nodes[2], e.nodes[3], 0}, 3, 0});
      } else {
        elements.push_back(e);
      }
    }
    model.elements = elements;
    model.boundary_conditions.push_back(
        {testing::nodes_where(model, [](const Vec3& p) { return near(p.x, 0.0); }), dof::all, {}});
    ShellSolverOptions options;
    options.damping = 50.0;
    options.threading.threads = threads;
    options.threading.threshold = 0;
    options.threading.shared = shared;
    ShellSolver solver(model, options);
    std::vector<NodalLoad> loads(model.nodes.size());
    for (std::size_t n = 0; n < loads.size(); ++n) {
      loads[n].force = {0.0, 0.0, -200.0 - 100.0 * std::sin(static_cast<double>(n))};
    }
    solver.set_loads(loads);
    const double dt = 0.8 * solver.stable_time_step().time_step;
    for (int s = 0; s < 300; ++s) solver.step(dt);
    return solver;
  };
  const ShellSolver one = run(1);
  SharedLoop shared;
  std::atomic<bool> stop{false};
  std::atomic<int> helped{0};
  std::thread helper([&] {
    while (!stop.load()) helped += shared.help() ? 1 : 0;
  });
  const ShellSolver joined = run(1, &shared);
  stop = true;
  helper.join();
  std::cout << "the helper ran items in " << helped.load() << " of the shared loops\n";
  const ShellSolver two = run(2);
  double plastic = 0.0;
  for (const ShellSolver* other : {&two, &joined}) {
    ASSERT_EQ(one.node_count(), other->node_count());
    EXPECT_EQ(0, std::memcmp(one.positions().data(), other->positions().data(),
                             one.positions().size_bytes()));
    EXPECT_EQ(0, std::memcmp(one.velocities().data(), other->velocities().data(),
                             one.velocities().size_bytes()));
    EXPECT_EQ(0, std::memcmp(one.angular_velocities().data(), other->angular_velocities().data(),
                             one.angular_velocities().size_bytes()));
    EXPECT_EQ(one.energies().internal, other->energies().internal);
    EXPECT_EQ(one.energies().hourglass, other->energies().hourglass);
    EXPECT_EQ(one.energies().kinetic, other->energies().kinetic);
    for (int e = 0; e < one.element_count(); ++e) {
      EXPECT_EQ(one.element_result(e).von_mises_top, other->element_result(e).von_mises_top);
      plastic = std::max(plastic, one.element_result(e).plastic_strain_max);
    }
  }
  EXPECT_GT(plastic, 0.0);  // the run did reach the plastic branch
}

void expect_model_error(const ShellModel& model, const std::string& fragment) {
  try {
    ShellSolver solver(model);
    ADD_FAILURE() << "no error for: " << fragment;
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find(fragment), std::string::npos) << error.what();
  }
}

TEST(ShellModelValidation, NamesTheElementAndTheValue) {
  const ShellModel good = testing::rectangle(2, 1, 0.2, 0.1, 0.002);
  EXPECT_NO_THROW(ShellSolver{good});
  ShellModel collinear = good;
  collinear.nodes.push_back({0.3, 0.0, 0.0});
  collinear.nodes.push_back({0.4, 0.0, 0.0});
  collinear.elements.push_back({{1, 2, 7, 0}, 3, 0});
  collinear.nodes[7] = {0.25, 0.0, 0.0};  // on the line through nodes 1 and 2
  expect_model_error(collinear, "element 2: degenerate");
  ShellModel repeated = good;
  repeated.elements[1].nodes = {1, 2, 2, 4};
  expect_model_error(repeated, "element 1: node 2 appears twice");
  ShellModel thin = good;
  thin.sections[0].thickness = 0.0;
  expect_model_error(thin, "section 0: thickness 0 m must be > 0");
  ShellModel rubber = good;
  rubber.materials[0].poisson_ratio = 0.5;
  expect_model_error(rubber, "material 0: Poisson's ratio 0.5");
  ShellModel missing = good;
  missing.elements[0].nodes[2] = 99;
  expect_model_error(missing, "element 0: node 99 does not exist");
  ShellModel bowtie = good;
  std::swap(bowtie.elements[0].nodes[2], bowtie.elements[0].nodes[3]);
  expect_model_error(bowtie, "element 0:");
}

}  // namespace
}  // namespace quarry::fem

namespace quarry::fem {
namespace {

// Checkpoints (fsi/structure_checkpoint.cpp): a solver given another's state mid-run (plastic
// points, reactions, loads, a damping changed on the way) takes the next steps to the same bits;
// a state that does not fit the model is refused and changes nothing.
TEST(ShellSolverState, ASolverGivenTheStateStepsToTheSameBits) {
  ShellModel model = testing::rectangle(6, 2, 0.06, 0.02, 0.001, testing::MeshKind::quads, 5,
                                        ThicknessRule::lobatto, testing::steel(5.0e7, 1.0e9));
  const auto root = testing::nodes_where(model, [](const Vec3& x) { return x.x == 0.0; });
  const auto tip = testing::nodes_where(model, [](const Vec3& x) { return std::abs(x.x - 0.06) < 1e-12; });
  model.boundary_conditions = {{root, dof::all, {}}, {tip, dof::uz, {0.0, 0.0, -10.0}}};
  ShellSolverOptions options;
  options.damping = 100.0;
  ShellSolver first(model, options);
  const double dt = 0.8 * first.stable_time_step().time_step;
  std::vector<NodalLoad> loads(model.nodes.size());
  loads[3].force = {0.0, 5.0, -1.0};
  first.set_loads(loads);
  for (int s = 0; s < 300; ++s) first.step(dt);
  first.set_damping(50.0);
  const ShellSolverState saved = first.state();
  for (int s = 0; s < 200; ++s) first.step(dt);

  ShellSolver second(model, options);
  ShellSolverState wrong = saved;
  wrong.plastic.pop_back();
  EXPECT_THROW(second.set_state(wrong), std::invalid_argument);
  wrong = saved;
  wrong.velocities[2].y = std::nan("");
  EXPECT_THROW(second.set_state(wrong), std::invalid_argument);
  EXPECT_EQ(second.step_count(), 0);  // refused: unchanged
  second.set_state(saved);
  for (int s = 0; s < 200; ++s) second.step(dt);

  const ShellSolverState a = first.state(), b = second.state();
  double plastic = 0.0;
  for (const double p : a.plastic) plastic = std::max(plastic, p);
  EXPECT_GT(plastic, 0.0);  // the plastic points are part of what is carried
  EXPECT_EQ(a.steps, b.steps);
  EXPECT_EQ(a.time, b.time);
  EXPECT_EQ(std::memcmp(a.positions.data(), b.positions.data(), a.positions.size() * sizeof(Vec3)), 0);
  EXPECT_EQ(std::memcmp(a.velocities.data(), b.velocities.data(), a.velocities.size() * sizeof(Vec3)), 0);
  EXPECT_EQ(a.stress, b.stress);
  EXPECT_EQ(a.plastic, b.plastic);
  EXPECT_EQ(a.hourglass, b.hourglass);
  EXPECT_EQ(a.energies.internal, b.energies.internal);
  EXPECT_EQ(a.energies.external_work, b.energies.external_work);
  EXPECT_EQ(a.energies.damping, b.energies.damping);
  EXPECT_EQ(a.energies.constraint_work, b.energies.constraint_work);
}

}  // namespace
}  // namespace quarry::fem
