// Verification of the smoothed surface pressure (issue #20): two layers of spheres settle on a
// plate meshed finer than the particles (4.2 mm triangles under 19 mm spheres). The raw
// per-triangle pressure is speckle — only triangles under a contact carry load — while the
// coarse-grained pressure (Gaussian of width = the particle radius) is the layer's weight per
// area, ρ_bulk g h, to within the lattice ripple that the kernel leaves.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <sstream>

#include "core/particle_store.h"
#include "export/med_file.h"
#include "fem_export/fem_export_support.h"
#include "geometry/surface_pressure.h"
#include "io/deck.h"
#include "sim/run.h"

namespace quarry::fem_export {
namespace {

namespace fs = std::filesystem;
using namespace quarry::fem_export_testing;

constexpr int kCells = 10;                 // particles per row of the lower layer
constexpr double kPitch = 0.02;            // m, lattice pitch p
constexpr double kSide = kCells * kPitch;  // m, plate side
constexpr int kDivisions = 48;             // 4.17 mm squares: not aligned with the lattice
constexpr double kRadius = 0.0095;         // m
constexpr double kDensity = 2500.0;        // kg/m³
constexpr double kGravity = 9.81;          // m/s²

std::string deck(const fs::path& stl, const fs::path& output) {
  return settled_layer_deck(stl, output, kSide, R"(export:
  interval: 0.1
  formats: [med, vtu]
)");
}

struct Stats {
  double mean = 0.0, std = 0.0, min = 1e300, max = -1e300;
  std::size_t count = 0, nonzero = 0;
  void add(double value) {
    ++count;
    nonzero += value != 0.0;
    mean += value;
    std += value * value;
    min = std::min(min, value);
    max = std::max(max, value);
  }
  void finish() {
    mean /= static_cast<double>(count);
    std = std::sqrt(std::max(0.0, std / static_cast<double>(count) - mean * mean));
  }
};

bool interior(const Vec3& x, double margin) {
  return x.x > margin && x.y > margin && x.x < kSide - margin && x.y < kSide - margin;
}

TEST(PlatePressure, SmoothedPressureOfASettledLayerIsItsWeightPerArea) {
  const fs::path folder = fs::path(::testing::TempDir()) / "quarry_plate_pressure";
  fs::remove_all(folder);
  fs::create_directories(folder);
  Surface plate = square_plate(kSide, kDivisions);
  write_ascii_stl(plate, folder / "plate.stl");
  World world =
      build_world(parse_deck_string(deck(folder / "plate.stl", folder / "out"), "plate.yaml"));
  // A lower layer on the square lattice and an upper one in its hollows (as in
  // plate_export_test.cpp).
  add_two_layers(world, kCells, kPitch, kRadius, kDensity);
  sim::RunOptions options;
  options.quiet = true;
  std::ostringstream log;
  options.log = &log;
  sim::run(world, options);
  ASSERT_EQ(world.particles.size(), 181u) << log.str();

  // Closed form. Away from the edges each p² column holds two spheres (one per layer), the layer
  // is h = 2R + upper_rise thick, so ρ_bulk = 2 m / (p² h) (measured from the packing) and the
  // plate carries ρ_bulk g h = 2 m g / p² (frictionless side walls take none of the weight).
  const double mass = kDensity * 4.0 / 3.0 * std::numbers::pi * std::pow(kRadius, 3);  // kg
  const double upper_rise = std::sqrt(4.0 * kRadius * kRadius - 0.5 * kPitch * kPitch);  // m
  const double height = 2.0 * kRadius + upper_rise;                                    // m
  const double bulk_density = 2.0 * mass / (kPitch * kPitch * height);                 // kg/m³
  const double expected = bulk_density * kGravity * height;                            // Pa

  const fs::path exported = folder / "out" / "fem_export";
  const MedLoadFile med = read_med_loads((exported / "plate.med").string());
  ASSERT_EQ(med.frames.size(), 5u);
  const LoadFrame& settled = med.frames.back();  // mean over 0.4–0.5 s
  const double width = world.max_radius;         // m, what the output stage uses
  ASSERT_EQ(width, kRadius);
  const std::vector<double> nodal = nodal_pressure(plate, settled.nodal_force);
  const std::vector<double> smoothed = coarse_grained_pressure(plate, nodal, width);

  // Interior: the edge spheres of the lower layer carry 1.5 m g (their outer upper neighbours
  // are missing), so leave out 1.5 p plus the kernel's 3w reach.
  const double margin = 1.5 * kPitch + 3.0 * width;  // m
  Stats raw, smooth, node;
  for (std::size_t t = 0; t < plate.triangle_count(); ++t) {
    const auto& tri = plate.triangles[t];
    if (interior((plate.vertices[tri[0]] + plate.vertices[tri[1]] + plate.vertices[tri[2]]) / 3.0,
                 margin))
      raw.add(settled.pressure[t]);
  }
  for (std::size_t v = 0; v < plate.vertex_count(); ++v)
    if (interior(plate.vertices[v], margin)) {
      smooth.add(smoothed[v]);
      node.add(nodal[v]);
    }
  raw.finish();
  smooth.finish();
  node.finish();
  // Spread. The kernel leaves the lattice's first harmonics, amplitude a = exp(−2π² w² / p²)
  // each (Fourier transform of the Gaussian): the field is 1 + 2a cos(2πx/p) + 2a cos(2πy/p),
  // standard deviation 2a (2.3 % here; 2.7 % with the 3w cut-off, summed numerically) and
  // extremes ±4a. On top comes the sphere-to-sphere scatter of the loads: an upper sphere on four
  // lower ones is statically indeterminate, so how the lower spheres share the weight depends on
  // the settling history (a relative scatter s of 3-10 % per sphere, measured below from the
  // plate's own nodal forces); the kernel averages about 4π w² / p² = 2.8 contacts, so it passes
  // s/√2.8 on. A third part is where the contacts sit: the lower spheres slide off their lattice
  // sites as the layer settles, and the kernel (w = R = p/2.1) does not average that out. With the
  // dashpots at the force's time (commit "the dashpots use the velocity at the force's time") this
  // settling measured s = 4.6 % yet a smoothed spread of 5.3 % and a low of −16 % (before: 3.0 %
  // and −8 %). Bounds: the mean within 2 % (what the field is for: the mean load), the spread
  // below 8 % and every vertex within 20 % of ρ_bulk g h.
  const double ripple =
      std::exp(-2.0 * std::numbers::pi * std::numbers::pi * width * width / (kPitch * kPitch));
  // The load of each interior lower sphere: the plate's nodal forces gathered to the nearest
  // lattice site (a contact's three vertices lie within a triangle, 4.2 mm, of its site).
  std::vector<double> site_load(static_cast<std::size_t>(kCells * kCells), 0.0);
  for (std::size_t v = 0; v < plate.vertex_count(); ++v) {
    const int i = std::clamp(static_cast<int>(plate.vertices[v].x / kPitch), 0, kCells - 1);
    const int j = std::clamp(static_cast<int>(plate.vertices[v].y / kPitch), 0, kCells - 1);
    site_load[static_cast<std::size_t>(i * kCells + j)] -= settled.nodal_force[v].z;
  }
  Stats sites;
  for (int i = 0; i < kCells; ++i)
    for (int j = 0; j < kCells; ++j)
      if (interior({kPitch * (i + 0.5), kPitch * (j + 0.5), 0.0}, 1.5 * kPitch))
        sites.add(site_load[static_cast<std::size_t>(i * kCells + j)]);
  sites.finish();
  const double scatter = sites.std / sites.mean;  // s
  const double passed = scatter / std::sqrt(4.0 * std::numbers::pi * width * width / (kPitch * kPitch));
  std::cout << "[ measured ] expected " << expected << " Pa; smoothed mean " << smooth.mean
            << " std " << smooth.std << " min " << smooth.min << " max " << smooth.max << " ("
            << smooth.count << " vertices); raw mean " << raw.mean << " std " << raw.std << ", "
            << raw.nonzero << " of " << raw.count << " triangles loaded; nodal std " << node.std
            << "; lattice ripple 2a = " << 2.0 * ripple << "; load per lower sphere " << sites.mean
            << " N, scatter " << scatter << " over " << sites.count << " spheres\n";
  EXPECT_NEAR(smooth.mean / expected, 1.0, 0.02);
  EXPECT_LT(scatter, 0.15);  // the layer is settled: no sphere carries nothing or double
  EXPECT_LT(smooth.std / expected, std::max(0.08, 1.25 * std::sqrt(0.027 * 0.027 + passed * passed)));
  EXPECT_GT(smooth.min / expected, 0.8);
  EXPECT_LT(smooth.max / expected, 1.2);
  // The raw field is speckle: one loaded triangle per sphere, A_t / p² = 2.2 % of them, so its
  // standard deviation is √(1/f − 1) ≈ 6.7 times its mean; the nodal one (three vertices per
  // contact) is speckle too.
  EXPECT_LT(static_cast<double>(raw.nonzero) / static_cast<double>(raw.count), 0.1);
  EXPECT_GT(raw.std / raw.mean, 3.0);
  EXPECT_GT(node.std / node.mean, 1.0);

  // The exporter's VTU records and the surface frames carry both vertex pressures.
  const std::string record = read_text(exported / "plate_loads_000004.vtu");
  EXPECT_NE(record.find("Name=\"pressure_smoothed\""), std::string::npos);
  EXPECT_NE(record.find("Name=\"pressure_nodal\""), std::string::npos);
  const std::string frame = read_text(folder / "out" / "plate_000001.vtu");
  EXPECT_NE(frame.find("Name=\"pressure_smoothed\""), std::string::npos);
}

}  // namespace
}  // namespace quarry::fem_export
