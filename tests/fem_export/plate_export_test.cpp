// Verification of the FEM load export end to end (issue 4): a layer of particles settles on a
// square steel plate; the exported nodal forces carry its weight, CalculiX run on the exported
// deck gives the reactions and the Kirchhoff centre deflection of the clamped plate, the MED file
// matches the streamed history, and 1 and 2 threads export identical files.
#include <gtest/gtest.h>
#include <omp.h>

#include <cmath>
#include <filesystem>
#include <sstream>

#include "core/particle_store.h"
#include "export/med_file.h"
#include "export/nodal_history.h"
#include "fem_export/fem_export_support.h"
#include "io/deck.h"
#include "sim/run.h"

namespace quarry::fem_export {
namespace {

namespace fs = std::filesystem;
using namespace quarry::fem_export_testing;

constexpr double kSide = 0.4;        // m, plate side a
constexpr double kThickness = 0.008; // m, plate thickness h (a/h = 50: Kirchhoff regime)
constexpr int kDivisions = 20;       // plate mesh: 20×20 squares, 800 triangles
constexpr double kGravity = 9.81;    // m/s²

// Two layers of spheres of radius 9.5 mm settle on the plate: 20×20 on a square lattice of
// 20 mm pitch (one above the centre of each mesh square) and 19×19 in the hollows above them, so
// that the layer is uniform up to the edges and the weight reaches the plate through real
// particle–particle contacts. Frictionless side walls carry no weight. Loads exported every 0.1 s.
constexpr double kRadius = 0.0095;  // m
constexpr double kPitch = 0.02;     // m

std::string plate_deck(const fs::path& stl, const fs::path& output) {
  return settled_layer_deck(stl, output, kSide, R"(export:
  interval: 0.1
  calculix:
    thickness: 0.008
    youngs_modulus: 2.1e11
    poisson_ratio: 0.3
    supports:
      - {name: west, box: {min: [-0.001, -0.001, -0.001], max: [0.001, 0.401, 0.001]}}
      - {name: east, box: {min: [0.399, -0.001, -0.001], max: [0.401, 0.401, 0.001]}}
      - {name: south, box: {min: [0.0004, -0.001, -0.001], max: [0.3996, 0.001, 0.001]}}
      - {name: north, box: {min: [0.0004, 0.399, -0.001], max: [0.3996, 0.401, 0.001]}}
)");
}

struct PlateRun {
  fs::path export_folder;
  double weight = 0.0;  // N, Σ m g of the particles at the end
};

PlateRun run_plate(const std::string& name, int threads) {
  const fs::path folder = fs::path(::testing::TempDir()) / ("quarry_plate_export_" + name);
  fs::remove_all(folder);
  fs::create_directories(folder);
  write_ascii_stl(square_plate(kSide, kDivisions), folder / "plate.stl");
  const SimulationSpec spec =
      parse_deck_string(plate_deck(folder / "plate.stl", folder / "out"), "plate.yaml");
  World world = build_world(spec);
  world.threading = Threading{threads, 0};  // both threads work even in this small scene
  add_two_layers(world, kDivisions, kPitch, kRadius, 2500.0);
  sim::RunOptions options;
  options.quiet = true;
  std::ostringstream log;
  options.log = &log;
  sim::run(world, options);
  PlateRun result;
  result.export_folder = folder / "out" / "fem_export";
  for (std::size_t i = 0; i < world.particles.size(); ++i)
    result.weight += kGravity / world.particles.inv_mass[i];
  EXPECT_EQ(world.particles.size(), 761u) << log.str();
  return result;
}

// Kirchhoff plate, all edges clamped, uniform load q: centre deflection
// w = 0.00126 q a⁴ / D, D = E h³ / (12 (1 − ν²)) (Timoshenko & Woinowsky-Krieger, "Theory of
// Plates and Shells", 2nd ed., 1959, table 35).
double kirchhoff_centre_deflection(double pressure) {
  const double flexural_rigidity = 2.1e11 * std::pow(kThickness, 3) / (12.0 * (1.0 - 0.3 * 0.3));
  return 0.00126 * pressure * std::pow(kSide, 4) / flexural_rigidity;
}

bool on_edge(const Vec3& p) {
  const double tolerance = 1e-6;  // m
  return p.x < tolerance || p.y < tolerance || p.x > kSide - tolerance || p.y > kSide - tolerance;
}

TEST(PlateExport, SettledLayerLoadsTheClampedPlateAsKirchhoffPredicts) {
  const PlateRun run = run_plate("one_thread", 1);
  const MedLoadFile med = read_med_loads((run.export_folder / "plate.med").string());
  ASSERT_EQ(med.frames.size(), 5u);  // 0.5 s / 0.1 s
  EXPECT_NEAR(med.frames.back().time, 0.5, 1e-3);  // within a time step

  // Static equilibrium of the settled layer (Newton): Σ nodal forces = weight, to 0.5 %.
  const LoadFrame& settled = med.frames.back();
  Vec3 total, on_supports;  // N
  for (std::size_t n = 0; n < settled.nodal_force.size(); ++n) {
    total += settled.nodal_force[n];
    if (on_edge(med.nodes[n])) on_supports += settled.nodal_force[n];
  }
  EXPECT_NEAR(-total.z / run.weight, 1.0, 0.005) << "nodal sum " << total.z << " N, weight " << run.weight;
  // The element forces and the pressure field carry the same total.
  double pressure_force = 0.0;  // N
  const Surface plate = square_plate(kSide, kDivisions);
  for (std::size_t e = 0; e < settled.pressure.size(); ++e) pressure_force += settled.pressure[e] * plate.triangle_areas[e];
  EXPECT_NEAR(pressure_force / run.weight, 1.0, 0.005);

  // The MED file holds exactly the streamed history.
  NodalHistoryReader history(run.export_folder / "plate_nodal_forces.bin");
  ASSERT_EQ(history.frame_count(), med.frames.size());
  std::vector<Vec3> record;
  for (std::size_t f = 0; f < med.frames.size(); ++f) {
    history.read_frame(f, record);
    EXPECT_EQ(record, med.frames[f].nodal_force) << "record " << f;
  }
  EXPECT_TRUE(fs::exists(run.export_folder / "plate_loads.csv"));
  EXPECT_TRUE(fs::exists(run.export_folder / "plate_loads.pvd"));

  if (!program_available("ccx")) GTEST_SKIP() << "ccx (Debian calculix-ccx) is not installed";
  std::size_t centre = 0;
  for (std::size_t n = 0; n < med.nodes.size(); ++n)
    if (norm(med.nodes[n] - Vec3{0.5 * kSide, 0.5 * kSide, 0.0}) < 1e-9) centre = n;
  const fs::path inp = run.export_folder / "plate.inp";
  add_before_end_step(inp, "*NSET, NSET=CENTRE\n" + std::to_string(centre + 1) +
                               ",\n*NODE PRINT, NSET=CENTRE\nU\n");
  ASSERT_TRUE(run_ccx(run.export_folder, "plate")) << read_text(run.export_folder / "plate.log");
  const fs::path dat = run.export_folder / "plate.dat";
  // Total reaction = RF of the supports + the loads applied on supported nodes (ccx hands those
  // to the supports directly) = weight, to 1 %.
  double reaction = 0.0;  // N, upwards
  for (const char* set : {"WEST", "EAST", "SOUTH", "NORTH"}) {
    const std::vector<double> row = dat_row_after(dat, "set " + std::string(set));
    ASSERT_EQ(row.size(), 3u) << set;
    reaction += row[2];
  }
  EXPECT_NEAR((reaction - on_supports.z) / run.weight, 1.0, 0.01)
      << "RF " << reaction << " N, on supports " << -on_supports.z << " N";
  const std::vector<double> displacement = dat_row_after(dat, "displacements");
  ASSERT_EQ(displacement.size(), 4u);
  const double expected = kirchhoff_centre_deflection(run.weight / (kSide * kSide));
  EXPECT_NEAR(-displacement[3] / expected, 1.0, 0.05)
      << "ccx " << displacement[3] << " m, Kirchhoff " << expected << " m";
}

// Element and node numbering, and every exported value, are the same for 1 and 2 threads.
TEST(PlateExport, OneAndTwoThreadsExportIdenticalFiles) {
  const MedLoadFile one = read_med_loads((run_plate("threads_1", 1).export_folder / "plate.med").string());
  const MedLoadFile two = read_med_loads((run_plate("threads_2", 2).export_folder / "plate.med").string());
  EXPECT_EQ(one.nodes, two.nodes);
  EXPECT_EQ(one.triangles, two.triangles);
  ASSERT_EQ(one.frames.size(), two.frames.size());
  for (std::size_t f = 0; f < one.frames.size(); ++f) {
    EXPECT_EQ(one.frames[f].pressure, two.frames[f].pressure) << "record " << f;
    EXPECT_EQ(one.frames[f].shear_stress, two.frames[f].shear_stress) << "record " << f;
    EXPECT_EQ(one.frames[f].nodal_force, two.frames[f].nodal_force) << "record " << f;
  }
}

}  // namespace
}  // namespace quarry::fem_export
