// Blocked fluid cells from the deck's geometry (issue #18 §1): the mask of boxes, half-spaces and
// closed surfaces; the errors at the deck's keys (open surface, nothing blocked, everything
// blocked, fluid cut off from the outlets); and a coupled channel around a blocked obstacle —
// continuity through every layer of faces, zero velocity on every blocked face, the particles'
// volume and the exchanged momentum whole on fluid cells, 1 vs 2 threads bit for bit.
#include "cfdem/fluid_blocked.h"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <numbers>
#include <sstream>

#include "cfdem/fluid_monitors.h"
#include "cfdem/fluid_output.h"
#include "cfdem/fluid_setup.h"
#include "cfdem/fluid_test_support.h"
#include "geometry/icosphere.h"
#include "geometry/stl_reader.h"
#include "io/deck.h"
#include "sim/exchange.h"
#include "sim/step.h"

namespace quarry::cfdem {
namespace {

// A 12 x 4 x 3 mm channel of 1 mm cells: an inlet at x_min (10 mm/s), an outlet at x_max, walls
// on the other faces; `blocked` is the fluid.blocked list, `surfaces` the surfaces: section.
std::string channel_deck(const std::string& blocked, const std::string& surfaces = "",
                         const std::string& boundaries = "") {
  return fmt::format(R"(simulation:
  end_time: 0.01
  time_step: 2.0e-6
  impact_speed: 0.01
  gravity: [0, 0, -9.81]
  sort_interval: 0
  domain: {{min: [0, 0, 0], max: [0.012, 0.004, 0.003]}}
materials:
  - {{name: glass, density: 2500, youngs_modulus: 1.0e7, poisson_ratio: 0.25}}
interactions:
  - {{materials: [glass, glass]}}
particle_types:
  - {{name: bead, material: glass, size: {{distribution: fixed, radius: 2.0e-4}}}}
{}fluid:
  time_step: 1.0e-4
  grid: {{origin: [0, 0, 0], cell_size: 0.001, cells: [12, 4, 3]}}
  boundaries:
{}  drag_law: schiller_naumann
  blocked:
{})",
                     surfaces,
                     boundaries.empty() ? "    x_min: {type: velocity_inlet, velocity: [0.01, 0, 0]}\n"
                                          "    x_max: {type: pressure_outlet, reference_point: [0.012, 0, 0.003]}\n"
                                        : boundaries,
                     blocked);
}

// An obstacle of 2 x 2 x 3 cells on the y_min wall in mid-channel, and a column of 3 cells at the
// inlet's y_max corner (its inlet faces feed nothing).
const char* kObstacles = "    - {type: box, min: [0.005, 0, 0], max: [0.007, 0.002, 0.003]}\n"
                         "    - {type: box, min: [0, 0.003, 0], max: [0.001, 0.004, 0.003]}\n";

bool in_obstacles(int i, int j, int) { return ((i == 5 || i == 6) && j <= 1) || (i == 0 && j == 3); }

World channel_world(const std::string& deck, int threads = 1) {
  World world = build_world(parse_deck_string(deck, "channel.yaml"));
  world.threading = Threading{threads, 0};
  return world;
}

// The formatted errors of building the coupling from the deck ("" when it builds).
std::string setup_errors(const std::string& deck) {
  return testing::fluid_setup_errors(deck, "channel.yaml");
}

// "channel.yaml:line:col" of the `occurrence`-th `needle` in `text`.
std::string at(const std::string& text, const std::string& needle, int occurrence = 1) {
  std::size_t found = std::string::npos;
  for (int n = 0; n < occurrence; ++n) found = text.find(needle, found == std::string::npos ? 0 : found + 1);
  const std::size_t line_start = text.rfind('\n', found) + 1;
  const auto line = 1 + std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(found), '\n');
  return fmt::format("channel.yaml:{}:{}", line, found - line_start + 1);
}

// Box, half-space and closed surfaces (a box surface, whose normals point inwards, and an inline
// mesh cube, outwards) give exactly the cells whose centres they hold.
TEST(FluidBlocked, MaskFromBoxesHalfSpacesAndSurfaces) {
  const std::string surfaces = R"(surfaces:
  - {name: post, type: box, min: [0.008, 0.001, 0], max: [0.01, 0.003, 0.003], material: glass}
  - name: cube
    type: mesh
    material: glass
    vertices: [[0.002, 0.001, 0.001], [0.004, 0.001, 0.001], [0.002, 0.003, 0.001], [0.004, 0.003, 0.001],
               [0.002, 0.001, 0.003], [0.004, 0.001, 0.003], [0.002, 0.003, 0.003], [0.004, 0.003, 0.003]]
    triangles: [[0, 4, 6], [0, 6, 2], [1, 3, 7], [1, 7, 5], [0, 1, 5], [0, 5, 4],
                [2, 6, 7], [2, 7, 3], [0, 2, 3], [0, 3, 1], [4, 5, 7], [4, 7, 6]]
)";
  const std::string deck = channel_deck("    - {type: box, min: [0.005, 0, 0], max: [0.007, 0.002, 0.003]}\n"
                                        "    - {type: half_space, point: [0, 0, 0.002], normal: [0, 0, -1]}\n"
                                        "    - {type: surface, surface: post}\n"
                                        "    - {type: surface, surface: cube}\n",
                                        surfaces);
  World world = channel_world(deck);
  const FluidCouplingOptions options = coupling_options_from_spec(world);
  const cfd::FluidGrid& g = options.grid;
  ASSERT_EQ(options.blocked.size(), g.cell_count());
  std::size_t count = 0;
  for (int k = 0; k < 3; ++k)
    for (int j = 0; j < 4; ++j)
      for (int i = 0; i < 12; ++i) {
        const bool box = (i == 5 || i == 6) && j <= 1;
        const bool half_space = k == 2;                                 // z ≥ 0.002
        const bool post = (i == 8 || i == 9) && (j == 1 || j == 2);     // all k
        const bool cube = (i == 2 || i == 3) && (j == 1 || j == 2) && k >= 1;
        const bool expected = box || half_space || post || cube;
        EXPECT_EQ(options.blocked[g.cell_index(i, j, k)], expected ? 1 : 0) << i << " " << j << " " << k;
        count += expected;
      }
  // Box 12, half-space 48 (4 of them the box's), post 12 (4 the half-space's), cube 8 (4 too).
  EXPECT_EQ(count, 12u + 44u + 8u + 4u);
  EXPECT_EQ(std::count(options.blocked.begin(), options.blocked.end(), 1), static_cast<std::ptrdiff_t>(count));
}

// Errors of the built geometry, each at its entry or key in the deck.
TEST(FluidBlocked, RefusesOpenSurfacesEmptyEntriesAndCutOffFluid) {
  // A plane surface has no inside.
  std::string deck = channel_deck("    - {type: surface, surface: floor}\n",
                                  "surfaces:\n  - {name: floor, type: plane, point: [0.006, 0.002, 0.0015], normal: "
                                  "[0, 0, 1], size: 0.002, material: glass}\n");
  std::string errors = setup_errors(deck);
  EXPECT_NE(errors.find(at(deck, "floor}") + ": error: surface \"floor\" is not closed, so it has no inside: 4 of its "
                                            "edges belong to an odd number of triangles"),
            std::string::npos)
      << errors;
  EXPECT_NE(errors.find("hint: a blocked surface must be watertight"), std::string::npos) << errors;

  // A mesh cube without its top face.
  deck = channel_deck("    - {type: surface, surface: cup}\n", R"(surfaces:
  - name: cup
    type: mesh
    material: glass
    vertices: [[0.002, 0.001, 0.001], [0.004, 0.001, 0.001], [0.002, 0.003, 0.001], [0.004, 0.003, 0.001],
               [0.002, 0.001, 0.003], [0.004, 0.001, 0.003], [0.002, 0.003, 0.003], [0.004, 0.003, 0.003]]
    triangles: [[0, 4, 6], [0, 6, 2], [1, 3, 7], [1, 7, 5], [0, 1, 5], [0, 5, 4],
                [2, 6, 7], [2, 7, 3], [0, 2, 3], [0, 3, 1]]
)");
  errors = setup_errors(deck);
  EXPECT_NE(errors.find(at(deck, "cup}") + ": error: surface \"cup\" is not closed"), std::string::npos) << errors;
  EXPECT_NE(errors.find("4 of its edges"), std::string::npos) << errors;

  // A box between the cell centres, and one outside the grid.
  for (const char* entry : {"    - {type: box, min: [0.0051, 0, 0], max: [0.0054, 0.002, 0.003]}\n",
                            "    - {type: box, min: [0.02, 0, 0], max: [0.03, 0.002, 0.003]}\n"}) {
    deck = channel_deck(entry);
    errors = setup_errors(deck);
    EXPECT_NE(errors.find(at(deck, "{type: box") + ": error: this blocked box blocks no fluid cell: no cell centre lies in it"),
              std::string::npos)
        << errors;
  }

  // A half-space whose normal points into the solid blocks the whole grid.
  deck = channel_deck("    - {type: half_space, point: [0, 0, 0.05], normal: [0, 0, 1]}\n");
  errors = setup_errors(deck);
  EXPECT_NE(errors.find(at(deck, "- {type: half_space") + ": error: every one of the 144 fluid cells is blocked"),
            std::string::npos)
      << errors;

  // A wall across the channel: the inlet's side is cut off from the outlet.
  deck = channel_deck("    - {type: box, min: [0.005, 0, 0], max: [0.006, 0.004, 0.003]}\n");
  errors = setup_errors(deck);
  EXPECT_NE(errors.find(at(deck, "- {type: box") + ": error: 60 fluid cells (cells (0, 0, 0) to (4, 3, 2), within [0, 0, "
                                                   "0] to [0.005, 0.004, 0.003] m) are cut off by blocked cells from "
                                                   "every pressure outlet: the velocity inlet that feeds them has no way out"),
            std::string::npos)
      << errors;
  // The same wall in a closed box (walls all round): two regions, each without a pressure reference.
  deck = channel_deck("    - {type: box, min: [0.005, 0, 0], max: [0.006, 0.004, 0.003]}\n", "",
                      "    x_min: {type: wall}\n");
  errors = setup_errors(deck);
  EXPECT_NE(errors.find("60 fluid cells (cells (0, 0, 0) to (4, 3, 2), within [0, 0, 0] to [0.005, 0.004, 0.003] m) are "
                        "cut off by blocked cells from the rest of the fluid (72 cells)"),
            std::string::npos)
      << errors;
  // A gap of one cell keeps the channel open.
  EXPECT_EQ(setup_errors(channel_deck("    - {type: box, min: [0.005, 0, 0], max: [0.006, 0.003, 0.003]}\n")), "");
}

// The cut-off search on its own: a sealed pocket with a periodic axis that reconnects it.
TEST(FluidBlocked, CutOffFluidFollowsPeriodicFaces) {
  cfd::FluidGrid grid;
  grid.cells = {6, 3, 3};
  cfd::FluidBoundaries boundaries;
  boundaries.face(2, 1).kind = cfd::BoundaryKind::pressure_outlet;
  std::vector<std::uint8_t> blocked(grid.cell_count(), 0);
  for (int k = 0; k < 3; ++k)
    for (int j = 0; j < 3; ++j) blocked[grid.cell_index(2, j, k)] = 1;  // a wall at i = 2
  // Both sides reach the outlet at z_max.
  EXPECT_FALSE(find_cut_off_fluid(grid, boundaries, blocked).has_value());
  // Roof over i < 2: that pocket is sealed; unless x is periodic (it joins i = 5 across the faces).
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 2; ++i) blocked[grid.cell_index(i, j, 2)] = 1;
  const std::optional<CutOffFluid> cut = find_cut_off_fluid(grid, boundaries, blocked);
  ASSERT_TRUE(cut.has_value());
  EXPECT_EQ(cut->cells, 12u);
  EXPECT_EQ(cut->low, (std::array<int, 3>{0, 0, 0}));
  EXPECT_EQ(cut->high, (std::array<int, 3>{1, 2, 1}));
  boundaries.set_periodic(0);
  EXPECT_FALSE(find_cut_off_fluid(grid, boundaries, blocked).has_value());
}

// The sphere mesh of geometry/icosphere.h as a Surface: a closed surface.
Surface sphere_surface(const Vec3& centre, double radius, int levels) {
  TriangleMesh sphere = quarry::icosphere(centre, radius, levels);
  Surface surface;
  surface.vertices = std::move(sphere.vertices);
  surface.reference_vertices = surface.vertices;
  surface.triangles = std::move(sphere.triangles);
  surface.update_normals_and_areas();
  return surface;
}

// Closed STL surfaces (binary, float32 corners) as blocked regions: a cube on the cells blocks
// exactly its 4 x 4 x 4 cells, a sphere of 5 mm radius (1280 facets) every cell whose centre is
// clearly inside it and none clearly outside.
TEST(FluidBlocked, ClosedStlSurfacesBlockTheCellsInside) {
  namespace fs = std::filesystem;
  std::string folder = (fs::temp_directory_path() / "quarry_fluid_blocked_XXXXXX").string();
  ASSERT_NE(::mkdtemp(folder.data()), nullptr);
  Surface box;
  for (int v = 0; v < 8; ++v)
    box.vertices.push_back({(v & 1) ? 0.006 : 0.002, (v & 2) ? 0.006 : 0.002, (v & 4) ? 0.006 : 0.002});
  box.triangles = {{0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}, {0, 1, 5}, {0, 5, 4},
                   {2, 6, 7}, {2, 7, 3}, {0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}};
  box.update_normals_and_areas();
  write_stl_binary(folder + "/cube.stl", box);
  const Vec3 centre{0.0131, 0.0127, 0.0124};
  const double radius = 0.005;
  write_stl_binary(folder + "/sphere.stl", sphere_surface(centre, radius, 3));
  const std::string deck = fmt::format(R"(simulation:
  end_time: 0.01
  time_step: 2.0e-6
  impact_speed: 0.01
  domain: {{min: [0, 0, 0], max: [0.02, 0.02, 0.02]}}
materials:
  - {{name: glass, density: 2500, youngs_modulus: 1.0e7, poisson_ratio: 0.25}}
interactions:
  - {{materials: [glass, glass]}}
particle_types:
  - {{name: bead, material: glass, size: {{distribution: fixed, radius: 2.0e-4}}}}
surfaces:
  - {{name: cube, type: stl, file: "{0}/cube.stl", material: glass}}
  - {{name: ball, type: stl, file: "{0}/sphere.stl", material: glass}}
fluid:
  time_step: 1.0e-4
  grid: {{origin: [0, 0, 0], cell_size: 0.001, cells: [20, 20, 20]}}
  blocked:
    - {{type: surface, surface: cube}}
    - {{type: surface, surface: ball}}
)",
                                       folder);
  World world = build_world(parse_deck_string(deck, "stl.yaml"));
  const FluidCouplingOptions options = coupling_options_from_spec(world);
  fs::remove_all(folder);
  const cfd::FluidGrid& g = options.grid;
  std::size_t cube_cells = 0, ball_cells = 0, between = 0;
  for (int k = 0; k < 20; ++k)
    for (int j = 0; j < 20; ++j)
      for (int i = 0; i < 20; ++i) {
        const std::uint8_t flag = options.blocked[g.cell_index(i, j, k)];
        const bool in_cube = i >= 2 && i <= 5 && j >= 2 && j <= 5 && k >= 2 && k <= 5;
        if (in_cube) {
          EXPECT_EQ(flag, 1) << i << " " << j << " " << k;
          cube_cells += flag;
          continue;
        }
        const double r = norm(g.cell_centre(i, j, k) - centre);
        if (r < 0.99 * radius) EXPECT_EQ(flag, 1) << i << " " << j << " " << k;   // facets ≤ 0.5 % inside
        else if (r > radius * (1.0 + 1e-6)) EXPECT_EQ(flag, 0) << i << " " << j << " " << k;
        else ++between;
        ball_cells += flag;
      }
  const double ball = 4.0 / 3.0 * std::numbers::pi * std::pow(radius / 0.001, 3);  // in cells
  std::printf("[ measured ] cube %zu cells (64), sphere %zu cells (%.1f by volume; %zu centres within 1 %% of its "
              "surface)\n",
              cube_cells, ball_cells, ball, between);
  EXPECT_EQ(cube_cells, 64u);
  EXPECT_EQ(std::count(options.blocked.begin(), options.blocked.end(), 1), static_cast<std::ptrdiff_t>(64 + ball_cells));
  EXPECT_NEAR(static_cast<double>(ball_cells) / ball, 1.0, 0.03);
}

struct Channel {
  World world;
  std::shared_ptr<FluidCoupling> coupling;
};

// The channel with kObstacles, and `particles` beads placed next to the obstacle (their weights
// reach into it) and two inside it.
Channel channel(int threads, bool particles) {
  Channel c{channel_world(channel_deck(kObstacles), threads), nullptr};
  if (particles) {
    std::vector<sim::NewParticle> beads;
    for (int n = 0; n < 12; ++n) {
      sim::NewParticle bead;
      const double x = 0.0042 + 0.00031 * n;                      // from before the obstacle to past it
      const double y = (x > 0.005 && x < 0.007) ? 0.0023 : 0.0012;  // above it, or beside it
      bead.position = {x, y + 0.0001 * (n % 3), 0.0006 + 0.0007 * (n % 3)};
      bead.velocity = {0.002 * (n % 4), -0.001 * (n % 2), 0.0005 * (n % 3)};
      bead.radius = 2e-4;
      beads.push_back(bead);
    }
    for (const Vec3& inside : {Vec3{0.0056, 0.0005, 0.0015}, Vec3{0.0061, 0.0009, 0.0021}}) {
      sim::NewParticle bead;
      bead.position = inside;
      bead.radius = 2e-4;
      beads.push_back(bead);
    }
    sim::add_particles(c.world, beads);
  }
  c.coupling = attach_fluid_from_spec(c.world);
  return c;
}

// Flow around the obstacle: every layer of faces along the channel carries the inlet's flow (the
// inlet's faces of the blocked corner feed nothing: 9 of 12 faces at 10 mm/s), the faces of every
// blocked cell are at rest, and the flow speeds up in the gap beside the obstacle.
TEST(FluidBlocked, ChannelAroundABlockedBoxKeepsContinuity) {
  Channel c = channel(1, false);
  sim::initialize(c.world);
  sim::advance(c.world, 1000);  // 20 fluid steps of 0.1 ms
  const cfd::FluidSolver& fluid = c.coupling->fluid();
  ASSERT_EQ(c.coupling->blocked_cells().count, 15u);
  const double inlet = 9 * 1e-6 * 0.01;  // m³/s
  for (int layer = 0; layer <= 12; ++layer) {
    const double q = flow_rate(fluid, c.coupling->void_fraction(), 0, 0.001 * layer);
    EXPECT_NEAR(q / inlet, 1.0, 1e-7) << "layer " << layer;
  }
  int faces = 0;
  for (int k = 0; k < 3; ++k)
    for (int j = 0; j < 4; ++j)
      for (int i = 0; i < 12; ++i) {
        if (!in_obstacles(i, j, k)) continue;
        for (int axis = 0; axis < 3; ++axis) {
          std::array<int, 3> high{i, j, k};
          high[static_cast<std::size_t>(axis)] += 1;
          EXPECT_EQ(fluid.face_velocity(axis, i, j, k), 0.0) << axis << " low face of " << i << " " << j << " " << k;
          EXPECT_EQ(fluid.face_velocity(axis, high[0], high[1], high[2]), 0.0)
              << axis << " high face of " << i << " " << j << " " << k;
          faces += 2;
        }
      }
  EXPECT_EQ(faces, 90);
  const double gap = fluid.face_velocity(0, 6, 3, 1);  // beside the obstacle, mid-height
  std::printf("[ measured ] u_x in the gap beside the obstacle %.5g m/s (inlet 0.01), divergence %.3g 1/s\n", gap,
              fluid.divergence_norm());
  EXPECT_GT(gap, 0.012);
  // A plane through the obstacle averages the fluid columns only.
  double sum = 0.0;
  int columns = 0;
  for (int k = 0; k < 3; ++k)
    for (int j = 2; j < 4; ++j, ++columns) sum += fluid.pressure(5, j, k);
  EXPECT_DOUBLE_EQ(plane_pressure(fluid, 0, 0.0055), sum / columns);
}

// Particles beside and inside the obstacle: all their volume on fluid cells (Σ (1 − ε) V_cell = Σ
// V_p to 1e-12, ε = 1 in blocked cells), nothing deposited on blocked cells, and the fluid's
// sources at an exchange exactly what the particles' drag says: Σ_c β_c V = Σ_p β_p and Σ_c f_c V
// = Σ_p β_p v_p plus the previous interval's correction Σ_p β_p (v̄_p − v_p) (docs/cfd.md
// "Exact momentum exchange"), the particles' drag β_p (u_p − v_p) read from fluid cells only.
TEST(FluidBlocked, ParticlesBesideBlockedCellsKeepTheirVolumeAndMomentum) {
  Channel c = channel(1, true);
  const ParticleStore& p = c.world.particles;
  const BlockedCells& blocked = c.coupling->blocked_cells();
  sim::initialize(c.world);
  sim::advance(c.world, 149);  // the next step (150) makes the fourth exchange
  const std::vector<FrozenParticle> before = c.coupling->frozen();
  const std::vector<FrozenForce> forces_before = c.coupling->frozen_forces();
  const std::vector<VelocitySum> sums_before = c.coupling->velocity_sums();
  sim::advance(c.world, 1);
  ASSERT_EQ(c.coupling->exchanges(), 4);
  const cfd::FluidGrid& g = c.coupling->options().grid;
  double particle_volume = 0.0, solid = 0.0;  // m³
  for (std::size_t i = 0; i < p.size(); ++i) particle_volume += 4.0 / 3.0 * std::numbers::pi * std::pow(p.radius[i], 3);
  const std::vector<double>& epsilon = c.coupling->void_fraction();
  for (std::size_t cell = 0; cell < epsilon.size(); ++cell) {
    solid += (1.0 - epsilon[cell]) * g.cell_volume();
    if (blocked.blocked(cell)) {
      EXPECT_EQ(epsilon[cell], 1.0);
    }
  }
  EXPECT_NEAR(solid / particle_volume, 1.0, 1e-12);
  // Some beads had weight on the obstacle's cells (moved off it), two sit inside it.
  int beside = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const CellWeights plain = cell_weights(g, PeriodicAxes{}, p.position[i]);
    for (std::size_t corner = 0; corner < 8; ++corner) beside += blocked.blocked(plain.cell[corner]) && plain.weight[corner] > 0.0;
    for (std::size_t corner = 0; corner < 8; ++corner) EXPECT_FALSE(blocked.blocked(c.coupling->weights()[i].cell[corner]));
  }
  EXPECT_GT(beside, 10);
  bool warned = false;
  for (const std::string& w : c.world.warnings) warned |= w.find("is among blocked fluid cells only") != std::string::npos;
  EXPECT_TRUE(warned);

  const std::span<const double> beta = c.coupling->fluid().drag_coefficient();
  const std::span<const Vec3> force = c.coupling->fluid().force_density();
  double beta_sum = 0.0, coefficient_sum = 0.0;  // kg/s
  Vec3 force_sum, expected_force;                // N
  double scale = 0.0;                            // N, Σ of the terms' magnitudes
  for (std::size_t cell = 0; cell < g.cell_count(); ++cell) {
    if (blocked.blocked(cell)) {
      EXPECT_EQ(beta[cell], 0.0);
      EXPECT_EQ(force[cell], Vec3{});
    }
    beta_sum += beta[cell] * g.cell_volume();
    force_sum += force[cell] * g.cell_volume();
  }
  const std::vector<FrozenParticle>& after = c.coupling->frozen();
  const std::vector<FrozenForce>& forces_after = c.coupling->frozen_forces();
  for (std::size_t i = 0; i < after.size(); ++i) {
    ASSERT_EQ(after[i].id, before[i].id);
    coefficient_sum += forces_after[i].coefficient;
    const Vec3 momentum = after[i].exchange_velocity * forces_after[i].coefficient;
    expected_force += momentum;
    scale += std::sqrt(norm2(momentum));
    if (sums_before[i].samples > 0) {
      const Vec3 correction =
          (sums_before[i].sum / sums_before[i].samples - before[i].exchange_velocity) * forces_before[i].coefficient;
      expected_force += correction;
      scale += std::sqrt(norm2(correction));
    }
    EXPECT_TRUE(std::isfinite(forces_after[i].fluid_velocity.x) && std::isfinite(after[i].pressure_gradient.z));
  }
  EXPECT_GT(coefficient_sum, 0.0);
  EXPECT_NEAR(beta_sum / coefficient_sum, 1.0, 1e-14);
  EXPECT_GT(scale, 0.0);
  for (int a = 0; a < 3; ++a) EXPECT_NEAR(force_sum[a], expected_force[a], 1e-14 * scale) << "axis " << a;
}

// The coupled channel with beads on 1 and 2 threads (every loop on the team): the same bits.
TEST(FluidBlocked, OneAndTwoThreadsAreBitIdentical) {
  std::vector<double> bits[2];
  for (int t = 0; t < 2; ++t) {
    Channel c = channel(t + 1, true);
    sim::initialize(c.world);
    sim::advance(c.world, 300);
    const ParticleStore& p = c.world.particles;
    for (std::size_t i = 0; i < p.size(); ++i)
      bits[t].insert(bits[t].end(), {p.position[i].x, p.position[i].y, p.position[i].z, p.velocity[i].x,
                                     p.velocity[i].y, p.velocity[i].z});
    for (double e : c.coupling->void_fraction()) bits[t].push_back(e);
    for (int k = 0; k < 3; ++k)
      for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 12; ++i) {
          const Vec3 u = c.coupling->fluid().cell_velocity(i, j, k);
          bits[t].insert(bits[t].end(), {u.x, u.y, u.z, c.coupling->fluid().pressure(i, j, k)});
        }
  }
  ASSERT_EQ(bits[0].size(), bits[1].size());
  for (std::size_t n = 0; n < bits[0].size(); ++n) EXPECT_EQ(bits[0][n], bits[1][n]) << "value " << n;
}

// The fluid frames carry the mask as a cell array "blocked" (0/1, x fastest).
TEST(FluidBlocked, FluidFramesCarryTheBlockedCells) {
  Channel c = channel(1, false);
  const std::string text = fluid_image_text(*c.coupling);
  const std::size_t open = text.find("<DataArray type=\"UInt8\" Name=\"blocked\" format=\"ascii\">");
  ASSERT_NE(open, std::string::npos) << text;
  std::istringstream values(text.substr(text.find('>', open) + 1));
  const cfd::FluidGrid& g = c.coupling->options().grid;
  for (int k = 0; k < 3; ++k)
    for (int j = 0; j < 4; ++j)
      for (int i = 0; i < 12; ++i) {
        int flag = -1;
        values >> flag;
        EXPECT_EQ(flag, in_obstacles(i, j, k) ? 1 : 0) << i << " " << j << " " << k;
        EXPECT_EQ(c.coupling->blocked_cells().blocked(g.cell_index(i, j, k)), in_obstacles(i, j, k));
      }
}

}  // namespace
}  // namespace quarry::cfdem
