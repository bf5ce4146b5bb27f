// Tests for the bulk data reader: the seed's EDEM card in fixed, free and large-field format, one
// plate model written in the three formats, continuation lines, Nastran reals, units, SET
// ranges, refused and ignored cards, and the broken models of tests/bad_models (first error
// line of each, as for tests/bad_decks).
#include "io/bulk_data.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "io/bulk_fields.h"
#include "io/gmsh_reader.h"
#include "io/io_test_support.h"

namespace quarry {
namespace {

namespace fs = std::filesystem;

using io_testing::first_line;
using io_testing::read_text;
using io_testing::replace_all;
using io_testing::source_dir;

// The formatted errors of a model text that must fail; empty (and a test failure) if it reads.
std::string errors_of(const std::string& text, const BulkDataOptions& options = {}) {
  try {
    read_bulk_data_string(text, "model.bdf", options);
  } catch (const UserError& error) {
    return error.diagnostics().format();
  }
  ADD_FAILURE() << "the model read without error:\n" << text;
  return {};
}

// A one-quad SI model around the card under test; SURF 2 holds the quad.
std::string with_quad(const std::string& cards) {
  return "DTI,UNITS,1,KG,N,M,S\n"
         "GRID,1,,0.,0.,0.\nGRID,2,,1.,0.,0.\nGRID,3,,1.,1.,0.\nGRID,4,,0.,1.,0.\n"
         "CQUAD4,1,1,1,2,3,4\nPSHELL,1,1,0.005,1,,1\nMAT1,1,2.1+11,,0.3,7850.\n"
         "SURF,2,ELFACE\n,1\n" +
         cards;
}

void expect_seed_edem(const StructureModel& model) {
  ASSERT_EQ(model.couplings.size(), 1u);
  const EdemCoupling& edem = model.couplings[0];
  EXPECT_EQ(edem.id, 100);
  ASSERT_TRUE(edem.period.has_value());
  EXPECT_DOUBLE_EQ(*edem.period, 0.1);
  ASSERT_TRUE(edem.filter.has_value());
  EXPECT_DOUBLE_EQ(*edem.filter, 0.15);
  ASSERT_EQ(edem.surfaces.size(), 1u);
  EXPECT_EQ(edem.surfaces[0].surface_id, 2);
  EXPECT_EQ(edem.surfaces[0].label.value_or(""), "Surf_2");
}

// The seed's example, "EDEM 100 CONTROL 0.1 0.15 COUPLING SURF 2 Surf_2", as written (one line
// of ten 8-column fields) and as the manual's table lays it out (flags on continuation lines),
// in fixed, free and large-field format.
TEST(BulkDataEdem, SeedExampleInEveryFormat) {
  const std::vector<std::pair<std::string, std::string>> variants = {
      {"fixed, one line as the seed writes it",
       "EDEM    100     CONTROL 0.1     0.15    COUPLINGSURF    2       Surf_2\n"},
      {"fixed, flags on blank-first-field continuation lines",
       "EDEM    100\n        CONTROL 0.1     0.15\n        COUPLINGSURF    2       Surf_2\n"},
      {"fixed, flags on '+' continuation lines",
       "EDEM    100                                                             +E1\n"
       "+E1     CONTROL 0.1     0.15                                            +E2\n"
       "+E2     COUPLINGSURF    2       Surf_2\n"},
      {"fixed, flags in field 1 as the manual's table shows them",
       "EDEM    100\nCONTROL 0.1     0.15\nCOUPLINGSURF    2       Surf_2\n"},
      {"free, one line", "EDEM,100,CONTROL,0.1,0.15,COUPLING,SURF,2,Surf_2\n"},
      {"free, continuation lines", "EDEM,100\n,CONTROL,0.1,0.15\n,COUPLING,SURF,2,Surf_2\n"},
      {"free, '+' continuation lines",
       "EDEM,100,,,,,,,,+\n+,CONTROL,.1,.15\n+,COUPLING,SURF,2,Surf_2\n"},
      {"large field",
       "EDEM*   100             CONTROL         0.1             0.15\n"
       "*       COUPLING        SURF            2               Surf_2\n"},
      {"large field, free", "EDEM*,100,CONTROL,1.-1,1.5-1\n*,COUPLING,SURF,2,Surf_2\n"},
  };
  for (const auto& [description, card] : variants) {
    SCOPED_TRACE(description);
    try {
      expect_seed_edem(read_bulk_data_string(with_quad(card), "edem.bdf"));
    } catch (const UserError& error) {
      ADD_FAILURE() << error.diagnostics().format();
    }
  }
}

// Blank PERIOD and FILTER stay absent (the coupling applies the seed's defaults, TTERM/100 and
// PERIOD); LABEL is optional; COUPLING lines repeat.
TEST(BulkDataEdem, DefaultsAndSeveralSurfaces) {
  const StructureModel model = read_bulk_data_string(
      with_quad("SURF,3,ELEM,LIST\n,1\nEDEM,7\n,CONTROL\n,COUPLING,SURF,2\n,COUPLING,SURF,3,lid\n"),
      "edem.bdf");
  ASSERT_EQ(model.couplings.size(), 1u);
  const EdemCoupling& edem = model.couplings[0];
  EXPECT_EQ(edem.id, 7);
  EXPECT_FALSE(edem.period.has_value());
  EXPECT_FALSE(edem.filter.has_value());
  ASSERT_EQ(edem.surfaces.size(), 2u);
  EXPECT_EQ(edem.surfaces[0].surface_id, 2);
  EXPECT_FALSE(edem.surfaces[0].label.has_value());
  EXPECT_EQ(default_coupling_label(7, 2), "coupling_7_interface_2");
  EXPECT_EQ(edem.surfaces[1].label.value_or(""), "lid");
  EXPECT_EQ(model.surfaces.at(3).elements, std::vector<int>{1});
}

TEST(BulkDataEdem, ErrorsAtTheField) {
  EXPECT_EQ(first_line(errors_of(with_quad("EDEM,100,CONTROL,0.1,0.05,COUPLING,SURF,2\n"))),
            "model.bdf:11:22: error: EDEM FILTER must be > PERIOD (0.1), got 0.05");
  EXPECT_EQ(first_line(errors_of(with_quad("EDEM,100,CONTROL,0.1,,COUPLING,SET,2\n"))),
            "model.bdf:11:32: error: EDEM COUPLING TYPE must be SURF, got \"SET\"");
  EXPECT_EQ(first_line(errors_of(with_quad("EDEM,100,CONTROL,0.1\n"))),
            "model.bdf:11:6: error: EDEM 100 has no COUPLING line");
  EXPECT_EQ(first_line(errors_of(with_quad("EDEM,100,,,,,,,,\n,COUPLING,SURF,9,x\n"))),
            "model.bdf:12:16: error: EDEM 100 names SURF 9, which is not defined");
  EXPECT_EQ(first_line(errors_of(with_quad("EDEM,100,PERIOD,0.1\n"))),
            "model.bdf:11:10: error: expected CONTROL or COUPLING in the EDEM card, got "
            "\"PERIOD\"");
}

// Compares everything but the source locations.
void expect_same_model(const StructureModel& a, const StructureModel& b) {
  EXPECT_EQ(a.declared_units, b.declared_units);
  ASSERT_EQ(a.nodes.size(), b.nodes.size());
  for (const auto& [id, node] : a.nodes) {
    ASSERT_TRUE(b.nodes.count(id)) << "grid " << id;
    EXPECT_EQ(node.position, b.nodes.at(id).position) << "grid " << id;
    EXPECT_EQ(node.permanent_constraints, b.nodes.at(id).permanent_constraints);
  }
  ASSERT_EQ(a.shells.size(), b.shells.size());
  for (std::size_t i = 0; i < a.shells.size(); ++i) {
    EXPECT_EQ(a.shells[i].id, b.shells[i].id);
    EXPECT_EQ(a.shells[i].property_id, b.shells[i].property_id);
    EXPECT_EQ(a.shells[i].shape, b.shells[i].shape);
    EXPECT_EQ(a.shells[i].nodes, b.shells[i].nodes);
  }
  ASSERT_EQ(a.properties.size(), b.properties.size());
  for (const auto& [id, p] : a.properties) {
    const ShellProperty& q = b.properties.at(id);
    EXPECT_EQ(p.thickness, q.thickness);
    EXPECT_EQ(p.membrane_material_id, q.membrane_material_id);
    EXPECT_EQ(p.bending_material_id, q.bending_material_id);
    EXPECT_EQ(p.shear_material_id, q.shear_material_id);
    EXPECT_EQ(p.bending_inertia_ratio, q.bending_inertia_ratio);
    EXPECT_EQ(p.shear_thickness_ratio, q.shear_thickness_ratio);
    EXPECT_EQ(p.nonstructural_mass, q.nonstructural_mass);
    EXPECT_EQ(p.fiber_bottom, q.fiber_bottom);
    EXPECT_EQ(p.fiber_top, q.fiber_top);
  }
  ASSERT_EQ(a.materials.size(), b.materials.size());
  for (const auto& [id, m] : a.materials) {
    const IsotropicMaterial& n = b.materials.at(id);
    EXPECT_EQ(m.youngs_modulus, n.youngs_modulus);
    EXPECT_EQ(m.shear_modulus, n.shear_modulus);
    EXPECT_EQ(m.poisson_ratio, n.poisson_ratio);
    EXPECT_EQ(m.density, n.density);
    ASSERT_EQ(m.plasticity.has_value(), n.plasticity.has_value());
    if (m.plasticity) {
      EXPECT_EQ(m.plasticity->initial_yield_stress, n.plasticity->initial_yield_stress);
      EXPECT_EQ(m.plasticity->hardening_modulus, n.plasticity->hardening_modulus);
    }
  }
  ASSERT_EQ(a.constraints.size(), b.constraints.size());
  for (std::size_t i = 0; i < a.constraints.size(); ++i) {
    EXPECT_EQ(a.constraints[i].set_id, b.constraints[i].set_id);
    EXPECT_EQ(a.constraints[i].dofs, b.constraints[i].dofs);
    EXPECT_EQ(a.constraints[i].nodes, b.constraints[i].nodes);
  }
  ASSERT_EQ(a.sets.size(), b.sets.size());
  for (const auto& [id, set] : a.sets) {
    EXPECT_EQ(set.kind, b.sets.at(id).kind);
    EXPECT_EQ(set.members, b.sets.at(id).members);
  }
  ASSERT_EQ(a.surfaces.size(), b.surfaces.size());
  for (const auto& [id, surface] : a.surfaces)
    EXPECT_EQ(surface.elements, b.surfaces.at(id).elements);
  ASSERT_EQ(a.couplings.size(), b.couplings.size());
  for (std::size_t i = 0; i < a.couplings.size(); ++i) {
    EXPECT_EQ(a.couplings[i].id, b.couplings[i].id);
    EXPECT_EQ(a.couplings[i].period, b.couplings[i].period);
    EXPECT_EQ(a.couplings[i].filter, b.couplings[i].filter);
    ASSERT_EQ(a.couplings[i].surfaces.size(), b.couplings[i].surfaces.size());
    for (std::size_t k = 0; k < a.couplings[i].surfaces.size(); ++k) {
      EXPECT_EQ(a.couplings[i].surfaces[k].surface_id, b.couplings[i].surfaces[k].surface_id);
      EXPECT_EQ(a.couplings[i].surfaces[k].label, b.couplings[i].surfaces[k].label);
    }
  }
}

StructureModel read_plate(const std::string& name) {
  const std::string path = (source_dir() / "tests" / "models" / name).string();
  try {
    return read_bulk_data(path);
  } catch (const UserError& error) {
    ADD_FAILURE() << error.diagnostics().format();
    return {};
  }
}

// tests/models/plate_{fixed,free,large}.bdf: one model, three formats, the same StructureModel.
// The values are in mm, tonne, s (DTI,UNITS MGG N MM S); in SI: length × 1e-3 m/mm, stress ×
// 1e6 Pa/MPa, density × 1e12 (kg/m³)/(t/mm³), time × 1.
TEST(BulkDataPlate, SameModelInFixedFreeAndLargeFormat) {
  const StructureModel fixed = read_plate("plate_fixed.bdf");
  const StructureModel free = read_plate("plate_free.bdf");
  const StructureModel large = read_plate("plate_large.bdf");
  {
    SCOPED_TRACE("free");
    expect_same_model(fixed, free);
  }
  {
    SCOPED_TRACE("large");
    expect_same_model(fixed, large);
  }

  const StructureModel& model = fixed;
  EXPECT_EQ(model.declared_units, UnitSystem::mm_tonne_second);
  ASSERT_EQ(model.nodes.size(), 9u);
  EXPECT_EQ(model.nodes.at(9).position, (Vec3{0.2, 0.2, 0.0}));
  EXPECT_EQ(model.nodes.at(5).position, (Vec3{0.1, 0.1, 0.0}));
  ASSERT_EQ(model.shells.size(), 5u);
  const std::vector<int> order = {model.shells[0].id, model.shells[1].id, model.shells[2].id,
                                  model.shells[3].id, model.shells[4].id};
  EXPECT_EQ(order, (std::vector<int>{1, 2, 3, 4, 5}));  // file order
  EXPECT_EQ(model.shells[1].nodes, (std::array<int, 4>{2, 3, 6, 5}));
  EXPECT_EQ(model.shells[3].shape, ShellShape::tria3);
  EXPECT_EQ(model.shells[3].nodes, (std::array<int, 4>{4, 5, 8, 0}));

  const ShellProperty& shell = model.properties.at(1);
  EXPECT_DOUBLE_EQ(shell.thickness, 0.005);
  EXPECT_EQ(shell.membrane_material_id, 1);
  EXPECT_EQ(shell.bending_material_id, 1);
  EXPECT_EQ(shell.shear_material_id, 1);
  EXPECT_DOUBLE_EQ(shell.bending_inertia_ratio, 1.0);
  EXPECT_DOUBLE_EQ(shell.shear_thickness_ratio, 0.833333);
  EXPECT_DOUBLE_EQ(shell.fiber_bottom, -0.0025);
  EXPECT_DOUBLE_EQ(shell.fiber_top, 0.0025);

  const IsotropicMaterial& steel = model.materials.at(1);
  EXPECT_DOUBLE_EQ(steel.youngs_modulus, 2.1e11);  // 2.1+5 MPa
  EXPECT_DOUBLE_EQ(steel.poisson_ratio, 0.3);
  EXPECT_DOUBLE_EQ(steel.shear_modulus, 2.1e11 / (2.0 * 1.3));  // E = 2(1 + ν)G
  EXPECT_NEAR(steel.density, 7850.0, 1e-9);                     // 7.85-9 t/mm³
  ASSERT_TRUE(steel.plasticity.has_value());
  EXPECT_DOUBLE_EQ(steel.plasticity->initial_yield_stress, 250e6);  // 250. MPa
  EXPECT_DOUBLE_EQ(steel.plasticity->hardening_modulus, 1e9);       // 1000. MPa

  ASSERT_EQ(model.constraints.size(), 2u);
  EXPECT_EQ(model.constraints[0].dofs, DofSet::all());
  EXPECT_EQ(model.constraints[0].nodes, (std::vector<int>{1, 4, 7}));
  EXPECT_EQ(model.constraints[1].nodes, (std::vector<int>{3}));
  EXPECT_TRUE(model.constraints[1].dofs.has(3));
  EXPECT_FALSE(model.constraints[1].dofs.has(1));

  EXPECT_EQ(model.sets.at(10).members, (std::vector<int>{1, 2, 3, 4, 6, 7, 8, 9}));
  EXPECT_EQ(model.sets.at(11).kind, SetKind::element);
  EXPECT_EQ(model.sets.at(11).members, (std::vector<int>{1, 2, 3, 4, 5}));
  EXPECT_EQ(model.surfaces.at(2).elements, (std::vector<int>{1, 2, 3, 4, 5}));
  expect_seed_edem(model);

  // Locations point at the cards in their file.
  EXPECT_EQ(model.where(model.shells[0].where).line, 14);
  EXPECT_NE(model.where(model.shells[0].where).file.find("plate_fixed.bdf"), std::string::npos);
  EXPECT_FALSE(model.notes.has_errors());
}

TEST(BulkDataFormat, NastranRealShorthand) {
  using bulk_detail::parse_real;
  EXPECT_DOUBLE_EQ(*parse_real("1.-3"), 1e-3);
  EXPECT_DOUBLE_EQ(*parse_real("7.85-9"), 7.85e-9);
  EXPECT_DOUBLE_EQ(*parse_real("2.1+5"), 2.1e5);
  EXPECT_DOUBLE_EQ(*parse_real("-2.1+5"), -2.1e5);
  EXPECT_DOUBLE_EQ(*parse_real(".5-1"), 0.05);
  EXPECT_DOUBLE_EQ(*parse_real("1.E-3"), 1e-3);
  EXPECT_DOUBLE_EQ(*parse_real("1.5e+3"), 1.5e3);
  EXPECT_DOUBLE_EQ(*parse_real("1.D-3"), 1e-3);
  EXPECT_DOUBLE_EQ(*parse_real("+3."), 3.0);
  EXPECT_DOUBLE_EQ(*parse_real("210000"), 210000.0);  // an integer is a real too
  EXPECT_DOUBLE_EQ(*parse_real("0."), 0.0);
  for (const char* bad : {"1-3", "1.0.0", "1.+", "E5", ".", "", "1.5 E3", "abc", "1.E", "1.e400"})
    EXPECT_FALSE(parse_real(bad).has_value()) << bad;

  using bulk_detail::parse_integer;
  EXPECT_EQ(*parse_integer("123"), 123);
  EXPECT_EQ(*parse_integer("+7"), 7);
  EXPECT_EQ(*parse_integer("-7"), -7);
  for (const char* bad : {"1.", "1e3", "", "+", "++1", "12a"})
    EXPECT_FALSE(parse_integer(bad).has_value()) << bad;

  const StructureModel model = read_bulk_data_string(
      with_quad("MAT1,2,2.1+5,8.+4,,7.85-9\n").replace(0, 20, "DTI,UNITS,1,MGG,N,MM,S"),
      "model.bdf");
  EXPECT_DOUBLE_EQ(model.materials.at(2).youngs_modulus, 2.1e11);
  EXPECT_DOUBLE_EQ(model.materials.at(2).shear_modulus, 8e10);
  EXPECT_DOUBLE_EQ(model.materials.at(2).poisson_ratio, 2.1e5 / (2.0 * 8e4) - 1.0);
}

// Every way a card continues: '+' and named '+A' marks, a blank first field, '*' large-field
// halves, free-format ',' and '+', with comment and blank lines in between.
TEST(BulkDataFormat, ContinuationVariants) {
  const std::string base =
      "DTI,UNITS,1,KG,N,M,S\nGRID,1\nGRID,2,,1.\nGRID,3,,1.,1.\n"
      "MAT1,1,2.1+11,,0.3,7850.\nCTRIA3,1,1,1,2,3\n";
  const std::vector<std::pair<std::string, std::string>> variants = {
      {"plus", "PSHELL  1       1       .005    1               1\n+       1.-3    2.-3\n"},
      {"named marks",
       "PSHELL  1       1       .005    1               1                       +PS1\n"
       "+PS1    1.-3    2.-3\n"},
      {"blank first field",
       "PSHELL  1       1       .005    1               1\n        1.-3    2.-3\n"},
      {"comments between",
       "PSHELL  1       1       .005    1               1 $ shell\n"
       "$ a comment line\n\n// another\n        1.-3    2.-3\n"},
      {"large",
       "PSHELL* 1               1               .005            1\n"
       "*                       1\n*       1.-3            2.-3\n"},
      {"large with a small continuation",
       "PSHELL* 1               1               .005            1\n"
       "*                       1\n+       1.-3    2.-3\n"},
      {"large with marks in columns 73-80",
       "PSHELL* 1               1               .005            1               *PS1\n"
       "*PS1                    1                                               *PS2\n"
       "*PS2    1.-3            2.-3\n"},
      {"free comma", "PSHELL,1,1,.005,1,,1\n,1.-3,2.-3\n"},
      {"free plus", "PSHELL,1,1,.005,1,,1,,,+\n+,1.-3,2.-3\n"},
      {"free with blanks", "PSHELL , 1 , 1 , .005 , 1 , , 1\n  , 1.-3 , 2.-3\n"},
  };
  for (const auto& [description, pshell] : variants) {
    SCOPED_TRACE(description);
    try {
      const StructureModel model = read_bulk_data_string(base + pshell, "model.bdf");
      const ShellProperty& property = model.properties.at(1);
      EXPECT_DOUBLE_EQ(property.thickness, 0.005);
      EXPECT_EQ(property.bending_material_id, 1);
      EXPECT_EQ(property.shear_material_id, 1);
      EXPECT_DOUBLE_EQ(property.fiber_bottom, 1e-3);
      EXPECT_DOUBLE_EQ(property.fiber_top, 2e-3);
    } catch (const UserError& error) {
      ADD_FAILURE() << error.diagnostics().format();
    }
  }
}

// The model declares its units (UNITS = in the I/O options, or DTI,UNITS) or the caller states
// them; never guessed. Conversion factors are those of convert_to_si (bulk_data.cpp).
TEST(BulkDataUnits, DeclaredStatedOrRefused) {
  const std::string cards =
      "BEGIN BULK\nGRID,1\nGRID,2,,1000.\nGRID,3,,1000.,1000.\n"
      "CTRIA3,1,1,1,2,3\nPSHELL,1,1,5.,1,,1,,2.-6\n"
      "MAT1,1,2.1+5,,.3,7.85-9\nENDDATA\n";
  const StructureModel mpa = read_bulk_data_string("SOL 129\nUNITS = MPA\n" + cards, "mpa.bdf");
  EXPECT_EQ(mpa.declared_units, UnitSystem::mm_tonne_second);
  EXPECT_EQ(mpa.nodes.at(3).position, (Vec3{1.0, 1.0, 0.0}));
  EXPECT_DOUBLE_EQ(mpa.properties.at(1).thickness, 5e-3);
  EXPECT_DOUBLE_EQ(mpa.properties.at(1).nonstructural_mass, 2e-6 * 1e9);  // t/mm² -> kg/m²
  EXPECT_DOUBLE_EQ(mpa.materials.at(1).youngs_modulus, 2.1e11);

  BulkDataOptions stated;
  stated.units = UnitSystem::mm_tonne_second;
  const StructureModel from_deck = read_bulk_data_string(cards, "deck_units.bdf", stated);
  EXPECT_EQ(from_deck.nodes.at(3).position, (Vec3{1.0, 1.0, 0.0}));

  // UNITS = also stands in a file without BEGIN BULK.
  const StructureModel bare = read_bulk_data_string(
      "UNITS = MPA\n" + replace_all(replace_all(cards, "BEGIN BULK\n", ""), "ENDDATA\n", ""),
      "bare.bdf");
  EXPECT_EQ(bare.declared_units, UnitSystem::mm_tonne_second);
  const StructureModel si = read_bulk_data_string("UNITS=SI\n" + cards, "si.bdf");
  EXPECT_EQ(si.declared_units, UnitSystem::si);
  EXPECT_EQ(si.nodes.at(3).position, (Vec3{1000.0, 1000.0, 0.0}));
  EXPECT_DOUBLE_EQ(si.materials.at(1).youngs_modulus, 2.1e5);

  // No declaration: an error at the first card.
  const std::string missing = errors_of(cards);
  EXPECT_EQ(first_line(missing), "model.bdf:2:1: error: the model does not declare its units");
  EXPECT_NE(missing.find("hint: add `UNITS = SI` or `UNITS = MPA`"), std::string::npos) << missing;
  // Two that disagree, and a model that disagrees with the deck.
  EXPECT_EQ(first_line(errors_of("UNITS = SI\n" +
                                 replace_all(cards, "ENDDATA", "DTI,UNITS,1,MGG,N,MM,S\nENDDATA"))),
            "model.bdf:9:13: error: DTI,UNITS MGG N MM S disagrees with UNITS = SI at "
            "model.bdf:1");
  BulkDataOptions si_deck;
  si_deck.units = UnitSystem::si;
  EXPECT_EQ(first_line(errors_of("UNITS = MPA\n" + cards, si_deck)),
            "model.bdf:1:9: error: the model declares mm, tonne, s (MPA) (UNITS = MPA) but the "
            "deck states SI (m, kg, s)");
  EXPECT_EQ(first_line(errors_of("UNITS = CGS\n" + cards)),
            "model.bdf:1:9: error: UNITS = CGS is not supported");
  EXPECT_EQ(first_line(errors_of(replace_all(cards, "ENDDATA", "DTI,UNITS,1,KG,N,MM,S"))),
            "model.bdf:8:13: error: unsupported unit system KG N MM S");
}

TEST(BulkDataSets, ThruRangesWithExcept) {
  std::string grids = "DTI,UNITS,1,KG,N,M,S\n";
  for (int id : {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 20, 21, 22})
    grids += "GRID," + std::to_string(id) + "\n";
  const std::string model_text = grids +
                                 "MAT1,1,1.+9,,.3,1000.\nPSHELL,1,1,.01,1,,1\n"
                                 "CTRIA3,1,1,1,2,3\nCTRIA3,2,1,2,3,4\nCTRIA3,4,1,3,4,5\n"
                                 "SET,1,GRID,LIST\n,1,THRU,10,EXCEPT,2,3,ENDTHRU,7\n"
                                 "SET,2,GRID\n,5,THRU,21,EXCEPT,6,9,22\n"
                                 "SET,3,ELEM,LIST\n,1,THRU,9\n"
                                 "SPC1,1,123,20,THRU,30\n";
  const StructureModel model = read_bulk_data_string(model_text, "sets.bdf");
  // ENDTHRU ends the EXCEPT list, so 7 is listed again (it is in the range anyway).
  EXPECT_EQ(model.sets.at(1).members, (std::vector<int>{1, 4, 5, 6, 7, 8, 9, 10}));
  // An id past the range ends the EXCEPT list; ids missing from a range are skipped.
  EXPECT_EQ(model.sets.at(2).members, (std::vector<int>{5, 7, 8, 10, 20, 21, 22}));
  EXPECT_EQ(model.sets.at(3).members, (std::vector<int>{1, 2, 4}));
  EXPECT_EQ(model.constraints.at(0).nodes, (std::vector<int>{20, 21, 22}));

  EXPECT_EQ(first_line(errors_of(model_text + "SET,4,GRID\n,11,THRU,19\n")),
            "model.bdf:28:2: error: 11 THRU 19 selects no GRID");
  EXPECT_EQ(first_line(errors_of(model_text + "SET,4,GRID\n,30\n")),
            "model.bdf:28:2: error: SET 4 names GRID 30, which is not defined");
  EXPECT_EQ(first_line(errors_of(model_text + "SET,4,ELEM\n,9,THRU,3\n")),
            "model.bdf:28:9: error: SET range 9 THRU 3 goes down");
}

TEST(BulkDataCards, RefusedUnknownAndIgnoredCards) {
  const std::string ok = with_quad("");
  const std::string refused = errors_of(ok + "CBEAM,9,1,1,2\nCBEAM,10,1,2,3\n");
  EXPECT_EQ(first_line(refused),
            "model.bdf:11:1: error: CBEAM is not supported (2 cards, the first here)");
  EXPECT_NE(refused.find("CQUAD4 and CTRIA3 shells only"), std::string::npos) << refused;
  const std::string unknown = errors_of(ok + "CQUDA4,2,1,1,2,3,4\n");
  EXPECT_EQ(first_line(unknown), "model.bdf:11:1: error: unknown card CQUDA4 (1 card)");
  EXPECT_NE(unknown.find("did you mean \"CQUAD4\"?"), std::string::npos) << unknown;

  const StructureModel model =
      read_bulk_data_string(ok + "PARAM,POST,-1\nPARAM,LGDISP,1\nEIGRL,1,,,10\n", "model.bdf");
  const std::string notes = model.notes.format();
  EXPECT_NE(notes.find("model.bdf:11:1: note: PARAM ignored (2 cards)"), std::string::npos)
      << notes;
  EXPECT_NE(notes.find("model.bdf:13:1: note: EIGRL ignored (1 card)"), std::string::npos) << notes;
  EXPECT_EQ(first_line(errors_of(ok + "PARAM,WTMASS,0.00259\n")),
            "model.bdf:11:14: error: PARAM,WTMASS = 0.00259 scales every mass");
}

// MAT1 (MSC Nastran MAT1 remarks): one blank of E, G, NU follows from E = 2(1 + NU)G; all
// three given but inconsistent by more than 1 % is a warning; GRID PS fixes DOFs for good.
TEST(BulkDataCards, Mat1RuleAndPermanentConstraints) {
  const StructureModel model = read_bulk_data_string(
      with_quad("MAT1,2,,80.+9,0.25\nMAT1,3,200.+9,80.+9\nMAT1,4,200.+9,70.+9,0.3\n"
                "GRID,5,,2.,0.,0.,,6\n"),
      "model.bdf");
  EXPECT_DOUBLE_EQ(model.materials.at(2).youngs_modulus, 2.0 * 1.25 * 80e9);
  EXPECT_DOUBLE_EQ(model.materials.at(3).poisson_ratio, 200.0 / 160.0 - 1.0);
  EXPECT_DOUBLE_EQ(model.materials.at(4).shear_modulus, 70e9);  // as given
  const std::string notes = model.notes.format();
  EXPECT_NE(notes.find("model.bdf:13:15: warning: MAT1 E, G and NU do not satisfy"),
            std::string::npos)
      << notes;
  EXPECT_TRUE(model.nodes.at(5).permanent_constraints.has(6));
  EXPECT_FALSE(model.nodes.at(5).permanent_constraints.has(5));
  EXPECT_TRUE(model.nodes.at(1).permanent_constraints.empty());

  EXPECT_EQ(first_line(errors_of(with_quad("MAT1,2,,,0.3\n"))),
            "model.bdf:11:8: error: MAT1 needs E or G");
  EXPECT_EQ(first_line(errors_of(with_quad("MAT1,2,1.+9,3.+8\n"))),
            "model.bdf:11:8: error: MAT1 E and G give NU = E/(2G) − 1 = 0.6667, outside "
            "(-1, 0.5)");
  EXPECT_EQ(first_line(errors_of(with_quad("SPC,1,1,0\n"))),
            "model.bdf:11:9: error: SPC C1 must be a code of DOFs 1-6 (such as 123456), got \"0\"");
  EXPECT_EQ(first_line(errors_of(with_quad("SPC1,1,1223,1\n"))),
            "model.bdf:11:8: error: SPC1 C must be a code of DOFs 1-6 (such as 123456), got "
            "\"1223\"");
}

// One run reports every error of the model, in the order of the file.
TEST(BulkDataErrors, AllErrorsInReadingOrder) {
  const std::string text =
      "DTI,UNITS,1,KG,N,M,S\n"
      "GRID,1,,0.,0.,0.\nGRID,2,,1..,0.,0.\nGRID,1,,0.,1.,0.\n"
      "CTRIA3,1,1,1,2,3\nPSHELL,1,1,0.\nMAT1,1,2.1+11,,0.3,7850.\n";
  try {
    read_bulk_data_string(text, "model.bdf");
    FAIL() << "read";
  } catch (const UserError& error) {
    const std::string all = error.diagnostics().format();
    const auto& items = error.diagnostics().all();
    ASSERT_EQ(items.size(), 4u) << all;
    EXPECT_EQ(items[0].message, "GRID X1 must be a real number, got \"1..\"");
    EXPECT_EQ(items[0].where.line, 3);
    EXPECT_EQ(items[1].message, "duplicate GRID id 1");
    EXPECT_NE(items[1].hint.find("first defined at model.bdf:2"), std::string::npos);
    EXPECT_EQ(items[2].message, "CTRIA3 1 names GRID 3, which is not defined");
    EXPECT_EQ(items[2].where.column, 16);
    EXPECT_EQ(items[3].message, "PSHELL T must be > 0, got 0.");
  }
}

TEST(BulkDataFiles, IncludeRelativeToTheIncludingFile) {
  const fs::path folder = fs::path(testing::TempDir()) / "bulk_include";
  fs::create_directories(folder / "mesh");
  std::ofstream(folder / "main.bdf") << "UNITS = SI\nBEGIN BULK\nINCLUDE 'mesh/plate.bdf'\n"
                                        "MAT1,1,2.1+11,,0.3,7850.\nENDDATA\nGRID,99\n";
  std::ofstream(folder / "mesh" / "plate.bdf")
      << "GRID,1\nGRID,2,,1.\nGRID,3,,1.,1.\nINCLUDE shell.bdf\nCTRIA3,1,1,1,2,3\n";
  std::ofstream(folder / "mesh" / "shell.bdf") << "PSHELL,1,1,.005,1,,1\n";
  const StructureModel model = read_bulk_data((folder / "main.bdf").string());
  EXPECT_EQ(model.nodes.size(), 3u);  // GRID 99 is after ENDDATA
  EXPECT_EQ(model.source_files.size(), 3u);
  EXPECT_EQ(model.where(model.shells[0].where).line, 5);
  EXPECT_NE(model.where(model.shells[0].where).file.find("plate.bdf"), std::string::npos);

  std::ofstream(folder / "mesh" / "shell.bdf") << "PSHELL,1,1,-.005,1,,1\n";
  try {
    read_bulk_data((folder / "main.bdf").string());
    FAIL() << "read";
  } catch (const UserError& error) {
    const std::string text = error.diagnostics().format();
    EXPECT_NE(text.find("shell.bdf:1:12: error: PSHELL T must be > 0, got -.005"),
              std::string::npos)
        << text;
    EXPECT_NE(text.find("    1 | PSHELL,1,1,-.005,1,,1"), std::string::npos) << text;
  }
}

// A file cut anywhere (an interrupted copy, a half-written export) either reads or fails with a
// UserError; nothing else escapes and nothing crashes (run under ASan in CI). Each of the three
// formats of the plate, cut after every character.
TEST(BulkDataFiles, EveryPrefixReadsOrFailsCleanly) {
  for (const char* name : {"plate_fixed.bdf", "plate_free.bdf", "plate_large.bdf"}) {
    const std::string text = read_text(source_dir() / "tests" / "models" / name);
    ASSERT_FALSE(text.empty()) << name;
    int read = 0;
    int refused = 0;
    for (std::size_t length = 0; length <= text.size(); ++length) {
      try {
        read_bulk_data_string(text.substr(0, length), "cut.bdf");
        ++read;
      } catch (const UserError& error) {
        ++refused;
        EXPECT_TRUE(error.diagnostics().has_errors()) << name << " cut at " << length;
      }
    }
    EXPECT_GT(refused, 0) << name;
    EXPECT_GT(read, 0) << name;  // the whole file, at least
  }
}

// Reads a broken model of tests/bad_models by its extension.
std::string formatted_errors(const fs::path& path) {
  try {
    if (path.extension() == ".msh") {
      GmshReadOptions options;
      options.units = UnitSystem::si;
      read_gmsh(path.string(), options);
    } else {
      read_bulk_data(path.string());
    }
  } catch (const UserError& error) {
    return error.diagnostics().format();
  }
  ADD_FAILURE() << path << " read without error";
  return {};
}

// Each tests/bad_models/NN_name.{bdf,msh} must fail with the first output line stored in
// NN_name.expected (the model path written as {model}). QUARRY_UPDATE_BAD_MODELS=1 rewrites
// the .expected files from the current output instead (review the diff).
TEST(BadModels, FirstErrorLineMatchesGolden) {
  const fs::path folder = source_dir() / "tests" / "bad_models";
  const std::vector<fs::path> models = io_testing::files_with_extensions(folder, {".bdf", ".msh"});
  ASSERT_GE(models.size(), 20u) << "expected at least 20 broken models in " << folder;
  const bool update = std::getenv("QUARRY_UPDATE_BAD_MODELS") != nullptr;
  for (const fs::path& model : models) {
    SCOPED_TRACE(model.filename().string());
    const std::string output = formatted_errors(model);
    const std::string actual = first_line(output);
    io_testing::expect_first_line_matches_golden(model, actual, "{model}", update, output);
    // Every error echoes its line and puts a caret under the column.
    if (actual.find(":0:") == std::string::npos) {
      EXPECT_NE(output.find("^"), std::string::npos) << output;
    }
  }
}

}  // namespace
}  // namespace quarry
