// The deck's structures: section as parsed (io/deck_structures.cpp); its bad-deck cases are
// tests/bad_decks/fsi_*.yaml.
#include <gtest/gtest.h>

#include <string>

#include "io/deck.h"
#include "io/deck_writer.h"

namespace quarry {
namespace {

TEST(DeckStructures, EntriesAsWritten) {
  const std::string model = std::string(QUARRY_SOURCE_DIR) + "/tests/models/plate_free.bdf";
  const SimulationSpec spec = parse_deck_string(R"(simulation:
  end_time: 1.0
  domain: {min: [0, 0, 0], max: [1, 1, 1]}
materials:
  - {name: steel, density: 7800, youngs_modulus: 2.0e8, poisson_ratio: 0.3}
structures:
  - {name: bed, model: )" + model + R"(, material: steel, constraint_set: 1, surface: 2,
     period: 1.0e-4, filter: 3.0e-4, mass_scaling_time_step: 1.0e-6, damping: 50, drilling: 0.5, export: true}
  - {name: liner, model: )" + model + R"(, material: steel}
)",
                                                "deck.yaml");
  ASSERT_EQ(spec.structures.size(), 2u);
  const StructureSpec& bed = spec.structures[0];
  EXPECT_EQ(bed.name.value, "bed");
  EXPECT_EQ(bed.model.value, model);
  EXPECT_EQ(bed.material.value, "steel");
  ASSERT_TRUE(bed.constraint_set && bed.surface && bed.period && bed.filter);
  EXPECT_EQ(bed.constraint_set->value, 1);
  EXPECT_EQ(bed.surface->value, 2);
  EXPECT_DOUBLE_EQ(bed.period->value, 1e-4);
  EXPECT_DOUBLE_EQ(bed.filter->value, 3e-4);
  EXPECT_DOUBLE_EQ(bed.mass_scaling_time_step.value, 1e-6);
  EXPECT_DOUBLE_EQ(bed.damping.value, 50.0);
  ASSERT_TRUE(bed.drilling);
  EXPECT_DOUBLE_EQ(bed.drilling->value, 0.5);
  EXPECT_TRUE(bed.export_loads.value);
  EXPECT_EQ(bed.where.line, 7);
  const StructureSpec& liner = spec.structures[1];
  EXPECT_FALSE(liner.period || liner.filter || liner.constraint_set || liner.surface ||
               liner.drilling);
  EXPECT_EQ(liner.damping.value, 0.0);
  EXPECT_FALSE(liner.export_loads.value);
}

// A Gmsh mesh's entry: its unit, section, material, coupling group and supports; and the deck
// a checkpoint stores (io/deck_writer) gives the same entry back, drilling included, so that a
// restart builds the same structure.
TEST(DeckStructures, GmshEntryAndItsWrittenDeck) {
  const std::string mesh = std::string(QUARRY_SOURCE_DIR) + "/tests/models/plate.msh";
  const std::string text = R"(simulation:
  end_time: 1.0
  domain: {min: [0, 0, 0], max: [1, 1, 1]}
materials:
  - {name: steel, density: 7800, youngs_modulus: 2.0e8, poisson_ratio: 0.3}
structures:
  - {name: plate, model: )" + mesh + R"(, material: steel, units: mm, thickness: 0.005,
     youngs_modulus: 2.1e11, poisson_ratio: 0.28, density: 7850, yield_stress: 2.5e8,
     hardening_modulus: 1.0e9, coupling_group: coupling surface, drilling: 0.2,
     supports: [{name: edge, box: {min: [0, 0, 0], max: [0, 0.2, 0]}, fix: pinned},
                {name: side, group: clamped}]}
)";
  const SimulationSpec spec = parse_deck_string(text, "deck.yaml");
  ASSERT_EQ(spec.structures.size(), 1u);
  const auto check = [&](const SimulationSpec& s) {
    const StructureSpec& plate = s.structures.at(0);
    ASSERT_TRUE(plate.mesh);
    const MeshStructureSpec& m = *plate.mesh;
    EXPECT_EQ(m.units.value, MeshLengthUnit::millimetre);
    EXPECT_DOUBLE_EQ(m.thickness.value, 0.005);
    EXPECT_DOUBLE_EQ(m.youngs_modulus.value, 2.1e11);
    EXPECT_DOUBLE_EQ(m.poisson_ratio.value, 0.28);
    EXPECT_DOUBLE_EQ(m.density.value, 7850.0);
    EXPECT_DOUBLE_EQ(m.yield_stress.value, 2.5e8);
    EXPECT_DOUBLE_EQ(m.hardening_modulus.value, 1.0e9);
    EXPECT_EQ(m.coupling_group.value, "coupling surface");
    ASSERT_EQ(m.supports.size(), 2u);
    EXPECT_EQ(m.supports[0].name.value, "edge");
    EXPECT_EQ(m.supports[0].max.value, (Vec3{0.0, 0.2, 0.0}));
    EXPECT_EQ(m.supports[0].fix.value, SupportFixity::pinned);
    EXPECT_TRUE(m.supports[0].group.value.empty());
    EXPECT_EQ(m.supports[1].group.value, "clamped");
    EXPECT_EQ(m.supports[1].fix.value, SupportFixity::clamped);
    ASSERT_TRUE(plate.drilling);
    EXPECT_DOUBLE_EQ(plate.drilling->value, 0.2);
  };
  check(spec);
  check(parse_deck_string(write_deck(spec), "written.yaml"));
  // A bulk-data entry has no mesh part.
  const std::string model = std::string(QUARRY_SOURCE_DIR) + "/tests/models/plate_free.bdf";
  EXPECT_FALSE(parse_deck_string(R"(simulation:
  end_time: 1.0
  domain: {min: [0, 0, 0], max: [1, 1, 1]}
materials:
  - {name: steel, density: 7800, youngs_modulus: 2.0e8, poisson_ratio: 0.3}
structures:
  - {name: bed, model: )" + model + R"(, material: steel}
)", "deck.yaml").structures.at(0).mesh);
}

}  // namespace
}  // namespace quarry
