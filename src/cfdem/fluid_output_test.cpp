// The fluid's VTK image data: extents, spacing, one value per cell for each field, the values
// those of the coupling (the void fraction read back holds the particle's volume), and the
// .pvd series listing the frame.
#include "cfdem/fluid_output.h"

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>

#include "io/deck.h"
#include "sim/exchange.h"
#include "sim/step.h"

namespace quarry::cfdem {
namespace {

// The numbers between <DataArray … Name="name" …> and </DataArray>.
std::vector<double> data_array(const std::string& text, const std::string& name) {
  const std::size_t open = text.find("Name=\"" + name + "\"");
  if (open == std::string::npos) return {};
  const std::size_t begin = text.find('>', open) + 1;
  const std::size_t end = text.find("</DataArray>", begin);
  std::istringstream values(text.substr(begin, end - begin));
  std::vector<double> result;
  for (double v; values >> v;) result.push_back(v);
  return result;
}

TEST(FluidOutput, ImageDataHoldsTheFieldsOfEveryCell) {
  const std::string deck = R"(
simulation:
  end_time: 0.001
  time_step: 1.0e-6
  impact_speed: 0.01
  domain: {min: [0, 0, 0], max: [0.002, 0.003, 0.004]}
materials:
  - {name: solid, density: 1500, youngs_modulus: 1.0e7, poisson_ratio: 0.3}
interactions:
  - {materials: [solid, solid]}
particle_types:
  - {name: sphere, material: solid, size: {distribution: fixed, radius: 5.0e-5}}
)";
  World world = build_world(parse_deck_string(deck, "output.yaml"));
  sim::NewParticle particle;
  particle.position = {0.0007, 0.0012, 0.0031};
  particle.radius = 5e-5;
  sim::add_particles(world, std::span<const sim::NewParticle>(&particle, 1));
  FluidCouplingOptions options;
  options.grid.cell_size = {0.001, 0.001, 0.001};
  options.grid.cells = {2, 3, 4};
  options.boundaries.face(2, 1).kind = cfd::BoundaryKind::pressure_outlet;
  options.boundaries.face(2, 1).reference_point = {0, 0, 0.004};
  options.coupling_steps = 10;
  auto coupling = FluidCoupling::attach(world, options);
  sim::initialize(world);
  sim::advance(world, 100);

  const std::string text = fluid_image_text(*coupling);
  EXPECT_NE(text.find("<VTKFile type=\"ImageData\""), std::string::npos);
  EXPECT_NE(text.find("WholeExtent=\"0 2 0 3 0 4\""), std::string::npos);
  EXPECT_NE(text.find("Spacing=\"0.001 0.001 0.001\""), std::string::npos);
  const std::vector<double> velocity = data_array(text, "velocity");
  const std::vector<double> pressure = data_array(text, "pressure");
  const std::vector<double> void_fraction = data_array(text, "void_fraction");
  ASSERT_EQ(velocity.size(), 3u * 24u);
  ASSERT_EQ(pressure.size(), 24u);
  ASSERT_EQ(void_fraction.size(), 24u);
  // Cell (1, 2, 3) is the 24th: its values as the solver has them, to the last bit.
  EXPECT_EQ(pressure[23], coupling->fluid().pressure(1, 2, 3));
  EXPECT_EQ(velocity[3 * 23 + 2], coupling->fluid().cell_velocity(1, 2, 3).z);
  double solid = 0.0;  // m³
  for (double e : void_fraction) solid += (1.0 - e) * 1e-9;
  EXPECT_NEAR(solid / (4.0 / 3.0 * std::numbers::pi * std::pow(5e-5, 3)), 1.0, 1e-9);
  // Hydrostatic: p falls by ρ g Δz = 9.81 Pa per cell upwards (the particle barely stirs it).
  EXPECT_NEAR(pressure[0] - pressure[18], 3 * 1000.0 * 9.81 * 0.001, 1e-3);

  std::string folder = (std::filesystem::temp_directory_path() / "quarry_fluid_output_XXXXXX").string();
  ASSERT_NE(::mkdtemp(folder.data()), nullptr);
  PvdSeries series(std::filesystem::path(folder) / "fluid.pvd");
  write_fluid_frame(*coupling, folder, 7, world.time, series);
  std::ifstream pvd(std::filesystem::path(folder) / "fluid.pvd");
  std::stringstream pvd_text;
  pvd_text << pvd.rdbuf();
  EXPECT_NE(pvd_text.str().find("fluid_000007.vti"), std::string::npos) << pvd_text.str();
  EXPECT_TRUE(std::filesystem::exists(std::filesystem::path(folder) / "fluid_000007.vti"));
  std::filesystem::remove_all(folder);
}

}  // namespace
}  // namespace quarry::cfdem
