// Unit tests of the FEM load export (src/export): interval means, the on-disk nodal history,
// MED round trip checked with the MED tools, the S6 shell mesh, and the CalculiX deck of a
// clamped plate under uniform pressure against Kirchhoff plate theory.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>
#include <fstream>

#include "export/calculix_deck.h"
#include "export/load_exporter.h"
#include "geometry/load_window.h"
#include "export/med_file.h"
#include "export/nodal_history.h"
#include "fem_export/fem_export_support.h"

namespace quarry::fem_export {
namespace {

namespace fs = std::filesystem;
using namespace quarry::fem_export_testing;

fs::path fresh_folder(const std::string& name) {
  const fs::path folder = fs::path(::testing::TempDir()) / ("quarry_fem_export_" + name);
  fs::remove_all(folder);
  fs::create_directories(folder);
  return folder;
}

// Mean of piecewise-constant forces: (Σ F_k dt_k) / Σ dt_k; pressure = −(F̄·n)/A, shear =
// (F̄ − (F̄·n)n)/A, consistent nodal forces likewise averaged (definitions of issue 4).
TEST(LoadWindow, MeansAreImpulsesOverTheInterval) {
  Surface plate = square_plate(1.0, 1);  // two triangles of 0.5 m², normal +z
  LoadWindow window(plate);
  plate.triangle_force[0] = {1.0, 0.0, -4.0};
  plate.vertex_force[2] = {0.0, 0.0, -4.0};
  plate.mark_step_loads();
  window.accumulate(plate, 0.1);
  plate.triangle_force[0] = {3.0, 0.0, -8.0};
  plate.vertex_force[2] = {0.0, 0.0, -8.0};
  plate.mark_step_loads();
  window.accumulate(plate, 0.3);
  LoadFrame frame;
  window.take_means(plate, 0.4, frame);
  EXPECT_DOUBLE_EQ(frame.duration, 0.4);
  EXPECT_NEAR(frame.force[0].x, 2.5, 1e-12);    // (0.1 + 0.9) / 0.4 N
  EXPECT_NEAR(frame.force[0].z, -7.0, 1e-12);   // (−0.4 − 2.4) / 0.4 N
  EXPECT_NEAR(frame.pressure[0], 14.0, 1e-12);  // 7 N / 0.5 m²
  EXPECT_NEAR(frame.shear_stress[0].x, 5.0, 1e-12);
  EXPECT_NEAR(frame.shear_stress[0].z, 0.0, 1e-12);
  EXPECT_EQ(frame.pressure[1], 0.0);
  EXPECT_NEAR(frame.nodal_force[2].z, -7.0, 1e-12);
  EXPECT_EQ(window.duration, 0.0);  // the take restarted the window
  window.take_means(plate, 0.5, frame);  // an empty window gives zeros, not NaN
  EXPECT_EQ(frame.force[0].z, 0.0);
}

TEST(NodalHistory, RoundTripAndResumeDropsLaterRecords) {
  const fs::path file = fresh_folder("history") / "h.bin";
  {
    NodalHistoryWriter writer(file, 2, std::nullopt);
    for (int k = 1; k <= 4; ++k) {
      const std::vector<Vec3> forces = {{1.0 * k, 0, 0}, {0, 0, -2.0 * k}};
      writer.append(0.1 * k, forces);
    }
  }
  NodalHistoryReader reader(file);
  ASSERT_EQ(reader.frame_count(), 4u);
  std::vector<Vec3> forces;
  reader.read_frame(2, forces);
  EXPECT_EQ(forces[0].x, 3.0);
  EXPECT_EQ(forces[1].z, -6.0);
  reader.read_nodes(1, 1, forces);
  ASSERT_EQ(forces.size(), 4u);
  EXPECT_EQ(forces[3].z, -8.0);
  {
    NodalHistoryWriter resumed(file, 2, 0.25);  // a restart at t = 0.25 s keeps 2 records
    EXPECT_EQ(resumed.frame_count(), 2u);
    const std::vector<Vec3> next = {{9, 9, 9}, {9, 9, 9}};
    resumed.append(0.3, next);
  }
  NodalHistoryReader after(file);
  ASSERT_EQ(after.frame_count(), 3u);
  EXPECT_DOUBLE_EQ(after.times()[2], 0.3);
  EXPECT_THROW(NodalHistoryWriter(file, 3, 0.25), std::runtime_error);  // another mesh
}

LoadFrame synthetic_frame(const Surface& surface, double time, double scale) {
  LoadFrame frame;
  frame.time = time;
  for (std::size_t e = 0; e < surface.triangle_count(); ++e) {
    frame.pressure.push_back(scale * (1.0 + e));
    frame.shear_stress.push_back({scale * e, -0.5 * e, 1e-3 * e});
    frame.force.push_back({0.25 * e, scale, -3.0 * e});
  }
  for (std::size_t n = 0; n < surface.vertex_count(); ++n)
    frame.nodal_force.push_back({1.0 / (n + 1), scale * n, -2.0 * n});
  return frame;
}

// The MED file holds exactly what was written (mesh, four fields, steps, times, units) and
// the reference MED tool reads it.
TEST(MedFile, ReadsBackIdenticallyAndMdumpAcceptsIt) {
  const fs::path folder = fresh_folder("med");
  const Surface plate = square_plate(0.4, 3);
  const std::string path = (folder / "plate.med").string();
  std::vector<LoadFrame> written;
  // Two overlapping node groups (a corner node is in both): three MED families besides 0.
  const std::vector<MedNodeGroup> groups = {{"LEFT_EDGE", nodes_in_box(plate.vertices, {-1, -1, -1}, {1e-9, 1, 1})},
                                            {"BOTTOM_EDGE", nodes_in_box(plate.vertices, {-1, -1, -1}, {1, 1e-9, 1})}};
  ASSERT_EQ(groups[0].nodes.size(), 4u);  // a 3 × 3 plate has 4 nodes on each edge
  ASSERT_EQ(groups[1].nodes.size(), 4u);
  {
    MedLoadWriter writer(path, "plate", plate.vertices, plate.triangles, false, groups);
    for (int k = 1; k <= 3; ++k) {
      written.push_back(synthetic_frame(plate, 0.05 * k, 1.5 * k));
      writer.write(k, written.back());
    }
  }
  const MedLoadFile file = read_med_loads(path);
  EXPECT_EQ(file.mesh_name, "plate");
  EXPECT_EQ(file.space_dimension, 3);
  EXPECT_EQ(file.mesh_dimension, 2);
  EXPECT_EQ(file.nodes, plate.vertices);
  EXPECT_EQ(file.triangles, plate.triangles);
  ASSERT_EQ(file.node_groups.size(), 2u);  // sorted by name
  EXPECT_EQ(file.node_groups[0].name, "BOTTOM_EDGE");
  EXPECT_EQ(file.node_groups[0].nodes, groups[1].nodes);
  EXPECT_EQ(file.node_groups[1].name, "LEFT_EDGE");
  EXPECT_EQ(file.node_groups[1].nodes, groups[0].nodes);
  ASSERT_EQ(file.frames.size(), 3u);
  for (std::size_t k = 0; k < 3; ++k) {
    EXPECT_EQ(file.step_numbers[k], static_cast<int>(k + 1));
    EXPECT_EQ(file.frames[k].time, written[k].time);
    EXPECT_EQ(file.frames[k].pressure, written[k].pressure);
    EXPECT_EQ(file.frames[k].shear_stress, written[k].shear_stress);
    EXPECT_EQ(file.frames[k].force, written[k].force);
    EXPECT_EQ(file.frames[k].nodal_force, written[k].nodal_force);
  }
  for (std::size_t f = 0; f < file.field_names.size(); ++f) {
    EXPECT_EQ(file.time_units[f], "s");
    EXPECT_EQ(file.field_units[f], file.field_names[f].find("force") != std::string::npos ? "N" : "Pa")
        << file.field_names[f];
  }
  // A restart overwrites step 3 and appends step 4 in the same file.
  {
    MedLoadWriter resumed(path, "plate", plate.vertices, plate.triangles, true);
    written[2] = synthetic_frame(plate, 0.15, 7.0);
    resumed.write(3, written[2]);
    written.push_back(synthetic_frame(plate, 0.2, 8.0));
    resumed.write(4, written[3]);
  }
  const MedLoadFile resumed = read_med_loads(path);
  ASSERT_EQ(resumed.frames.size(), 4u);
  EXPECT_EQ(resumed.frames[2].pressure, written[2].pressure);
  EXPECT_EQ(resumed.frames[3].nodal_force, written[3].nodal_force);

  if (!program_available("mdump")) GTEST_SKIP() << "mdump (Debian libmed-tools) is not installed";
  const fs::path dump = folder / "mdump.txt";
  ASSERT_EQ(std::system(("mdump '" + path + "' NODALE FULL_INTERLACE 1 > '" + dump.string() +
                         "' 2>&1").c_str()),
            0)
      << read_text(dump);
  const std::string text = read_text(dump);
  for (const char* expected : {"pressure", "shear_stress", "nodal_force", "TRIA3", "Pa", "LEFT_EDGE",
                               "BOTTOM_EDGE", "PRES", "FX", "FZ"})
    EXPECT_NE(text.find(expected), std::string::npos) << expected << " missing in mdump output";
}

TEST(ShellMesh, SharedEdgesGetOneMidsideNode) {
  const Surface plate = square_plate(1.0, 4);
  const ShellMesh mesh = quadratic_shell_mesh(plate.vertices, plate.triangles);
  // An n×n grid of split squares has 3n² + 2n edges: one mid-side node each.
  EXPECT_EQ(mesh.corner_count, 25u);
  EXPECT_EQ(mesh.nodes.size(), 25u + 3 * 16 + 2 * 4);
  ASSERT_EQ(mesh.elements.size(), plate.triangle_count());
  for (std::size_t e = 0; e < mesh.elements.size(); ++e)
    for (int k = 0; k < 3; ++k) {
      const Vec3 middle = 0.5 * (plate.vertices[plate.triangles[e][k]] +
                                 plate.vertices[plate.triangles[e][(k + 1) % 3]]);
      EXPECT_EQ(mesh.nodes[mesh.elements[e][3 + k]], middle);
      EXPECT_EQ(mesh.elements[e][k], plate.triangles[e][k]);  // corner numbering kept
    }
}

// Steel plate of the plate tests: side 0.4 m, thickness 8 mm (a/h = 50, where transverse shear
// adds < 1 % to the Kirchhoff deflection), clamped on all four edges.
CalculixSpec clamped_steel_plate(double side, double thickness) {
  CalculixSpec spec;
  spec.thickness = thickness;      // m
  spec.youngs_modulus = 2.1e11;    // Pa
  spec.poisson_ratio = 0.3;
  spec.density = 7850.0;           // kg/m³
  const double tolerance = 1e-6;   // m
  const auto edge = [&](const char* name, Vec3 lower, Vec3 upper) {
    SupportSpec support;
    support.name = std::string(name);
    support.min = lower;
    support.max = upper;
    spec.supports.push_back(support);
  };
  // Four edge boxes without overlap (south and north stop short of the corners), so that the
  // reactions of the four sets add up to the total.
  const double inset = 1e-3 * side;  // m, less than any element
  edge("west", {-tolerance, -tolerance, -tolerance}, {tolerance, side + tolerance, tolerance});
  edge("east", {side - tolerance, -tolerance, -tolerance}, {side + tolerance, side + tolerance, tolerance});
  edge("south", {inset, -tolerance, -tolerance}, {side - inset, tolerance, tolerance});
  edge("north", {inset, side - tolerance, -tolerance}, {side - inset, side + tolerance, tolerance});
  return spec;
}

// Kirchhoff plate, all edges clamped, uniform load q: centre deflection
// w = 0.00126 q a⁴ / D, D = E h³ / (12 (1 − ν²)) (Timoshenko & Woinowsky-Krieger, "Theory of
// Plates and Shells", 2nd ed., 1959, §44 and table 35).
double clamped_plate_centre_deflection(double pressure, double side, double thickness) {
  const double flexural_rigidity = 2.1e11 * std::pow(thickness, 3) / (12.0 * (1.0 - 0.3 * 0.3));
  return 0.00126 * pressure * std::pow(side, 4) / flexural_rigidity;
}

// The S6 deck of a 20×20 plate under the consistent nodal forces of a uniform pressure (each
// triangle gives q·A/3 to each corner, what the DEM's barycentric distribution gives for a
// uniform layer): CalculiX's centre deflection is within 5 % of Kirchhoff and the supports carry
// q a² within 1 %.
TEST(CalculixDeck, ClampedPlateMatchesKirchhoffAndCarriesTheLoad) {
  if (!program_available("ccx")) GTEST_SKIP() << "ccx (Debian calculix-ccx) is not installed";
  const fs::path folder = fresh_folder("calculix_static");
  const double side = 0.4, thickness = 0.008, pressure = 1000.0;  // m, m, Pa
  const Surface plate = square_plate(side, 20);
  std::vector<Vec3> nodal(plate.vertex_count());
  for (std::size_t t = 0; t < plate.triangle_count(); ++t)
    for (int k = 0; k < 3; ++k)
      nodal[plate.triangles[t][k]].z -= pressure * plate.triangle_areas[t] / 3.0;
  {
    NodalHistoryWriter writer(folder / "plate.bin", plate.vertex_count(), std::nullopt);
    std::vector<Vec3> half = nodal;
    for (auto& f : half) f = f * 0.5;
    writer.append(0.1, half);   // an earlier, lighter record the static step must not use
    writer.append(0.2, nodal);
  }
  NodalHistoryReader history(folder / "plate.bin");
  CalculixSpec spec = clamped_steel_plate(side, thickness);
  spec.static_time = Located<double>(0.15);  // inside the interval (0.1, 0.2]
  const ShellMesh mesh = quadratic_shell_mesh(plate.vertices, plate.triangles);
  const CalculixDeckSummary summary =
      write_calculix_deck(folder / "plate.inp", "plate", mesh, spec, history);
  EXPECT_EQ(summary.static_frame, 1u);
  EXPECT_NEAR(-summary.static_total_load.z, pressure * side * side, 1e-9);
  // Centre node (10, 10) of the 21×21 grid.
  add_before_end_step(folder / "plate.inp", "*NSET, NSET=CENTRE\n221,\n*NODE PRINT, NSET=CENTRE\nU\n");
  ASSERT_TRUE(run_ccx(folder, "plate")) << read_text(folder / "plate.log");
  const std::vector<double> centre = dat_row_after(folder / "plate.dat", "displacements");
  ASSERT_EQ(centre.size(), 4u);
  EXPECT_EQ(centre[0], 221.0);
  const double expected = clamped_plate_centre_deflection(pressure, side, thickness);
  EXPECT_NEAR(-centre[3] / expected, 1.0, 0.05) << "ccx " << centre[3] << " m, Kirchhoff " << expected;
  // Reactions: ccx's RF holds what the plate carries to the supports; the loads sitting on
  // supported nodes go straight into the supports (summary.static_load_on_supports).
  double reaction = 0.0;  // N, upwards
  for (const char* set : {"WEST", "EAST", "SOUTH", "NORTH"}) {
    const std::vector<double> total = dat_row_after(folder / "plate.dat", "set " + std::string(set));
    ASSERT_EQ(total.size(), 3u) << set;
    reaction += total[2];
  }
  const double carried = reaction - summary.static_load_on_supports.z;
  EXPECT_NEAR(carried / (pressure * side * side), 1.0, 0.01)
      << "RF " << reaction << " N + direct " << -summary.static_load_on_supports.z << " N";
}

// The dynamic deck: one *AMPLITUDE per loaded node DOF with every record, and CalculiX runs it.
TEST(CalculixDeck, DynamicHistoryRuns) {
  if (!program_available("ccx")) GTEST_SKIP() << "ccx (Debian calculix-ccx) is not installed";
  const fs::path folder = fresh_folder("calculix_dynamic");
  const Surface plate = square_plate(0.4, 4);
  {
    NodalHistoryWriter writer(folder / "plate.bin", plate.vertex_count(), std::nullopt);
    for (int k = 1; k <= 5; ++k) {
      std::vector<Vec3> nodal(plate.vertex_count());
      nodal[12].z = -10.0 * k;  // centre node, N
      writer.append(1e-3 * k, nodal);
    }
  }
  NodalHistoryReader history(folder / "plate.bin");
  CalculixSpec spec = clamped_steel_plate(0.4, 0.008);
  spec.analysis = CalculixAnalysis::dynamic;
  write_calculix_deck(folder / "plate.inp", "plate", quadratic_shell_mesh(plate.vertices, plate.triangles),
                      spec, history);
  const std::string deck = read_text(folder / "plate.inp");
  EXPECT_NE(deck.find("*AMPLITUDE, NAME=F13_3\n0.001, -10\n0.002, -20\n"), std::string::npos);
  EXPECT_EQ(deck.find("*AMPLITUDE, NAME=F1_"), std::string::npos);  // unloaded DOFs get none
  EXPECT_NE(deck.find("*DYNAMIC"), std::string::npos);
  ASSERT_TRUE(run_ccx(folder, "plate")) << read_text(folder / "plate.log");
  EXPECT_TRUE(fs::exists(folder / "plate.frd"));
}

// The centre node's vertical displacement at every output time of a CalculiX .dat (the blocks
// "displacements (vx,vy,vz) for set CENTRE and time T" followed by "node ux uy uz"): (T, uz).
std::vector<std::pair<double, double>> centre_history(const fs::path& dat) {
  std::ifstream in(dat);
  std::vector<std::pair<double, double>> history;
  std::string line;
  double time = 0.0;
  bool expect_row = false;
  while (std::getline(in, line)) {
    if (line.find("displacements") != std::string::npos) {
      std::istringstream words(line.substr(line.rfind("time") + 4));
      expect_row = static_cast<bool>(words >> time);
      continue;
    }
    std::istringstream row(line);
    double node, ux, uy, uz;
    if (expect_row && (row >> node >> ux >> uy >> uz)) {
      history.emplace_back(time, uz);
      expect_row = false;
    }
  }
  return history;
}

// The dynamic deck's physics: a uniform load ramped up slowly and held. An undamped oscillator
// under a ramp of duration t_r follows u(t) = u_st(t) − u_st0 sin(ω t)/(ω t_r) (Chopra, Dynamics
// of Structures, 4th ed., 2012, §4.4): within u_st0/(ω t_r) of the static response at every
// instant, and the plate's modes each do so with its own ω ≥ ω₁. The clamped square plate's
// first mode, ω₁ = 35.99/a² √(D/(ρh)) (Leissa 1969, Vibration of Plates, NASA SP-160, table
// 4.20), is 2,816 rad/s for a 0.4 m, 8 mm steel plate: over t_r = 50 ms the bound is 0.71 % of the
// full static deflection. CalculiX's direct integration of the exported history (increments of
// one record, 0.5 ms: ω₁Δt = 1.4) must track λ(t) times its own static deflection of the same
// (coarse) mesh within 1.5 times that bound (room for the integrator's period elongation at
// that step), and end there too; a history late by one record would be 1 % further off.
TEST(CalculixDeck, DynamicHistoryOfASlowRampTracksTheStaticDeflection) {
  if (!program_available("ccx")) GTEST_SKIP() << "ccx (Debian calculix-ccx) is not installed";
  const fs::path folder = fresh_folder("calculix_ramp");
  const double side = 0.4, thickness = 0.008, pressure = 1000.0;  // m, m, Pa
  constexpr int kDivisions = 6, kRamp = 100, kHold = 60;            // records of 0.5 ms
  constexpr double kInterval = 5e-4;                                // s
  const Surface plate = square_plate(side, kDivisions);
  std::vector<Vec3> nodal(plate.vertex_count());
  for (std::size_t t = 0; t < plate.triangle_count(); ++t)
    for (int k = 0; k < 3; ++k)
      nodal[plate.triangles[t][k]].z -= pressure * plate.triangle_areas[t] / 3.0;
  const auto load_factor = [&](double time) { return std::min(1.0, time / (kRamp * kInterval)); };
  {
    NodalHistoryWriter writer(folder / "plate.bin", plate.vertex_count(), std::nullopt);
    for (int k = 1; k <= kRamp + kHold; ++k) {
      std::vector<Vec3> record = nodal;
      for (Vec3& f : record) f = f * load_factor(k * kInterval);
      writer.append(k * kInterval, record);
    }
  }
  NodalHistoryReader history(folder / "plate.bin");
  const ShellMesh mesh = quadratic_shell_mesh(plate.vertices, plate.triangles);
  const int centre = kDivisions / 2 * (kDivisions + 1) + kDivisions / 2 + 1;  // node number
  const std::string centre_output =
      fmt::format("*NSET, NSET=CENTRE\n{},\n*NODE PRINT, NSET=CENTRE\nU\n", centre);
  CalculixSpec spec = clamped_steel_plate(side, thickness);
  write_calculix_deck(folder / "still.inp", "plate", mesh, spec, history);  // the last record
  spec.analysis = CalculixAnalysis::dynamic;
  write_calculix_deck(folder / "ramp.inp", "plate", mesh, spec, history);
  for (const char* job : {"still", "ramp"}) {
    add_before_end_step(folder / (std::string(job) + ".inp"), centre_output);
    ASSERT_TRUE(run_ccx(folder, job)) << read_text(folder / (std::string(job) + ".log"));
  }
  const std::vector<double> still = dat_row_after(folder / "still.dat", "displacements");
  ASSERT_EQ(still.size(), 4u);
  const double static_deflection = still[3];  // m, negative
  const std::vector<std::pair<double, double>> ramp = centre_history(folder / "ramp.dat");
  ASSERT_GE(ramp.size(), static_cast<std::size_t>(kRamp + kHold));
  double worst = 0.0;  // largest |u − λ u_static| / |u_static|
  for (const auto& [time, uz] : ramp)
    worst = std::max(worst, std::abs(uz - load_factor(time) * static_deflection) / std::abs(static_deflection));
  std::printf("[ measured ] static centre deflection %.6g m; the ramp's history within %.4f of it (bound "
              "0.0071); at the end %.6g m\n",
              static_deflection, worst, ramp.back().second);
  const double first_mode = 35.99 / (side * side) *
                            std::sqrt(2.1e11 * std::pow(thickness, 3) / (12.0 * (1.0 - 0.3 * 0.3)) /
                                      (7850.0 * thickness));  // rad/s
  const double bound = 1.0 / (first_mode * kRamp * kInterval);
  EXPECT_NEAR(bound, 0.0071, 0.0001);
  EXPECT_LT(worst, 1.5 * bound);
  EXPECT_NEAR(ramp.back().first, (kRamp + kHold) * kInterval, 1e-9);
  EXPECT_NEAR(ramp.back().second / static_deflection, 1.0, 1.5 * bound);
}

// Memory stays flat however many intervals are exported: 2000 records cost no more resident
// memory than 500 (the CSV and nodal history are streamed to disk, the CalculiX amplitudes are
// written from disk in bounded blocks, and the MED writer shuts HDF5 down after each record —
// without that, HDF5's caches grew by ~3.5 kB per stored step, measured: 7.1 MB over 1500).
TEST(LoadExporter, MemoryIsIndependentOfTheNumberOfIntervals) {
  const fs::path folder = fresh_folder("memory");
  std::vector<Surface> surfaces = {square_plate(0.4, 4)};
  surfaces[0].export_loads = true;
  ExportSpec spec;
  spec.enabled = true;
  spec.interval = 1e-4;
  spec.formats = {Located<ExportFormat>(ExportFormat::csv),
                  Located<ExportFormat>(ExportFormat::calculix), Located<ExportFormat>(ExportFormat::med)};
  spec.calculix = clamped_steel_plate(0.4, 0.008);
  spec.calculix->analysis = CalculixAnalysis::dynamic;
  const std::vector<const Surface*> meshes = {&surfaces[0]};
  LoadExporter exporter(spec, meshes, folder, 1e-4, 1e-4 * 2000, std::nullopt);
  ASSERT_TRUE(exporter.active());
  long resident_early = 0;
  const int steps = 2000;
  for (int n = 1; n <= steps; ++n) {
    for (std::size_t v = 0; v < surfaces[0].vertex_count(); ++v)
      surfaces[0].vertex_force[v] = {0.0, 0.0, -std::sin(0.01 * n + v)};
    surfaces[0].triangle_force[3] = {0.0, 0.0, -1.0};
    surfaces[0].mark_step_loads();
    exporter.after_step(meshes, 1e-4 * n, static_cast<std::uint64_t>(n), 1e-4);
    if (n == 500) resident_early = resident_bytes();
  }
  const long resident_late = resident_bytes();
  exporter.finish(meshes, 1e-4 * steps, false);
#ifndef __SANITIZE_ADDRESS__  // ASan quarantines freed memory, so RSS grows by design there
  EXPECT_LT(resident_late - resident_early, 1l << 20)
      << "resident memory grew by " << (resident_late - resident_early) << " bytes";
#else
  (void)resident_early;
  (void)resident_late;
#endif
  NodalHistoryReader history(folder / "fem_export" / "plate_nodal_forces.bin");
  EXPECT_EQ(history.frame_count(), static_cast<std::size_t>(steps));
  std::vector<Vec3> last;
  history.read_frame(steps - 1, last);
  EXPECT_NEAR(last[0].z, -std::sin(0.01 * steps), 1e-12);
  const std::string csv = read_text(folder / "fem_export" / "plate_loads.csv");
  EXPECT_EQ(static_cast<std::size_t>(std::count(csv.begin(), csv.end(), '\n')),
            1 + static_cast<std::size_t>(steps) * surfaces[0].triangle_count());
  EXPECT_TRUE(fs::exists(folder / "fem_export" / "plate.inp"));
}

}  // namespace
}  // namespace quarry::fem_export
