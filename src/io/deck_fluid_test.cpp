// The deck's fluid: section: every key read into FluidSpec, and written back by the deck writer
// so that a checkpoint's effective deck keeps it (bad decks: tests/bad_decks/6*_fluid_*).
#include <gtest/gtest.h>

#include "io/deck.h"
#include "io/deck_writer.h"

namespace quarry {
namespace {

const char* kFluidDeck = R"(simulation:
  end_time: 0.015
  time_step: 1.0e-6
  domain: {min: [-0.001, -0.001, 0.0], max: [0.001, 0.001, 0.006]}
materials:
  - {name: particle, density: 1500, youngs_modulus: 1.0e7, poisson_ratio: 0.3}
interactions:
  - {materials: [particle, particle]}
particle_types:
  - {name: sphere, material: particle, size: {distribution: fixed, radius: 5.0e-5}}
fluid:
  density: 998.5
  viscosity: 0.00102
  time_step: 5.0e-5
  grid: {origin: [-0.001, -0.001, 0.0], cell_size: 5.0e-4, cells: [4, 4, 12]}
  boundaries:
    x_min: {type: periodic}
    x_max: {type: periodic}
    y_min: {type: velocity_inlet, velocity: [0, 0.01, 0]}
    y_max: {type: wall, velocity: [0, 0, 0.002]}
    z_max: {type: pressure_outlet, reference_pressure: 101325, reference_point: [0, 0, 0.006]}
  model: A
  drag_udf: {library: libs/usrStokesDrag.so, function: usrStokesDrag}
)";

void expect_fluid(const FluidSpec& f) {
  EXPECT_EQ(f.density.value, 998.5);
  EXPECT_EQ(f.viscosity.value, 0.00102);
  EXPECT_EQ(f.time_step.value, 5.0e-5);
  EXPECT_EQ(f.origin.value, (Vec3{-0.001, -0.001, 0.0}));
  EXPECT_EQ(f.cell_size.value, 5.0e-4);
  EXPECT_EQ(f.cells.value, (Vec3{4, 4, 12}));
  EXPECT_EQ(f.faces[0].type.value, FluidBoundaryType::periodic);
  EXPECT_EQ(f.faces[1].type.value, FluidBoundaryType::periodic);
  EXPECT_EQ(f.faces[2].type.value, FluidBoundaryType::velocity_inlet);
  EXPECT_EQ(f.faces[2].velocity.value, (Vec3{0, 0.01, 0}));
  EXPECT_EQ(f.faces[3].type.value, FluidBoundaryType::wall);
  EXPECT_EQ(f.faces[3].velocity.value, (Vec3{0, 0, 0.002}));
  EXPECT_EQ(f.faces[4].type.value, FluidBoundaryType::wall);  // not named: a wall
  EXPECT_EQ(f.faces[5].type.value, FluidBoundaryType::pressure_outlet);
  EXPECT_EQ(f.faces[5].reference_pressure.value, 101325.0);
  EXPECT_EQ(f.faces[5].reference_point.value, (Vec3{0, 0, 0.006}));
  EXPECT_EQ(f.model.value, FluidModel::a);
  ASSERT_TRUE(f.drag_udf.has_value());
  EXPECT_EQ(f.drag_udf->function.value, "usrStokesDrag");
}

// Particles periodic along x in a fluid periodic along x over the same period (the grid spans
// the domain): accepted. The mismatches are bad decks periodic_04 and periodic_07.
TEST(DeckFluid, PeriodicParticlesWithAFluidOfTheSamePeriod) {
  std::string deck = kFluidDeck;
  const std::string domain = "max: [0.001, 0.001, 0.006]}";
  deck.replace(deck.find(domain), domain.size(), "max: [0.001, 0.001, 0.006], periodic: [x]}");
  const SimulationSpec spec = parse_deck_string(deck, "fluid.yaml");
  EXPECT_TRUE(spec.simulation.periodic.value[0]);
  ASSERT_TRUE(spec.fluid.has_value());
}

TEST(DeckFluid, ReadsEveryKey) {
  const SimulationSpec spec = parse_deck_string(kFluidDeck, "fluid.yaml");
  ASSERT_TRUE(spec.fluid.has_value());
  expect_fluid(*spec.fluid);
  EXPECT_EQ(spec.fluid->drag_udf->library.value, "libs/usrStokesDrag.so");
  EXPECT_EQ(spec.fluid->drag_udf->library.where.line, 23);
  EXPECT_EQ(spec.fluid->time_step.where.line, 14);
}

TEST(DeckFluid, UdfLibraryIsRelativeToTheDecksFolder) {
  DeckParseOptions options;
  options.base_directory = "/some/where";
  const SimulationSpec spec = parse_deck_string(kFluidDeck, "fluid.yaml", options);
  EXPECT_EQ(spec.fluid->drag_udf->library.value, "/some/where/libs/usrStokesDrag.so");
}

TEST(DeckFluid, DefaultsAndTheBuiltInLaw) {
  std::string deck = kFluidDeck;
  deck = deck.substr(0, deck.find("  density: 998.5")) +
         "  time_step: 5.0e-5\n  grid: {origin: [0, 0, 0], cell_size: 0.001, cells: [2, 2, 6]}\n"
         "  drag_law: schiller_naumann\n";
  const SimulationSpec spec = parse_deck_string(deck, "fluid.yaml");
  ASSERT_TRUE(spec.fluid.has_value());
  EXPECT_EQ(spec.fluid->density.value, 1000.0);
  EXPECT_EQ(spec.fluid->viscosity.value, 1e-3);
  EXPECT_EQ(spec.fluid->drag_law.value, "schiller_naumann");
  EXPECT_FALSE(spec.fluid->drag_udf.has_value());
  for (const FluidFaceSpec& face : spec.fluid->faces) EXPECT_EQ(face.type.value, FluidBoundaryType::wall);
}

TEST(DeckFluid, WriterRoundTrip) {
  const SimulationSpec spec = parse_deck_string(kFluidDeck, "fluid.yaml");
  const std::string written = write_deck(spec);
  const SimulationSpec again = parse_deck_string(written, "written.yaml");
  ASSERT_TRUE(again.fluid.has_value()) << written;
  expect_fluid(*again.fluid);
  EXPECT_EQ(again.fluid->drag_udf->library.value, "libs/usrStokesDrag.so");
  EXPECT_EQ(write_deck(again), written);
}

}  // namespace
}  // namespace quarry
