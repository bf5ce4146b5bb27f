// The deck's fluid: section: every key read into FluidSpec, and written back by the deck writer
// so that a checkpoint's effective deck keeps it (bad decks: tests/bad_decks/6*_fluid_*).
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>

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
  advection: hybrid
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
  EXPECT_EQ(f.advection.value, FluidAdvection::hybrid);
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
  EXPECT_EQ(spec.fluid->advection.value, FluidAdvection::central);
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

// ---- fluid.blocked (issue #18 §1): boxes, half-spaces and named surfaces ----

const char* kBlockedDeck = R"(simulation:
  end_time: 0.01
  time_step: 1.0e-5
  domain: {min: [0, 0, 0], max: [0.01, 0.004, 0.004]}
materials:
  - {name: glass, density: 2500, youngs_modulus: 1.0e7, poisson_ratio: 0.25}
interactions:
  - {materials: [glass, glass]}
particle_types:
  - {name: bead, material: glass, size: {distribution: fixed, radius: 1.0e-4}}
surfaces:
  - {name: post, type: box, min: [0.004, 0.001, 0], max: [0.005, 0.003, 0.004], material: glass}
  - {name: paddle, type: box, min: [0.007, 0, 0], max: [0.008, 0.001, 0.001], material: glass, motion: {type: translation, velocity: [0, 0, 0.01]}}
fluid:
  time_step: 1.0e-4
  grid: {origin: [0, 0, 0], cell_size: 0.001, cells: [10, 4, 4]}
  blocked:
    - {type: box, min: [0.001, 0, 0], max: [0.002, 0.004, 0.002]}
    - {type: half_space, point: [0, 0, 0.0035], normal: [0, 0, -1]}
    - {type: surface, surface: post}
)";

// "line:col" (1-based) of the `occurrence`-th `needle` in `text`.
std::string location_of(const std::string& text, const std::string& needle, int occurrence = 1) {
  std::size_t at = std::string::npos;
  for (int n = 0; n < occurrence; ++n) at = text.find(needle, at == std::string::npos ? 0 : at + 1);
  if (at == std::string::npos) return "not found";
  const std::size_t line_start = text.rfind('\n', at) == std::string::npos ? 0 : text.rfind('\n', at) + 1;
  const auto line = 1 + std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(at), '\n');
  return std::to_string(line) + ":" + std::to_string(at - line_start + 1);
}

// The formatted errors of a deck read as fluid.yaml ("" if none).
std::string deck_errors(const std::string& deck) {
  try {
    parse_deck_string(deck, "fluid.yaml");
  } catch (const UserError& e) {
    return e.diagnostics().format();
  }
  return {};
}

// The deck with its last blocked entry replaced by `entry`; the formatted errors ("" if none).
std::string blocked_errors(const std::string& entry, std::string* deck_text = nullptr) {
  std::string deck = kBlockedDeck;
  deck.replace(deck.find("    - {type: surface, surface: post}"), std::string("    - {type: surface, surface: post}").size(), entry);
  if (deck_text) *deck_text = deck;
  return deck_errors(deck);
}

TEST(DeckFluid, ReadsBlockedBoxesHalfSpacesAndSurfaces) {
  const SimulationSpec spec = parse_deck_string(kBlockedDeck, "fluid.yaml");
  ASSERT_TRUE(spec.fluid.has_value());
  const std::vector<FluidBlockedSpec>& blocked = spec.fluid->blocked;
  ASSERT_EQ(blocked.size(), 3u);
  EXPECT_EQ(blocked[0].kind.value, FluidBlockedKind::box);
  EXPECT_EQ(blocked[0].min.value, (Vec3{0.001, 0, 0}));
  EXPECT_EQ(blocked[0].max.value, (Vec3{0.002, 0.004, 0.002}));
  EXPECT_EQ(blocked[1].kind.value, FluidBlockedKind::half_space);
  EXPECT_EQ(blocked[1].point.value, (Vec3{0, 0, 0.0035}));
  EXPECT_EQ(blocked[1].normal.value, (Vec3{0, 0, -1}));
  EXPECT_EQ(blocked[2].kind.value, FluidBlockedKind::surface);
  EXPECT_EQ(blocked[2].surface.value, "post");
  // Locations: the entry (its map), the values, the list.
  const std::string deck = kBlockedDeck;
  EXPECT_EQ(fmt::format("{}:{}", blocked[0].where.line, blocked[0].where.column), location_of(deck, "{type: box, min: [0.001"));
  EXPECT_EQ(fmt::format("{}:{}", blocked[2].surface.where.line, blocked[2].surface.where.column),
            location_of(deck, "post", 2));
  EXPECT_EQ(spec.fluid->blocked_where.line, 18);
}

TEST(DeckFluid, BlockedRoundTripsThroughTheWriter) {
  const SimulationSpec spec = parse_deck_string(kBlockedDeck, "fluid.yaml");
  const std::string written = write_deck(spec);
  EXPECT_NE(written.find("  blocked:\n    - {type: box, min: [0.001, 0, 0], max: [0.002, 0.004, 0.002]}\n"),
            std::string::npos)
      << written;
  const SimulationSpec again = parse_deck_string(written, "written.yaml");
  ASSERT_TRUE(again.fluid.has_value()) << written;
  ASSERT_EQ(again.fluid->blocked.size(), 3u);
  for (std::size_t n = 0; n < 3; ++n) {
    const FluidBlockedSpec &a = spec.fluid->blocked[n], &b = again.fluid->blocked[n];
    EXPECT_EQ(a.kind.value, b.kind.value);
    EXPECT_EQ(a.min.value, b.min.value);
    EXPECT_EQ(a.max.value, b.max.value);
    EXPECT_EQ(a.point.value, b.point.value);
    EXPECT_EQ(a.normal.value, b.normal.value);
    EXPECT_EQ(a.surface.value, b.surface.value);
  }
  EXPECT_EQ(write_deck(again), written);
  // No blocked entries: no key written.
  EXPECT_EQ(write_deck(parse_deck_string(kFluidDeck, "fluid.yaml")).find("blocked"), std::string::npos);
}

// Bad entries, each reported at its own line and column with a hint.
TEST(DeckFluid, RefusesBadBlockedEntriesAtTheirKey) {
  std::string deck;
  std::string errors = blocked_errors("    - {type: surface, surface: pst}", &deck);
  EXPECT_NE(errors.find("fluid.yaml:" + location_of(deck, "pst") + ": error: unknown surface \"pst\""),
            std::string::npos)
      << errors;
  EXPECT_NE(errors.find("did you mean \"post\"?"), std::string::npos) << errors;

  errors = blocked_errors("    - {type: surface, surface: paddle}", &deck);
  EXPECT_NE(errors.find("fluid.yaml:" + location_of(deck, "paddle", 2) +
                        ": error: surface \"paddle\" has a motion, but blocked fluid cells are fixed"),
            std::string::npos)
      << errors;

  errors = blocked_errors("    - {type: box, min: [0.003, 0, 0], max: [0.003, 0.004, 0.002]}", &deck);
  EXPECT_NE(errors.find("fluid.yaml:" + location_of(deck, "[0.003, 0.004") +
                        ": error: blocked box max must exceed min in every component, but max.x = 0.003 m"),
            std::string::npos)
      << errors;

  errors = blocked_errors("    - {type: half_space, point: [0, 0, 0], normal: [0, 0, 0]}", &deck);
  EXPECT_NE(errors.find("fluid.yaml:" + location_of(deck, "[0, 0, 0]}") + ": error: normal must be a non-zero vector"),
            std::string::npos)
      << errors;

  errors = blocked_errors("    - {type: boxx, min: [0, 0, 0], max: [1, 1, 1]}", &deck);
  EXPECT_NE(errors.find("fluid.yaml:" + location_of(deck, "boxx") + ": error: unknown blocked region type \"boxx\""),
            std::string::npos)
      << errors;
  EXPECT_NE(errors.find("did you mean \"box\"?"), std::string::npos) << errors;

  errors = blocked_errors("    - {type: box, min: [0, 0, 0], max: [1, 1, 1], normal: [0, 0, 1]}", &deck);
  EXPECT_NE(errors.find("fluid.yaml:" + location_of(deck, "normal: [0, 0, 1]}") +
                        ": error: key \"normal\" does not apply to blocked region type \"box\""),
            std::string::npos)
      << errors;

  errors = blocked_errors("    - {type: surface}", &deck);
  EXPECT_NE(errors.find("missing required key \"surface\""), std::string::npos) << errors;
}

// An inflow needs a way out: with no pressure_outlet the inlets' volume flows must sum to zero
// (an incompressible fluid; bad deck fluid_outlet_01). Flow in at y_min and out at y_max through
// two inlets of the same face area and speed passes; in alone, or in at both, is refused at the
// first inlet's velocity with the net flow: 2 × (4 × 12 cells × 0.25 mm²) × 0.01 m/s =
// 2.4e-7 m³/s.
TEST(DeckFluid, AnInflowWithNoOutletMustBalance) {
  const auto errors_with = [](const std::string& y_max) {
    std::string deck = kFluidDeck;
    const std::string outlet = "    z_max: {type: pressure_outlet, reference_pressure: 101325, ";
    deck.erase(deck.find(outlet), deck.find('\n', deck.find(outlet)) + 1 - deck.find(outlet));
    const std::string wall = "    y_max: {type: wall, velocity: [0, 0, 0.002]}";
    deck.replace(deck.find(wall), wall.size(), "    y_max: " + y_max);
    return deck_errors(deck);
  };
  EXPECT_EQ(errors_with("{type: velocity_inlet, velocity: [0, 0.01, 0]}"), "");
  std::string errors = errors_with("{type: wall}");
  EXPECT_NE(errors.find("fluid.yaml:19:45: error: fluid flows in through the velocity inlets "
                        "(1.2e-07 m³/s net) but no face is a pressure_outlet"),
            std::string::npos)
      << errors;
  errors = errors_with("{type: velocity_inlet, velocity: [0, -0.01, 0]}");
  EXPECT_NE(errors.find("(2.4e-07 m³/s net)"), std::string::npos) << errors;
}

// A boundary the fluid step cannot carry: dt_f Σ|u_a| / Δx > 1 (CFL). 0.01 m/s with a step of
// 5e-5 s in cells of 0.5 mm is 0.001 of a cell per step; 20 m/s is 2 cells.
TEST(DeckFluid, BoundaryVelocitiesWithinTheFluidStepsCfl) {
  std::string deck = kFluidDeck;
  deck.replace(deck.find("[0, 0.01, 0]"), std::string("[0, 0.01, 0]").size(), "[0, 20, 0]");
  const std::string errors = deck_errors(deck);
  EXPECT_NE(errors.find("yaml:19:45: error: the fluid at y_min moves 2 cells per fluid step"),
            std::string::npos)
      << errors;
  EXPECT_NE(errors.find("a fluid time_step of at most 2.5e-05 s"), std::string::npos) << errors;
}

// A viscosity below any real fluid's (fuzzing found 1e-320 Pa·s, which passed as > 0 and made
// the first fluid step NaN): refused at its key. Hydrogen gas, the least viscous, has
// 8.8e-6 Pa·s at 20 °C (CRC Handbook), so 2e-6 (a rarefied gas) stays accepted.
TEST(DeckFluid, RefusesAViscosityBelowAnyRealFluid) {
  const auto with_viscosity = [](const std::string& value) {
    std::string deck = kFluidDeck;
    deck.replace(deck.find("0.00102"), std::string("0.00102").size(), value);
    return deck_errors(deck);
  };
  EXPECT_EQ(with_viscosity("2e-6"), "");
  const std::string errors = with_viscosity("1e-320");
  EXPECT_NE(errors.find("fluid.yaml:13:14: error: \"viscosity\" must be at least 1e-07 Pa·s, got "
                        "1e-320 Pa·s"),
            std::string::npos)
      << errors;
  EXPECT_NE(errors.find("hydrogen, has 8.8e-6 Pa·s"), std::string::npos) << errors;
}

}  // namespace
}  // namespace quarry
