// Tests for the deck parser: the bad-deck golden cases in tests/bad_decks (first line of the
// formatted errors), and positive tests that decks parse into the expected values and locations.
#include "io/atomic_file.h"
#include "io/deck.h"
#include "io/io_test_support.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace quarry {
namespace {

namespace fs = std::filesystem;

using io_testing::first_line;
using io_testing::read_text;
using io_testing::replace_all;
using io_testing::source_dir;

// The formatted errors of a deck that must fail; empty (and a test failure) if it parses.
std::string formatted_errors(const std::string& deck_path) {
  try {
    parse_deck(deck_path);
  } catch (const UserError& error) {
    return error.diagnostics().format();
  }
  ADD_FAILURE() << deck_path << " parsed without error";
  return {};
}

// Each tests/bad_decks/NN_name.yaml must fail with the first output line stored in
// NN_name.expected (the deck path written as {deck}). Setting QUARRY_UPDATE_BAD_DECKS=1
// rewrites the .expected files from the current output instead (review the diff).
TEST(BadDecks, FirstErrorLineMatchesGolden) {
  const fs::path folder = source_dir() / "tests" / "bad_decks";
  const std::vector<fs::path> decks = io_testing::files_with_extensions(folder, {".yaml"});
  ASSERT_GE(decks.size(), 15u) << "expected at least 15 bad-deck cases in " << folder;
  const bool update = std::getenv("QUARRY_UPDATE_BAD_DECKS") != nullptr;
  for (const fs::path& deck : decks) {
    SCOPED_TRACE(deck.filename().string());
    io_testing::expect_first_line_matches_golden(deck, first_line(formatted_errors(deck.string())),
                                                 "{deck}", update);
  }
}

// Every error of a deck is reported at once, in file order, each with the offending line
// echoed; no partial spec escapes.
TEST(BadDecks, ReportsAllErrorsInFileOrder) {
  const std::string deck =
      (source_dir() / "tests" / "bad_decks" / "15_multiple_errors.yaml").string();
  try {
    parse_deck(deck);
    FAIL() << "deck parsed";
  } catch (const UserError& error) {
    const auto& items = error.diagnostics().all();
    ASSERT_EQ(items.size(), 4u) << error.diagnostics().format();
    for (std::size_t i = 1; i < items.size(); ++i)
      EXPECT_LT(items[i - 1].where.line, items[i].where.line) << error.diagnostics().format();
    const std::string text = error.diagnostics().format();
    EXPECT_NE(text.find("unknown key \"densty\" in material"), std::string::npos) << text;
    EXPECT_NE(text.find("did you mean \"density\"?"), std::string::npos) << text;
    EXPECT_NE(text.find("unknown contact model \"hertz_mindln\""), std::string::npos) << text;
    EXPECT_NE(text.find("restitution must be in (0, 1], got 1.5"), std::string::npos) << text;
    EXPECT_NE(text.find("unknown material \"stel\""), std::string::npos) << text;
  }
}

TEST(Deck, MissingFileIsAUserError) {
  const std::string path = (fs::path(testing::TempDir()) / "no_such_deck.yaml").string();
  try {
    parse_deck(path);
    FAIL() << "no error";
  } catch (const UserError& error) {
    EXPECT_EQ(first_line(error.diagnostics().format()),
              path + ": error: cannot open the deck file");
  }
}

// The minimal deck: only required keys; everything else takes the documented defaults.
TEST(Deck, MinimalDeckTakesDefaults) {
  const std::string path = (source_dir() / "tests" / "decks" / "minimal.yaml").string();
  const SimulationSpec spec = parse_deck(path);
  EXPECT_EQ(spec.deck_path, path);
  EXPECT_DOUBLE_EQ(spec.simulation.end_time.value, 0.5);
  EXPECT_EQ(spec.simulation.end_time.where.file, path);
  EXPECT_EQ(spec.simulation.end_time.where.line, 4);
  EXPECT_EQ(spec.simulation.end_time.where.column, 13);
  EXPECT_FALSE(spec.simulation.fixed_time_step.has_value());
  EXPECT_DOUBLE_EQ(spec.simulation.rayleigh_fraction.value, 0.2);
  EXPECT_EQ(spec.simulation.gravity.value, (Vec3{0, 0, -9.81}));
  EXPECT_EQ(spec.simulation.domain.value.lo, (Vec3{-0.1, -0.1, 0}));
  EXPECT_EQ(spec.simulation.domain.value.hi, (Vec3{0.1, 0.1, 0.3}));
  EXPECT_EQ(spec.simulation.integrator.value, Integrator::velocity_verlet);
  EXPECT_LT(spec.simulation.skin.value, 0.0);  // automatic
  ASSERT_EQ(spec.materials.size(), 1u);
  EXPECT_EQ(spec.materials[0].name.value, "glass");
  ASSERT_EQ(spec.interactions.size(), 1u);
  EXPECT_EQ(spec.interactions[0].normal_model.value, NormalModel::hertz_mindlin);
  ASSERT_EQ(spec.particle_types.size(), 1u);
  EXPECT_DOUBLE_EQ(spec.particle_types[0].size.radius.value, 0.005);
  ASSERT_EQ(spec.surfaces.size(), 1u);
  EXPECT_EQ(spec.surfaces[0].kind.value, SurfaceKind::plane);
  EXPECT_EQ(spec.surfaces[0].motion.kind.value, MotionKind::none);
  ASSERT_EQ(spec.factories.size(), 1u);
  ASSERT_TRUE(spec.factories[0].target_count.has_value());
  EXPECT_EQ(spec.factories[0].target_count->value, 20);
  EXPECT_FALSE(spec.factories[0].mass_rate.has_value());
  EXPECT_TRUE(spec.monitors.empty());
  EXPECT_EQ(spec.output.directory.value, "out");
  EXPECT_TRUE(spec.output.plots.value);
}

// `skin: auto` asks for the skin chosen at every list build, a number is a fixed skin (any other
// word: tests/bad_decks/70_skin_word.yaml).
TEST(Deck, SkinAutoIsTheChosenSkinAndANumberAFixedOne) {
  const auto deck = [](const std::string& skin) {
    return "simulation:\n  end_time: 1\n  domain: {min: [0, 0, 0], max: [1, 1, 1]}\n  skin: " + skin +
           "\nmaterials:\n  - {name: m, density: 1000, youngs_modulus: 1.0e6, poisson_ratio: 0}\n"
           "interactions:\n  - {materials: [m, m]}\n"
           "particle_types:\n  - {name: p, material: m, size: {distribution: fixed, radius: 0.01}}\n";
  };
  const SimulationSpec automatic = parse_deck_string(deck("auto"), "auto.yaml");
  EXPECT_LT(automatic.simulation.skin.value, 0.0);
  EXPECT_EQ(automatic.simulation.skin.where.line, 4);
  const SimulationSpec fixed = parse_deck_string(deck("0.001"), "fixed.yaml");
  EXPECT_DOUBLE_EQ(fixed.simulation.skin.value, 0.001);
}

// A deck using every key: each value lands in its SimulationSpec field with its location.
const char* const kFullDeck = R"(simulation:
  end_time: 2.0
  time_step: 1.0e-5
  impact_speed: 3.0
  gravity: [0, -9.81, 0]
  domain: {min: [-1, -2, -3], max: [1, 2, 3]}
  integrator: symplectic_euler
  threads: 2
  skin: 0.0002
  sort_interval: 500
  max_overlap_fraction: 0.05
  seed: 7
materials:
  - {name: ore, density: 2500, youngs_modulus: 5.0e7, poisson_ratio: 0.25}
  - {name: steel, density: 7800, youngs_modulus: 2.0e11, poisson_ratio: 0.3}
interactions:
  - materials: [ore, ore]
    restitution: 0.4
    static_friction: 0.6
    rolling_friction: 0.05
    rolling_model: epsd
    cohesion: 5000
    model: linear
    stiffness: 1.0e4
    tangential_stiffness_ratio: 0.3
    clip_attraction: true
  - {materials: [steel, ore], restitution: 0.5, cohesion_model: jkr, surface_energy: 0.05}
particle_types:
  - {name: fixed, material: ore, size: {distribution: fixed, radius: 0.01}}
  - {name: flat, material: ore, size: {distribution: uniform, min_radius: 0.01, max_radius: 0.02}}
  - {name: bell, material: ore, size: {distribution: normal, mean_radius: 0.01, std_radius: 0.001}}
  - {name: skew, material: ore, size: {distribution: log_normal, median_radius: 0.01, log_std: 0.2, max_radius: 0.02}}
  - {name: sieve, material: ore, size: {distribution: discrete, radii: [0.01, 0.02], mass_fractions: [0.25, 0.75]}}
surfaces:
  - name: bed
    type: stl
    file: parts/bed.stl
    scale: 0.001
    offset: [0, 0, 0.5]
    material: steel
    motion: {type: rotation, axis_point: [0, 0, 1], axis_direction: [0, 1, 0], angular_velocity: -1.5, start_time: 0.1, stop_time: 1}
    export: true
  - {name: floor, type: plane, point: [0, 0, 0], normal: [0, 0, 2], size: 3, material: steel,
     motion: {type: vibration, amplitude: [0, 0, 0.001], frequency: 50}}
  - {name: belt, type: box, min: [0, 0, 0], max: [1, 0.5, 0.1], material: steel, conveyor_velocity: [1, 0, 0],
     motion: {type: translation, velocity: [0.1, 0, 0]}}
  - {name: drum, type: cylinder, base: [0, 0, 0], axis: [1, 0, 0], radius: 0.5, length: 1, capped: true, resolution: 48, material: steel}
factories:
  - name: left
    particle_type: bell
    region: {type: cylinder, base: [0, 0, 1], axis: [0, 0, 1], radius: 0.2, length: 0.3}
    mass: 12.5
    mass_rate: 50
    start_time: 0.1
    stop_time: 1.0
    velocity: [0, 0, -1]
    max_attempts: 20
  - {name: right, particle_type: fixed, region: {type: box, min: [0, 0, 0], max: [1, 1, 1]}, count: 1000}
monitors:
  - {name: in_bed, region: {type: box, min: [0, 0, 0], max: [1, 1, 1]}}
  - {name: everything}
output:
  directory: results
  interval: 0.05
  monitor_interval: 0.01
  checkpoint_interval: 0.5
  plots: false
  progress_interval: 5
)";

class FullDeck : public testing::Test {
 protected:
  void SetUp() override {
    // One folder per test: CTest runs the cases in parallel processes.
    folder_ = fs::path(testing::TempDir()) /
              ("quarry_full_deck_" + std::string(testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::create_directories(folder_ / "parts");
    std::ofstream(folder_ / "parts" / "bed.stl") << "solid bed\nendsolid bed\n";
    deck_path_ = (folder_ / "full.yaml").string();
    std::ofstream(deck_path_) << kFullDeck;
  }
  void TearDown() override { fs::remove_all(folder_); }
  fs::path folder_;
  std::string deck_path_;
};

TEST_F(FullDeck, SimulationAndOutput) {
  const SimulationSpec spec = parse_deck(deck_path_);
  const SimulationSettings& simulation = spec.simulation;
  EXPECT_DOUBLE_EQ(simulation.end_time.value, 2.0);
  ASSERT_TRUE(simulation.fixed_time_step.has_value());
  EXPECT_DOUBLE_EQ(simulation.fixed_time_step->value, 1.0e-5);
  EXPECT_EQ(simulation.fixed_time_step->where.line, 3);
  EXPECT_EQ(simulation.fixed_time_step->where.column, 14);
  ASSERT_TRUE(simulation.impact_speed.has_value());
  EXPECT_DOUBLE_EQ(simulation.impact_speed->value, 3.0);
  EXPECT_EQ(simulation.gravity.value, (Vec3{0, -9.81, 0}));
  EXPECT_EQ(simulation.gravity.where.line, 5);
  EXPECT_EQ(simulation.domain.value.lo, (Vec3{-1, -2, -3}));
  EXPECT_EQ(simulation.domain.value.hi, (Vec3{1, 2, 3}));
  EXPECT_EQ(simulation.domain.where.line, 6);
  EXPECT_EQ(simulation.domain.where.column, 11);  // the flow map's "{"
  EXPECT_EQ(simulation.integrator.value, Integrator::symplectic_euler);
  EXPECT_EQ(simulation.threads.value, 2);
  EXPECT_DOUBLE_EQ(simulation.skin.value, 0.0002);
  EXPECT_EQ(simulation.sort_interval.value, 500);
  EXPECT_DOUBLE_EQ(simulation.max_overlap_fraction.value, 0.05);
  EXPECT_EQ(simulation.seed, 7u);
  EXPECT_EQ(spec.output.directory.value, "results");
  EXPECT_DOUBLE_EQ(spec.output.interval.value, 0.05);
  EXPECT_DOUBLE_EQ(spec.output.monitor_interval.value, 0.01);
  EXPECT_DOUBLE_EQ(spec.output.checkpoint_interval.value, 0.5);
  EXPECT_FALSE(spec.output.plots.value);
  EXPECT_DOUBLE_EQ(spec.output.progress_interval.value, 5.0);
}

TEST_F(FullDeck, MaterialsAndInteractions) {
  const SimulationSpec spec = parse_deck(deck_path_);
  ASSERT_EQ(spec.materials.size(), 2u);
  const MaterialSpec& steel = spec.materials[1];
  EXPECT_EQ(steel.name.value, "steel");
  EXPECT_DOUBLE_EQ(steel.density.value, 7800);
  EXPECT_DOUBLE_EQ(steel.youngs_modulus.value, 2.0e11);
  EXPECT_DOUBLE_EQ(steel.poisson_ratio.value, 0.3);
  EXPECT_EQ(steel.youngs_modulus.where.line, 15);
  EXPECT_EQ(steel.youngs_modulus.where.column, 50);

  ASSERT_EQ(spec.interactions.size(), 2u);
  const InteractionSpec& ore_ore = spec.interactions[0];
  EXPECT_EQ(ore_ore.material_a.value, "ore");
  EXPECT_EQ(ore_ore.material_b.value, "ore");
  EXPECT_EQ(ore_ore.material_b.where.line, 17);
  EXPECT_EQ(ore_ore.material_b.where.column, 22);
  EXPECT_DOUBLE_EQ(ore_ore.restitution.value, 0.4);
  EXPECT_DOUBLE_EQ(ore_ore.static_friction.value, 0.6);
  EXPECT_DOUBLE_EQ(ore_ore.rolling_friction.value, 0.05);
  EXPECT_EQ(ore_ore.rolling_model.value, RollingModel::epsd);
  EXPECT_DOUBLE_EQ(ore_ore.cohesion_energy_density.value, 5000);
  EXPECT_EQ(ore_ore.normal_model.value, NormalModel::linear);
  EXPECT_EQ(ore_ore.normal_model.where.line, 23);
  EXPECT_DOUBLE_EQ(ore_ore.linear_stiffness.value, 1.0e4);
  EXPECT_DOUBLE_EQ(ore_ore.linear_tangential_ratio.value, 0.3);
  EXPECT_TRUE(ore_ore.clip_attraction.value);
  // Written as [steel, ore]: covers the ore–steel contacts (order-independent); the rest
  // keeps the defaults of InteractionSpec, but for its JKR cohesion.
  const InteractionSpec& steel_ore = spec.interactions[1];
  EXPECT_EQ(steel_ore.material_a.value, "steel");
  EXPECT_DOUBLE_EQ(steel_ore.restitution.value, 0.5);
  EXPECT_DOUBLE_EQ(steel_ore.static_friction.value, 0.5);
  EXPECT_EQ(steel_ore.normal_model.value, NormalModel::hertz_mindlin);
  EXPECT_EQ(steel_ore.rolling_model.value, RollingModel::constant_torque);
  EXPECT_EQ(ore_ore.cohesion_model.value, CohesionModel::sjkr);
  EXPECT_EQ(steel_ore.cohesion_model.value, CohesionModel::jkr);
  EXPECT_DOUBLE_EQ(steel_ore.surface_energy.value, 0.05);
  EXPECT_DOUBLE_EQ(steel_ore.cohesion_energy_density.value, 0.0);
}

TEST_F(FullDeck, SizeDistributions) {
  const SimulationSpec spec = parse_deck(deck_path_);
  ASSERT_EQ(spec.particle_types.size(), 5u);
  const SizeDistributionSpec& fixed = spec.particle_types[0].size;
  EXPECT_EQ(fixed.kind.value, SizeDistributionKind::fixed);
  EXPECT_DOUBLE_EQ(fixed.radius.value, 0.01);
  const SizeDistributionSpec& flat = spec.particle_types[1].size;
  EXPECT_EQ(flat.kind.value, SizeDistributionKind::uniform);
  EXPECT_DOUBLE_EQ(flat.min_radius.value, 0.01);
  EXPECT_DOUBLE_EQ(flat.max_radius.value, 0.02);
  // Normal without bounds: clipped at mean ± 3 std (the deck reference, docs/deck.md).
  const SizeDistributionSpec& bell = spec.particle_types[2].size;
  EXPECT_EQ(bell.kind.value, SizeDistributionKind::normal);
  EXPECT_DOUBLE_EQ(bell.mean_radius.value, 0.01);
  EXPECT_DOUBLE_EQ(bell.std_radius.value, 0.001);
  EXPECT_NEAR(bell.min_radius.value, 0.007, 1e-15);
  EXPECT_NEAR(bell.max_radius.value, 0.013, 1e-15);
  // Log-normal: the median of exp(N(μ, σ²)) is exp(μ), so μ = ln(median / 1 m)
  // (Crow & Shimizu, "Lognormal Distributions", 1988); default min = median·exp(−3σ).
  const SizeDistributionSpec& skew = spec.particle_types[3].size;
  EXPECT_EQ(skew.kind.value, SizeDistributionKind::log_normal);
  EXPECT_NEAR(skew.log_mean.value, std::log(0.01), 1e-12);
  EXPECT_DOUBLE_EQ(skew.log_std.value, 0.2);
  EXPECT_NEAR(skew.min_radius.value, 0.01 * std::exp(-0.6), 1e-15);
  EXPECT_DOUBLE_EQ(skew.max_radius.value, 0.02);
  const SizeDistributionSpec& sieve = spec.particle_types[4].size;
  EXPECT_EQ(sieve.kind.value, SizeDistributionKind::discrete);
  ASSERT_EQ(sieve.discrete_radii.size(), 2u);
  ASSERT_EQ(sieve.discrete_mass_fractions.size(), 2u);
  EXPECT_DOUBLE_EQ(sieve.discrete_radii[1].value, 0.02);
  EXPECT_DOUBLE_EQ(sieve.discrete_mass_fractions[0].value, 0.25);
  EXPECT_EQ(sieve.discrete_mass_fractions[0].where.line, 33);
  EXPECT_EQ(sieve.discrete_mass_fractions[0].where.column, 103);
}

TEST_F(FullDeck, Surfaces) {
  const SimulationSpec spec = parse_deck(deck_path_);
  ASSERT_EQ(spec.surfaces.size(), 4u);
  const SurfaceSpec& bed = spec.surfaces[0];
  EXPECT_EQ(bed.kind.value, SurfaceKind::stl);
  // Resolved against the deck's folder, not the current directory, and stored absolute.
  EXPECT_TRUE(fs::path(bed.file.value).is_absolute());
  EXPECT_TRUE(fs::equivalent(bed.file.value, folder_ / "parts" / "bed.stl"));
  EXPECT_EQ(bed.file.where.line, 37);
  EXPECT_EQ(bed.file.where.column, 11);
  EXPECT_DOUBLE_EQ(bed.scale.value, 0.001);
  EXPECT_EQ(bed.offset.value, (Vec3{0, 0, 0.5}));
  EXPECT_EQ(bed.material.value, "steel");
  EXPECT_TRUE(bed.export_loads.value);
  EXPECT_EQ(bed.motion.kind.value, MotionKind::rotation);
  EXPECT_EQ(bed.motion.axis_point.value, (Vec3{0, 0, 1}));
  EXPECT_EQ(bed.motion.axis_direction.value, (Vec3{0, 1, 0}));
  EXPECT_DOUBLE_EQ(bed.motion.angular_velocity.value, -1.5);
  EXPECT_DOUBLE_EQ(bed.motion.start_time.value, 0.1);
  EXPECT_DOUBLE_EQ(bed.motion.stop_time.value, 1.0);

  const SurfaceSpec& floor = spec.surfaces[1];
  EXPECT_EQ(floor.kind.value, SurfaceKind::plane);
  EXPECT_EQ(floor.normal.value, (Vec3{0, 0, 2}));
  EXPECT_DOUBLE_EQ(floor.size.value, 3.0);
  EXPECT_EQ(floor.motion.kind.value, MotionKind::vibration);
  EXPECT_EQ(floor.motion.amplitude.value, (Vec3{0, 0, 0.001}));
  EXPECT_DOUBLE_EQ(floor.motion.frequency.value, 50.0);
  EXPECT_GT(floor.motion.stop_time.value, 1e299);  // default: never stops

  const SurfaceSpec& belt = spec.surfaces[2];
  EXPECT_EQ(belt.kind.value, SurfaceKind::box);
  EXPECT_EQ(belt.max.value, (Vec3{1, 0.5, 0.1}));
  EXPECT_EQ(belt.conveyor_velocity.value, (Vec3{1, 0, 0}));
  EXPECT_EQ(belt.motion.velocity.value, (Vec3{0.1, 0, 0}));
  EXPECT_FALSE(belt.export_loads.value);

  const SurfaceSpec& drum = spec.surfaces[3];
  EXPECT_EQ(drum.kind.value, SurfaceKind::cylinder);
  EXPECT_EQ(drum.axis.value, (Vec3{1, 0, 0}));
  EXPECT_DOUBLE_EQ(drum.radius.value, 0.5);
  EXPECT_DOUBLE_EQ(drum.length.value, 1.0);
  EXPECT_TRUE(drum.capped.value);
  EXPECT_EQ(drum.resolution.value, 48);
}

TEST_F(FullDeck, FactoriesAndMonitors) {
  const SimulationSpec spec = parse_deck(deck_path_);
  ASSERT_EQ(spec.factories.size(), 2u);
  const FactorySpec& left = spec.factories[0];
  EXPECT_EQ(left.particle_type.value, "bell");
  EXPECT_EQ(left.region.kind.value, RegionKind::cylinder);
  EXPECT_EQ(left.region.base.value, (Vec3{0, 0, 1}));
  EXPECT_DOUBLE_EQ(left.region.radius.value, 0.2);
  EXPECT_DOUBLE_EQ(left.region.length.value, 0.3);
  EXPECT_FALSE(left.target_count.has_value());
  ASSERT_TRUE(left.target_mass.has_value());
  EXPECT_DOUBLE_EQ(left.target_mass->value, 12.5);
  EXPECT_EQ(left.target_mass->where.line, 52);
  EXPECT_EQ(left.target_mass->where.column, 11);
  ASSERT_TRUE(left.mass_rate.has_value());
  EXPECT_DOUBLE_EQ(left.mass_rate->value, 50.0);
  EXPECT_DOUBLE_EQ(left.start_time.value, 0.1);
  EXPECT_DOUBLE_EQ(left.stop_time.value, 1.0);
  EXPECT_EQ(left.initial_velocity.value, (Vec3{0, 0, -1}));
  EXPECT_EQ(left.max_attempts.value, 20);
  const FactorySpec& right = spec.factories[1];
  EXPECT_EQ(right.region.kind.value, RegionKind::box);
  ASSERT_TRUE(right.target_count.has_value());
  EXPECT_EQ(right.target_count->value, 1000);
  EXPECT_FALSE(right.mass_rate.has_value());

  ASSERT_EQ(spec.monitors.size(), 2u);
  ASSERT_TRUE(spec.monitors[0].region.has_value());
  EXPECT_EQ(spec.monitors[0].region->max.value, (Vec3{1, 1, 1}));
  EXPECT_FALSE(spec.monitors[1].region.has_value());
}

// parse_deck_string: locations name the given display name; STL paths start at the current
// directory.
TEST(Deck, StringDeckUsesDisplayNameAndCurrentDirectory) {
  const std::string deck =
      "simulation: {end_time: 1, domain: {min: [0, 0, 0], max: [1, 1, 1]}}\n"
      "materials: [{name: m, density: 1000, youngs_modulus: 1.0e6, poisson_ratio: 0.3}]\n"
      "surfaces: [{name: s, type: stl, file: surely_missing.stl, material: m}]\n";
  try {
    parse_deck_string(deck, "inline.yaml");
    FAIL() << "missing STL accepted";
  } catch (const UserError& error) {
    ASSERT_EQ(error.diagnostics().all().size(), 1u) << error.diagnostics().format();
    const Diagnostic& item = error.diagnostics().all()[0];
    EXPECT_EQ(item.where.file, "inline.yaml");
    EXPECT_EQ(item.where.line, 3);
    EXPECT_EQ(item.message, "STL file \"surely_missing.stl\" not found");
    EXPECT_NE(item.hint.find((fs::current_path() / "surely_missing.stl").string()),
              std::string::npos)
        << item.hint;
  }
}

// DeckParseOptions: relative STL paths start at base_directory, and with require_files false
// a missing file is accepted (the caller supplies the mesh) and still stored absolute.
TEST(Deck, StringDeckOptionsResolveAndWaiveFiles) {
  const fs::path folder = fs::path(testing::TempDir()) / "quarry_deck_options";
  fs::create_directories(folder / "parts");
  std::ofstream(folder / "parts" / "bed.stl") << "solid bed\nendsolid bed\n";
  const std::string head =
      "simulation: {end_time: 1, domain: {min: [0, 0, 0], max: [1, 1, 1]}}\n"
      "materials: [{name: m, density: 1000, youngs_modulus: 1.0e6, poisson_ratio: 0.3}]\n";
  DeckParseOptions options;
  options.base_directory = folder.string();
  const SimulationSpec found = parse_deck_string(
      head + "surfaces: [{name: s, type: stl, file: parts/bed.stl, material: m}]\n", "inline.yaml",
      options);
  ASSERT_EQ(found.surfaces.size(), 1u);
  EXPECT_TRUE(fs::path(found.surfaces[0].file.value).is_absolute());
  EXPECT_TRUE(fs::equivalent(found.surfaces[0].file.value, folder / "parts" / "bed.stl"));

  const std::string missing_deck =
      head + "surfaces: [{name: s, type: stl, file: parts/gone.stl, material: m}]\n";
  EXPECT_THROW(parse_deck_string(missing_deck, "inline.yaml", options), UserError);
  options.require_files = false;
  const SimulationSpec waived = parse_deck_string(missing_deck, "inline.yaml", options);
  ASSERT_EQ(waived.surfaces.size(), 1u);
  EXPECT_EQ(waived.surfaces[0].file.value, (folder / "parts" / "gone.stl").string());
  fs::remove_all(folder);
}

// The head of the small inline decks below: one material that every surface may use.
const char* const kSurfaceDeckHead =
    "simulation: {end_time: 1, domain: {min: [0, 0, 0], max: [1, 1, 1]}}\n"
    "materials: [{name: m, density: 1000, youngs_modulus: 1.0e6, poisson_ratio: 0.3}]\n";

// The errors of a deck held in memory that must fail; empty (and a test failure) if it parses.
std::vector<Diagnostic> string_deck_errors(const std::string& deck) {
  try {
    parse_deck_string(deck, "deck.yaml");
  } catch (const UserError& error) {
    return error.diagnostics().all();
  }
  ADD_FAILURE() << "parsed without error:\n" << deck;
  return {};
}

// coupled: on any surface type, false by default; with a motion it is an error at the key.
TEST(Deck, CoupledSurfaces) {
  const SimulationSpec spec = parse_deck_string(
      std::string(kSurfaceDeckHead) +
          "surfaces:\n"
          "  - {name: lid, type: plane, point: [0, 0, 1], normal: [0, 0, -1], material: m,\n"
          "     coupled: true}\n"
          "  - {name: wall, type: box, min: [0, 0, 0], max: [1, 1, 1], material: m,\n"
          "     coupled: false, motion: {type: translation, velocity: [1, 0, 0]}}\n"
          "  - {name: drum, type: cylinder, base: [0, 0, 0], axis: [0, 0, 1], radius: 1,\n"
          "     length: 1, material: m}\n",
      "deck.yaml");
  ASSERT_EQ(spec.surfaces.size(), 3u);
  EXPECT_TRUE(spec.surfaces[0].coupled.value);
  EXPECT_EQ(spec.surfaces[0].coupled.where.line, 5);
  EXPECT_EQ(spec.surfaces[0].coupled.where.column, 15);
  EXPECT_FALSE(spec.surfaces[1].coupled.value);
  EXPECT_EQ(spec.surfaces[1].motion.kind.value, MotionKind::translation);
  EXPECT_FALSE(spec.surfaces[2].coupled.value);

  const std::vector<Diagnostic> errors = string_deck_errors(
      std::string(kSurfaceDeckHead) +
      "surfaces:\n"
      "  - {name: lid, type: plane, point: [0, 0, 1], normal: [0, 0, -1], material: m,\n"
      "     motion: {type: rotation, axis_point: [0, 0, 0], axis_direction: [0, 0, 1],\n"
      "              angular_velocity: 1}, coupled: true}\n"
      "  - {name: gate, type: plane, point: [0, 0, 1], normal: [0, 0, -1], material: m,\n"
      "     coupled: maybe}\n");
  ASSERT_EQ(errors.size(), 2u);
  EXPECT_EQ(errors[0].message, "a coupled surface cannot also have a motion");
  EXPECT_EQ(errors[0].where.line, 6);
  EXPECT_EQ(errors[0].where.column, 37);  // the key, not its value
  EXPECT_NE(errors[0].hint.find("one driver"), std::string::npos) << errors[0].hint;
  EXPECT_EQ(errors[1].message, "expected true or false for \"coupled\", got \"maybe\"");
  EXPECT_EQ(errors[1].where.line, 8);
}

// type: mesh: vertices (m) and 0-based triangles and quads land in SurfaceSpec as written.
TEST(Deck, MeshSurfaces) {
  const SimulationSpec spec = parse_deck_string(
      std::string(kSurfaceDeckHead) +
          "surfaces:\n"
          "  - name: chute\n"
          "    type: mesh\n"
          "    vertices: [[0, 0, 0], [1, 0, 0], [1, 1, 0.5], [0, 1, 0.5], [0.5, 2, 1]]\n"
          "    triangles:\n"
          "      - [2, 3, 4]\n"
          "    quads: [[0, 1, 2, 3]]\n"
          "    material: m\n"
          "  - {name: plate, type: mesh, vertices: [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]],\n"
          "     quads: [[0, 1, 2, 3]], triangles: [], material: m, coupled: true}\n",
      "deck.yaml");
  ASSERT_EQ(spec.surfaces.size(), 2u);
  const SurfaceSpec& chute = spec.surfaces[0];
  EXPECT_EQ(chute.kind.value, SurfaceKind::mesh);
  ASSERT_EQ(chute.mesh_vertices.size(), 5u);
  EXPECT_EQ(chute.mesh_vertices[2], (Vec3{1, 1, 0.5}));
  EXPECT_EQ(chute.mesh_vertices[4], (Vec3{0.5, 2, 1}));
  ASSERT_EQ(chute.mesh_triangles.size(), 1u);
  EXPECT_EQ(chute.mesh_triangles[0], (std::array<std::uint32_t, 3>{2, 3, 4}));
  ASSERT_EQ(chute.mesh_quads.size(), 1u);
  EXPECT_EQ(chute.mesh_quads[0], (std::array<std::uint32_t, 4>{0, 1, 2, 3}));
  EXPECT_EQ(chute.mesh_where.line, 6);
  EXPECT_EQ(chute.mesh_where.column, 15);
  const SurfaceSpec& plate = spec.surfaces[1];
  EXPECT_TRUE(plate.mesh_triangles.empty());
  EXPECT_EQ(plate.mesh_quads.size(), 1u);
  EXPECT_TRUE(plate.coupled.value);
}

// Every bad entry of a mesh is reported at once, each at the offending vertex, index or
// element, in file order.
TEST(Deck, MeshErrorsPointAtTheEntry) {
  const std::vector<Diagnostic> errors = string_deck_errors(
      std::string(kSurfaceDeckHead) +
      "surfaces:\n"
      "  - name: bad\n"
      "    type: mesh\n"
      "    vertices: [[0, 0, 0], [1, 0, 0], [1, 1], [0, 1, x]]\n"
      "    triangles:\n"
      "      - [0, 1, 4]\n"
      "      - [0, 2, 0]\n"
      "      - [0, 1]\n"
      "      - [-1, 1.5, 2]\n"
      "    quads: [[0, 1, 2, 1]]\n"
      "    radius: 1\n"
      "    material: m\n");
  ASSERT_EQ(errors.size(), 9u);
  const auto expect_error = [&](std::size_t index, int line, int column,
                                const std::string& message) {
    SCOPED_TRACE(index);
    EXPECT_EQ(errors[index].where.line, line);
    EXPECT_EQ(errors[index].where.column, column);
    EXPECT_EQ(errors[index].message, message);
  };
  expect_error(0, 6, 38, "expected a list of 3 numbers for \"vertices[2]\", got a list of 2");
  expect_error(1, 6, 53, "expected a number for \"vertices[3][2]\", got \"x\"");
  expect_error(2, 8, 16, "triangles[0][2] = 4 is out of range: the mesh has 4 vertices");
  EXPECT_EQ(errors[2].hint, "indices are 0-based, from 0 to 3");
  expect_error(3, 9, 9, "degenerate triangle \"triangles[1]\": vertex 0 appears twice");
  expect_error(4, 10, 9,
               "expected a list of 3 vertex indices for \"triangles[2]\", got a list of 2");
  expect_error(5, 11, 10, "triangles[3][0] = -1 is out of range: the mesh has 4 vertices");
  expect_error(6, 11, 14, "expected an integer for \"triangles[3][1]\", got \"1.5\"");
  expect_error(7, 12, 13, "degenerate quad \"quads[0]\": vertex 1 appears twice");
  expect_error(8, 13, 5, "key \"radius\" does not apply to surface type \"mesh\"");
}

// A mesh needs its vertices and at least one element; its keys belong to type: mesh only.
TEST(Deck, MeshNeedsVerticesAndElements) {
  const std::string head = std::string(kSurfaceDeckHead) + "surfaces:\n";
  struct Case {
    std::string surface;
    std::string first_message;
    int line = 4;  // of the error
  };
  const std::vector<Case> cases = {
      {"  - {name: s, type: mesh, triangles: [[0, 1, 2]], material: m}\n",
       "missing required key \"vertices\" in surface"},
      {"  - {name: s, type: mesh, vertices: [[0, 0, 0], [1, 0, 0], [0, 1, 0]], material: m}\n",
       "missing required key \"triangles\" in surface"},
      {"  - {name: s, type: mesh, vertices: [[0, 0, 0], [1, 0, 0], [0, 1, 0]], triangles: [],\n"
       "     quads: [], material: m}\n",
       "a mesh surface needs at least one triangle or quad"},
      {"  - {name: s, type: mesh, vertices: [], triangles: [[0, 1, 2]], material: m}\n",
       "expected a non-empty list of points for \"vertices\", got a list of 0"},
      {"  - {name: s, type: mesh, vertices: [[0, 0, 0], [1, 0, 0], [0, 1, 0]], triangles: 3,\n"
       "     material: m}\n",
       "expected a list of triangles for \"triangles\", got \"3\""},
      {"  - {name: s, type: plane, point: [0, 0, 0], normal: [0, 0, 1], material: m,\n"
       "     quads: [[0, 1, 2, 3]]}\n",
       "key \"quads\" does not apply to surface type \"plane\"", 5},
  };
  for (const Case& item : cases) {
    SCOPED_TRACE(item.surface);
    const std::vector<Diagnostic> errors = string_deck_errors(head + item.surface);
    ASSERT_EQ(errors.size(), 1u);
    EXPECT_EQ(errors[0].message, item.first_message);
    EXPECT_EQ(errors[0].where.line, item.line);
  }
}

// The error the style guide quotes, with its location on the offending value.
TEST(Deck, UnknownEnumPointsAtValueWithSuggestion) {
  const std::string deck =
      "simulation: {end_time: 1, domain: {min: [0, 0, 0], max: [1, 1, 1]}}\n"
      "materials: [{name: m, density: 1000, youngs_modulus: 1.0e6, poisson_ratio: 0.3}]\n"
      "interactions:\n"
      "  - materials: [m, m]\n"
      "    model: hertz_mindln\n";
  try {
    parse_deck_string(deck, "deck.yaml");
    FAIL() << "typo accepted";
  } catch (const UserError& error) {
    ASSERT_EQ(error.diagnostics().all().size(), 1u) << error.diagnostics().format();
    const Diagnostic& item = error.diagnostics().all()[0];
    EXPECT_EQ(first_line(error.diagnostics().format()),
              "deck.yaml:5:12: error: unknown contact model \"hertz_mindln\"");
    EXPECT_EQ(item.hint, "did you mean \"hertz_mindlin\"?");
  }
}

// Decks with the wrong shape anywhere must give a UserError pointing into the deck — never
// another exception type or a crash (the sanitizer build runs this too).
TEST(Deck, MalformedShapesAreUserErrors) {
  const std::string valid_head =
      "simulation: {end_time: 1, domain: {min: [0, 0, 0], max: [1, 1, 1]}}\n"
      "materials: [{name: m, density: 1000, youngs_modulus: 1.0e6, poisson_ratio: 0.3}]\n";
  const std::vector<std::string> tails = {
      "interactions: [{materials: m}]\n",
      "interactions: [{materials: [m, [m]]}]\n",
      "interactions: [[m, m]]\n",
      "interactions:\n  -\n",
      "particle_types: [{name: p, material: m, size: 3}]\n",
      "particle_types: [{name: p, material: m, size: {radius: 0.1}}]\n",
      "particle_types: [{name: p, material: m, size: {distribution: discrete, radii: 1, "
      "mass_fractions: {a: 1}}}]\n",
      "particle_types: [{name: p, material: m, size: {distribution: [fixed]}}]\n",
      "surfaces: [{name: s, type: [stl], material: m}]\n",
      "surfaces: [{name: s, type: plane, point: [a, b, c], normal: [0, 0, 1], material: m, "
      "motion: 4}]\n",
      "surfaces: [{name: s, material: m, motion: {type: rotation}}]\n",
      "factories: [{name: f, particle_type: p, region: 5, count: 1.5}]\n",
      "factories: [{name: f, particle_type: p, region: {min: [0, 0, 0]}}]\n",
      "monitors: [{name: m, region: {type: cylinder}}]\n",
      "output: [1, 2]\n",
      "output: {interval: .inf, plots: maybe}\n",
      "simulation2: &anchor {a: 1}\nother: *anchor\n",
      "? [complex, key]\n: 1\n",
  };
  for (const std::string& tail : tails) {
    SCOPED_TRACE(tail);
    try {
      parse_deck_string(valid_head + tail, "shape.yaml");
      ADD_FAILURE() << "accepted";
    } catch (const UserError& error) {
      ASSERT_FALSE(error.diagnostics().all().empty());
      for (const Diagnostic& item : error.diagnostics().all()) {
        EXPECT_EQ(item.where.file, "shape.yaml");
        EXPECT_GE(item.where.line, 1) << item.message;
      }
    }
  }
  for (const std::string& whole : {std::string("just a scalar\n"), std::string("- [1, 2]\n")}) {
    EXPECT_THROW(parse_deck_string(whole, "shape.yaml"), UserError) << whole;
  }
}

}  // namespace
}  // namespace quarry
