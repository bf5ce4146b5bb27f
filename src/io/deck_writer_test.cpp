// Tests for the deck writer: every deck of the repository, decks using every key and variant,
// and specs built in code survive write → parse → write byte for byte, with the re-read spec
// equal to the written one in every value (bit for bit; locations may differ).
#include "io/deck_writer.h"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <optional>
#include <string>
#include <type_traits>
#include <vector>

#include "io/deck.h"

namespace quarry {
namespace {

namespace fs = std::filesystem;

fs::path source_dir() {
  const char* from_environment = std::getenv("QUARRY_SOURCE_DIR");
  return fs::path(from_environment ? from_environment : QUARRY_SOURCE_DIR);
}

// ---- Value comparison: every field of the spec, bit for bit. Overloads for the spec's
// structs first, so that the templates for lists and optionals below find them. ----
void expect_same(const Aabb& a, const Aabb& b, const std::string& what);
void expect_same(const SimulationSettings& a, const SimulationSettings& b, const std::string& what);
void expect_same(const MaterialSpec& a, const MaterialSpec& b, const std::string& what);
void expect_same(const InteractionSpec& a, const InteractionSpec& b, const std::string& what);
void expect_same(const SizeDistributionSpec& a, const SizeDistributionSpec& b,
                 const std::string& what);
void expect_same(const ParticleTypeSpec& a, const ParticleTypeSpec& b, const std::string& what);
void expect_same(const MotionSpec& a, const MotionSpec& b, const std::string& what);
void expect_same(const SurfaceSpec& a, const SurfaceSpec& b, const std::string& what);
void expect_same(const RegionSpec& a, const RegionSpec& b, const std::string& what);
void expect_same(const FactorySpec& a, const FactorySpec& b, const std::string& what);
void expect_same(const ParticleSourceSpec& a, const ParticleSourceSpec& b, const std::string& what);
void expect_same(const MonitorSpec& a, const MonitorSpec& b, const std::string& what);
void expect_same(const OutputSpec& a, const OutputSpec& b, const std::string& what);
void expect_same(const SupportSpec& a, const SupportSpec& b, const std::string& what);
void expect_same(const CalculixSpec& a, const CalculixSpec& b, const std::string& what);
void expect_same(const ExportSpec& a, const ExportSpec& b, const std::string& what);

// Doubles by their bits: -0 and 0 differ, and a value one ulp off is a failure.
void expect_same(double a, double b, const std::string& what) {
  EXPECT_EQ(std::bit_cast<std::uint64_t>(a), std::bit_cast<std::uint64_t>(b))
      << what << ": " << fmt::format("{} vs {}", a, b);
}

void expect_same(const Vec3& a, const Vec3& b, const std::string& what) {
  for (int component = 0; component < 3; ++component)
    expect_same(a[component], b[component], fmt::format("{}[{}]", what, component));
}

// Names, flags, counts, enums and index arrays: plain equality.
template <class T>
requires std::is_enum_v<T> || std::is_integral_v<T> || std::is_same_v<T, std::string> ||
    std::is_same_v<T, std::array<std::uint32_t, 3>> ||
    std::is_same_v<T, std::array<std::uint32_t, 4>> || std::is_same_v<T, std::array<bool, 3>>
void expect_same(const T& a, const T& b, const std::string& what) {
  EXPECT_TRUE(a == b) << what;
}

template <class T>
void expect_same(const Located<T>& a, const Located<T>& b, const std::string& what) {
  expect_same(a.value, b.value, what);
}

template <class T>
void expect_same(const std::optional<T>& a, const std::optional<T>& b, const std::string& what) {
  ASSERT_EQ(a.has_value(), b.has_value()) << what;
  if (a) expect_same(*a, *b, what);
}

template <class T>
void expect_same(const std::vector<T>& a, const std::vector<T>& b, const std::string& what) {
  ASSERT_EQ(a.size(), b.size()) << what;
  for (std::size_t index = 0; index < a.size(); ++index)
    expect_same(a[index], b[index], fmt::format("{}[{}]", what, index));
}

#define EXPECT_SAME_FIELD(field) expect_same(a.field, b.field, what + "." #field)

void expect_same(const Aabb& a, const Aabb& b, const std::string& what) {
  EXPECT_SAME_FIELD(lo);
  EXPECT_SAME_FIELD(hi);
}

void expect_same(const SimulationSettings& a, const SimulationSettings& b,
                 const std::string& what) {
  EXPECT_SAME_FIELD(end_time);
  EXPECT_SAME_FIELD(fixed_time_step);
  EXPECT_SAME_FIELD(rayleigh_fraction);
  EXPECT_SAME_FIELD(impact_speed);
  EXPECT_SAME_FIELD(gravity);
  EXPECT_SAME_FIELD(domain);
  EXPECT_SAME_FIELD(periodic);
  EXPECT_SAME_FIELD(integrator);
  EXPECT_SAME_FIELD(threads);
  EXPECT_SAME_FIELD(skin);
  EXPECT_SAME_FIELD(sort_interval);
  EXPECT_SAME_FIELD(max_overlap_fraction);
  EXPECT_SAME_FIELD(seed);
}

void expect_same(const MaterialSpec& a, const MaterialSpec& b, const std::string& what) {
  EXPECT_SAME_FIELD(name);
  EXPECT_SAME_FIELD(density);
  EXPECT_SAME_FIELD(youngs_modulus);
  EXPECT_SAME_FIELD(poisson_ratio);
  EXPECT_SAME_FIELD(rigid);
}

void expect_same(const InteractionSpec& a, const InteractionSpec& b, const std::string& what) {
  EXPECT_SAME_FIELD(material_a);
  EXPECT_SAME_FIELD(material_b);
  EXPECT_SAME_FIELD(restitution);
  EXPECT_SAME_FIELD(static_friction);
  EXPECT_SAME_FIELD(rolling_friction);
  EXPECT_SAME_FIELD(rolling_model);
  EXPECT_SAME_FIELD(cohesion_energy_density);
  EXPECT_SAME_FIELD(cohesion_model);
  EXPECT_SAME_FIELD(surface_energy);
  EXPECT_SAME_FIELD(normal_model);
  EXPECT_SAME_FIELD(linear_stiffness);
  EXPECT_SAME_FIELD(linear_tangential_ratio);
  EXPECT_SAME_FIELD(clip_attraction);
}

void expect_same(const SizeDistributionSpec& a, const SizeDistributionSpec& b,
                 const std::string& what) {
  EXPECT_SAME_FIELD(kind);
  EXPECT_SAME_FIELD(radius);
  EXPECT_SAME_FIELD(min_radius);
  EXPECT_SAME_FIELD(max_radius);
  EXPECT_SAME_FIELD(mean_radius);
  EXPECT_SAME_FIELD(std_radius);
  EXPECT_SAME_FIELD(log_mean);
  EXPECT_SAME_FIELD(log_std);
  EXPECT_SAME_FIELD(discrete_radii);
  EXPECT_SAME_FIELD(discrete_mass_fractions);
}

void expect_same(const ParticleTypeSpec& a, const ParticleTypeSpec& b, const std::string& what) {
  EXPECT_SAME_FIELD(name);
  EXPECT_SAME_FIELD(material);
  EXPECT_SAME_FIELD(size);
  EXPECT_SAME_FIELD(fixed);
}

void expect_same(const MotionSpec& a, const MotionSpec& b, const std::string& what) {
  EXPECT_SAME_FIELD(kind);
  EXPECT_SAME_FIELD(velocity);
  EXPECT_SAME_FIELD(axis_point);
  EXPECT_SAME_FIELD(axis_direction);
  EXPECT_SAME_FIELD(angular_velocity);
  EXPECT_SAME_FIELD(amplitude);
  EXPECT_SAME_FIELD(frequency);
  EXPECT_SAME_FIELD(start_time);
  EXPECT_SAME_FIELD(stop_time);
}

void expect_same(const SurfaceSpec& a, const SurfaceSpec& b, const std::string& what) {
  EXPECT_SAME_FIELD(name);
  EXPECT_SAME_FIELD(kind);
  EXPECT_SAME_FIELD(file);
  EXPECT_SAME_FIELD(scale);
  EXPECT_SAME_FIELD(offset);
  EXPECT_SAME_FIELD(point);
  EXPECT_SAME_FIELD(normal);
  EXPECT_SAME_FIELD(size);
  EXPECT_SAME_FIELD(min);
  EXPECT_SAME_FIELD(max);
  EXPECT_SAME_FIELD(base);
  EXPECT_SAME_FIELD(axis);
  EXPECT_SAME_FIELD(radius);
  EXPECT_SAME_FIELD(length);
  EXPECT_SAME_FIELD(capped);
  EXPECT_SAME_FIELD(resolution);
  EXPECT_SAME_FIELD(mesh_vertices);
  EXPECT_SAME_FIELD(mesh_triangles);
  EXPECT_SAME_FIELD(mesh_quads);
  EXPECT_SAME_FIELD(material);
  EXPECT_SAME_FIELD(motion);
  EXPECT_SAME_FIELD(conveyor_velocity);
  EXPECT_SAME_FIELD(export_loads);
  EXPECT_SAME_FIELD(coupled);
}

void expect_same(const RegionSpec& a, const RegionSpec& b, const std::string& what) {
  EXPECT_SAME_FIELD(kind);
  EXPECT_SAME_FIELD(min);
  EXPECT_SAME_FIELD(max);
  EXPECT_SAME_FIELD(base);
  EXPECT_SAME_FIELD(axis);
  EXPECT_SAME_FIELD(radius);
  EXPECT_SAME_FIELD(length);
}

void expect_same(const FactorySpec& a, const FactorySpec& b, const std::string& what) {
  EXPECT_SAME_FIELD(name);
  EXPECT_SAME_FIELD(particle_type);
  EXPECT_SAME_FIELD(region);
  EXPECT_SAME_FIELD(target_count);
  EXPECT_SAME_FIELD(target_mass);
  EXPECT_SAME_FIELD(mass_rate);
  EXPECT_SAME_FIELD(start_time);
  EXPECT_SAME_FIELD(stop_time);
  EXPECT_SAME_FIELD(initial_velocity);
  EXPECT_SAME_FIELD(initial_angular_velocity);
  EXPECT_SAME_FIELD(max_attempts);
}

void expect_same(const ParticleSourceSpec& a, const ParticleSourceSpec& b, const std::string& what) {
  EXPECT_SAME_FIELD(file);
  EXPECT_SAME_FIELD(type);
  EXPECT_SAME_FIELD(position);
  EXPECT_SAME_FIELD(radius);
  EXPECT_SAME_FIELD(velocity);
  EXPECT_SAME_FIELD(angular_velocity);
  EXPECT_SAME_FIELD(allow_overlap);
}

void expect_same(const MonitorSpec& a, const MonitorSpec& b, const std::string& what) {
  EXPECT_SAME_FIELD(name);
  EXPECT_SAME_FIELD(kind);
  EXPECT_SAME_FIELD(region);
  EXPECT_SAME_FIELD(particle_id);
  EXPECT_SAME_FIELD(point);
  EXPECT_SAME_FIELD(normal);
  EXPECT_SAME_FIELD(axis);
  EXPECT_SAME_FIELD(bins);
}

void expect_same(const OutputSpec& a, const OutputSpec& b, const std::string& what) {
  EXPECT_SAME_FIELD(directory);
  EXPECT_SAME_FIELD(interval);
  EXPECT_SAME_FIELD(monitor_interval);
  EXPECT_SAME_FIELD(checkpoint_interval);
  EXPECT_SAME_FIELD(plots);
  EXPECT_SAME_FIELD(progress_interval);
  EXPECT_SAME_FIELD(contacts);
}

void expect_same(const SupportSpec& a, const SupportSpec& b, const std::string& what) {
  EXPECT_SAME_FIELD(name);
  EXPECT_SAME_FIELD(min);
  EXPECT_SAME_FIELD(max);
  EXPECT_SAME_FIELD(fix);
}

void expect_same(const CalculixSpec& a, const CalculixSpec& b, const std::string& what) {
  EXPECT_SAME_FIELD(thickness);
  EXPECT_SAME_FIELD(youngs_modulus);
  EXPECT_SAME_FIELD(poisson_ratio);
  EXPECT_SAME_FIELD(density);
  EXPECT_SAME_FIELD(analysis);
  EXPECT_SAME_FIELD(static_time);
  EXPECT_SAME_FIELD(supports);
}

void expect_same(const ExportSpec& a, const ExportSpec& b, const std::string& what) {
  EXPECT_SAME_FIELD(enabled);
  EXPECT_SAME_FIELD(interval);
  EXPECT_SAME_FIELD(directory);
  EXPECT_SAME_FIELD(formats);
  EXPECT_SAME_FIELD(calculix);
}

// Every value of the spec; deck_path only names the text a spec was read from.
void expect_same(const SimulationSpec& a, const SimulationSpec& b, const std::string& what) {
  EXPECT_SAME_FIELD(simulation);
  EXPECT_SAME_FIELD(materials);
  EXPECT_SAME_FIELD(interactions);
  EXPECT_SAME_FIELD(particle_types);
  EXPECT_SAME_FIELD(surfaces);
  EXPECT_SAME_FIELD(factories);
  EXPECT_SAME_FIELD(particle_sources);
  EXPECT_SAME_FIELD(monitors);
  EXPECT_SAME_FIELD(output);
  EXPECT_SAME_FIELD(fem_export);
}

#undef EXPECT_SAME_FIELD

// The property a checkpoint relies on: the written deck reads back into `spec` value for value,
// and writing that again gives the same text byte for byte. Returns the written deck.
std::string expect_round_trip(const SimulationSpec& spec,
                              const DeckParseOptions& options = DeckParseOptions{}) {
  const std::string written = write_deck(spec);
  SimulationSpec reread;
  try {
    reread = parse_deck_string(written, "written.yaml", options);
  } catch (const UserError& error) {
    std::string messages;
    for (const Diagnostic& item : error.diagnostics().all())
      messages += fmt::format("{}:{}: {} ({})\n", item.where.line, item.where.column, item.message,
                              item.hint);
    ADD_FAILURE() << "the written deck does not parse:\n" << messages << written;
    return written;
  }
  EXPECT_EQ(write_deck(reread), written);
  expect_same(spec, reread, "spec");
  return written;
}

// Every deck the repository ships: examples, verification cases, test decks.
TEST(DeckWriter, RepositoryDecksRoundTrip) {
  std::vector<fs::path> decks;
  const auto add_yaml_files = [&](const fs::path& folder, bool recursive) {
    const auto add = [&](const fs::directory_entry& entry) {
      if (entry.is_regular_file() && entry.path().extension() == ".yaml")
        decks.push_back(entry.path());
    };
    if (recursive)
      for (const auto& entry : fs::recursive_directory_iterator(folder)) add(entry);
    else
      for (const auto& entry : fs::directory_iterator(folder)) add(entry);
  };
  add_yaml_files(source_dir() / "examples", true);
  add_yaml_files(source_dir() / "tests" / "verification", true);
  add_yaml_files(source_dir() / "tests" / "decks", false);
  std::sort(decks.begin(), decks.end());
  ASSERT_GE(decks.size(), 9u) << "4 examples, 3 verification decks, 2 test decks";
  for (const fs::path& deck : decks) {
    SCOPED_TRACE(deck.string());
    expect_round_trip(parse_deck(deck.string()));
  }
}

// Every key and variant the parser knows: all surface types (two STL surfaces on one file,
// meshes of triangles, quads and both, coupled or not), all motions, size distributions,
// regions, contact and rolling models, the export section with CalculiX supports.
const char* const kEveryKeyDeck = R"(simulation:
  end_time: 2.5
  time_step: 1.0e-5
  impact_speed: 3.0
  gravity: [0.1, -9.81, 0]
  domain: {min: [-3, -3, -3], max: [3, 3, 3], periodic: [y, x]}
  integrator: symplectic_euler
  threads: 2
  skin: 0.0002
  sort_interval: 500
  max_overlap_fraction: 0.05
  seed: 2016
materials:
  - {name: ore, density: 2600, youngs_modulus: 5.0e7, poisson_ratio: 0.25}
  - {name: steel, density: 7850, youngs_modulus: 2.1e11, poisson_ratio: 0.3}
  - {name: rubber, density: 1100, youngs_modulus: 1.0e6, poisson_ratio: 0.45}
  - {name: anvil, density: 7800, rigid: true}
interactions:
  - {materials: [ore, ore], restitution: 0.3, static_friction: 0.6, rolling_friction: 0.1,
     rolling_model: constant_torque, cohesion: 30000}
  - {materials: [ore, steel], restitution: 0.4, static_friction: 0.5, rolling_friction: 0.05,
     rolling_model: epsd, clip_attraction: true}
  - {materials: [rubber, ore], model: linear, stiffness: 2.5e4, tangential_stiffness_ratio: 0.3,
     rolling_model: none}
  - {materials: [steel, rubber], model: hertz_mindlin, restitution: 0.9, cohesion_model: jkr,
     surface_energy: 0.08}
particle_types:
  - {name: fine, material: ore, size: {distribution: fixed, radius: 0.012}}
  - {name: studs, material: ore, size: {distribution: fixed, radius: 0.01}, fixed: true}
  - {name: medium, material: ore, size: {distribution: uniform, min_radius: 0.013, max_radius: 0.016}}
  - {name: coarse, material: ore, size: {distribution: normal, mean_radius: 0.018, std_radius: 0.0015}}
  - {name: clipped, material: ore, size: {distribution: normal, mean_radius: 0.018, std_radius: 0.0015,
     min_radius: 0.015, max_radius: 0.021}}
  - {name: skewed, material: ore, size: {distribution: log_normal, median_radius: 0.0123, log_std: 0.2}}
  - {name: skewed_clipped, material: ore, size: {distribution: log_normal, median_radius: 0.01,
     log_std: 0.25, min_radius: 0.008, max_radius: 0.02}}
  - {name: sieved, material: ore, size: {distribution: discrete, radii: [0.01, 0.015, 0.02],
     mass_fractions: [0.2, 0.3, 0.5]}}
surfaces:
  - {name: bed, type: stl, file: parts/bed.stl, scale: 0.001, offset: [0, 0, 0.5], material: steel,
     export: true, motion: {type: rotation, axis_point: [0, 0, 1], axis_direction: [0, 1, 0],
     angular_velocity: -1.5, start_time: 0.1, stop_time: 1}}
  - {name: plain_stl, type: stl, file: parts/bed.stl, material: steel}
  - {name: floor, type: plane, point: [0, 0, -0.5], normal: [0, 0, 2], size: 3, material: steel,
     motion: {type: vibration, amplitude: [0, 0, 0.001], frequency: 50}}
  - {name: belt, type: box, min: [0, 0, 0], max: [1, 0.5, 0.1], material: rubber,
     conveyor_velocity: [1, 0, 0], motion: {type: translation, velocity: [0.1, 0, 0], start_time: 0.5}}
  - {name: drum, type: cylinder, base: [0, 0, 0], axis: [1, 0, 0], radius: 0.5, length: 1,
     capped: true, resolution: 48, material: steel}
  - {name: pipe, type: cylinder, base: [0, 0, 0], axis: [0, 0, 1], radius: 0.25, length: 2,
     material: steel}
  - name: chute
    type: mesh
    vertices: [[0, 0, 0], [1, 0, 0], [1, 0.5, 0.3], [0, 0.5, 0.3], [0.5, 1, 0.5]]
    triangles: [[3, 2, 4]]
    quads: [[0, 1, 2, 3]]
    material: steel
    coupled: true
    export: true
  - {name: flap, type: mesh, vertices: [[0, 0, 1], [1, 0, 1], [1, 1, 1]], triangles: [[0, 1, 2]],
     material: rubber, coupled: false}
  - {name: lid, type: mesh, vertices: [[0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]],
     quads: [[0, 1, 2, 3]], material: steel, coupled: true}
factories:
  - name: left
    particle_type: coarse
    region: {type: cylinder, base: [0, 0, 1], axis: [0, 0, 1], radius: 0.2, length: 0.3}
    mass: 12.5
    mass_rate: 50
    start_time: 0.1
    stop_time: 1.0
    velocity: [0, 0, -1]
    angular_velocity: [0, 5, -2.5]
    max_attempts: 20
  - {name: right, particle_type: fine, region: {type: box, min: [0, 0, 0], max: [1, 1, 1]}, count: 1000}
  - {name: batch, particle_type: skewed, region: {type: box, min: [0, 0, 1], max: [1, 1, 2]}, mass: 3}
particles:
  - {type: fine, position: [0.5, 0.5, 0.5], radius: 0.012, velocity: [0, 0, -1], angular_velocity: [1, 2, 3],
     allow_overlap: true}
  - {type: fine, position: [0.1, 0.1, 0.1]}
monitors:
  - {name: in_bed, region: {type: box, min: [0, 0, 0], max: [1, 1, 1]}}
  - {name: in_pipe, region: {type: cylinder, base: [0, 0, 0], axis: [0, 0, 1], radius: 0.25, length: 2}}
  - {name: everything}
  - {name: tracer, type: particle, id: 17}
  - {name: discharge, type: mass_flow, point: [0, 0, 0.5], normal: [0, 0, -1]}
  - {name: bed_stress, type: stress, region: {type: box, min: [0, 0, 0], max: [1, 1, 0.5]}}
  - {name: shear, type: velocity_profile, region: {type: box, min: [0, 0, 0], max: [1, 1, 1]}, axis: y, bins: 7}
output:
  directory: results
  interval: 0.05
  monitor_interval: 0.01
  checkpoint_interval: 0.5
  plots: false
  progress_interval: 5
  contacts: true
export:
  interval: 0.1
  directory: loads
  formats: [med, calculix, vtu, csv]
  calculix:
    thickness: 0.005
    youngs_modulus: 2.1e11
    poisson_ratio: 0.28
    analysis: static
    time: 1.5
    supports:
      - {name: front, box: {min: [0, -1, 0], max: [0, 1, 0]}, fix: clamped}
      - {name: rear, box: {min: [1, -1, 0], max: [1, 1, 0]}, fix: pinned}
      - {name: middle, box: {min: [0.5, -1, 0], max: [0.5, 1, 0]}}
)";

// The variants the deck above cannot hold at once: the Rayleigh time step, the automatic
// skin, no output section, a dynamic CalculiX analysis with all formats, and an export
// without CalculiX; and sections left empty.
const std::vector<std::string> kVariantDecks = {
    R"(simulation:
  end_time: 1
  time_step: {rayleigh_fraction: 0.15}
  domain: {min: [0, 0, 0], max: [1, 1, 1]}
  skin: auto
materials:
  - {name: m, density: 1000, youngs_modulus: 1.0e6, poisson_ratio: 0}
interactions:
  - {materials: [m, m]}
particle_types:
  - {name: p, material: m, size: {distribution: fixed, radius: 0.01}}
surfaces:
  - {name: plate, type: plane, point: [0.5, 0.5, 0], normal: [0, 0, 1], material: m, export: true}
export:
  interval: 0.25
  calculix: {thickness: 0.002, youngs_modulus: 7.0e10, density: 2700, analysis: dynamic}
)",
    R"(simulation: {end_time: 0.5, domain: {min: [0, 0, 0], max: [1, 1, 1]}, integrator: velocity_verlet}
materials: [{name: m, density: 1000, youngs_modulus: 1.0e6, poisson_ratio: 0.3}]
surfaces:
  - {name: plate, type: plane, point: [0.5, 0.5, 0], normal: [0, 0, 1], material: m, export: true}
export: {interval: 0.1, directory: csv_only, formats: [csv, vtu]}
)",
    R"(simulation: {end_time: 0.5, domain: {min: [0, 0, 0], max: [1, 1, 1]}}
materials: [{name: m, density: 1000, youngs_modulus: 1.0e6, poisson_ratio: 0.3}]
interactions: []
particle_types: []
surfaces: []
factories: []
monitors: []
)",
};

class DeckWriterFiles : public testing::Test {
 protected:
  void SetUp() override {
    // One folder per test: CTest runs the cases in parallel processes.
    folder_ = fs::path(testing::TempDir()) /
              ("quarry_deck_writer_" +
               std::string(testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::create_directories(folder_ / "parts");
    std::ofstream(folder_ / "parts" / "bed.stl") << "solid bed\nendsolid bed\n";
  }
  void TearDown() override { fs::remove_all(folder_); }
  // Writes `text` as a deck file in the test folder and parses it (STL paths from there).
  SimulationSpec parse_file(const std::string& text, const std::string& name) {
    const std::string path = (folder_ / name).string();
    std::ofstream(path) << text;
    return parse_deck(path);
  }
  fs::path folder_;
};

TEST_F(DeckWriterFiles, EveryKeyDeckRoundTrips) {
  const SimulationSpec spec = parse_file(kEveryKeyDeck, "every_key.yaml");
  const std::string written = expect_round_trip(spec);
  // The user's own spelling where the spec holds another quantity (ln of the median), the
  // resolved clip bounds, the absolute STL path, and the new keys.
  EXPECT_NE(written.find("median_radius: 0.0123, log_std: 0.2, "), std::string::npos) << written;
  EXPECT_NE(
      written.find("median_radius: 0.01, log_std: 0.25, min_radius: 0.008, max_radius: 0.02}"),
      std::string::npos)
      << written;
  EXPECT_NE(written.find("mean_radius: 0.018, std_radius: 0.0015, min_radius: "), std::string::npos)
      << written;
  EXPECT_NE(written.find("    file: " + (folder_ / "parts" / "bed.stl").string() + "\n"),
            std::string::npos)
      << written;
  EXPECT_NE(written.find("    type: mesh\n    vertices:\n      - [0, 0, 0]\n"), std::string::npos)
      << written;
  EXPECT_NE(written.find("    quads:\n      - [0, 1, 2, 3]\n"), std::string::npos) << written;
  EXPECT_NE(written.find("    coupled: true\n"), std::string::npos) << written;
  EXPECT_NE(written.find("  time_step: 1e-05\n"), std::string::npos) << written;
  EXPECT_NE(written.find(", periodic: [x, y]}\n"), std::string::npos) << written;
}

TEST_F(DeckWriterFiles, VariantDecksRoundTrip) {
  for (std::size_t index = 0; index < kVariantDecks.size(); ++index) {
    SCOPED_TRACE(kVariantDecks[index]);
    expect_round_trip(parse_file(kVariantDecks[index], fmt::format("variant_{}.yaml", index)));
  }
}

// A spec filled in code, as through the C API: values with no short decimal form, extreme
// magnitudes, names that plain YAML would misread, an STL file that is not there, a log-normal
// size given by ln(median) directly.
TEST(DeckWriter, SpecBuiltInCodeRoundTrips) {
  SimulationSpec spec;
  spec.simulation.end_time = 0.1 + 0.2;
  spec.simulation.fixed_time_step = Located<double>(1.0 / 3.0 * 1e-5);
  spec.simulation.gravity = Vec3{5e-324, -0.0, -9.80665};
  Aabb domain;
  domain.lo = Vec3{-1.7976931348623157e308, -1, -2.2250738585072014e-308};
  domain.hi = Vec3{1e300, 1.0 / 7.0, 3};
  spec.simulation.domain = domain;
  spec.simulation.skin = 1e-3 / 3.0;
  spec.simulation.seed = static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max());

  const std::vector<std::string> awkward_names = {
      "ore #1",    "true",     "null",        "a: b",   "- x",    "with \"quotes\" and \\",
      "tab\there", "5",        "ünïcode",     "[list]", "{map}",  "&anchor",
      "*alias",    "!tag",     "%directive",  "@at",    "`tick`", "trailing space ",
      " leading",  "'single'", "multi\nline", ".5",     "~"};
  for (const std::string& name : awkward_names) {
    MaterialSpec material;
    material.name = name;
    material.density = 2500.0 / 3.0;
    material.youngs_modulus = 5.0e7 * std::sqrt(2.0);
    material.poisson_ratio = 0.1 + 0.2;
    spec.materials.push_back(material);
    InteractionSpec interaction;
    interaction.material_a = name;
    interaction.material_b = name;
    interaction.restitution = 1.0 / 3.0;
    spec.interactions.push_back(interaction);
  }

  ParticleTypeSpec skewed;
  skewed.name = std::string("skewed");
  skewed.material = awkward_names[0];
  skewed.size.kind = SizeDistributionKind::log_normal;
  skewed.size.log_mean = -4.321;
  skewed.size.log_std = 0.3;
  skewed.size.min_radius = std::exp(-4.321 - 0.9);
  skewed.size.max_radius = std::exp(-4.321 + 0.9);
  spec.particle_types.push_back(skewed);

  SurfaceSpec part;
  part.name = std::string("part with spaces");
  part.kind = SurfaceKind::stl;
  part.file = std::string("/no such folder/part #2.stl");
  part.scale = 0.001;
  part.material = awkward_names[0];
  spec.surfaces.push_back(part);

  SurfaceSpec mesh;
  mesh.name = std::string("wavy");
  mesh.kind = SurfaceKind::mesh;
  mesh.material = awkward_names[0];
  mesh.coupled = true;
  constexpr std::uint32_t kColumns = 10;
  for (std::uint32_t row = 0; row < 2; ++row)
    for (std::uint32_t column = 0; column < kColumns; ++column)
      mesh.mesh_vertices.push_back(Vec3{column / 9.0, row / 3.0, std::sin(column * 0.7)});
  for (std::uint32_t column = 0; column + 1 < kColumns; ++column) {
    if (column % 2 == 0)
      mesh.mesh_quads.push_back({column, column + 1, kColumns + column + 1, kColumns + column});
    else
      mesh.mesh_triangles.push_back({column, column + 1, kColumns + column});
  }
  spec.surfaces.push_back(mesh);

  FactorySpec factory;
  factory.name = std::string("pour");
  factory.particle_type = std::string("skewed");
  factory.region.min = Vec3{0, 0, 0};
  factory.region.max = Vec3{0.1, 0.1, 0.1};
  factory.target_count = Located<std::int64_t>(std::numeric_limits<std::int64_t>::max());
  spec.factories.push_back(factory);
  spec.output.directory = std::string("out dir/run: 1");

  DeckParseOptions options;
  options.require_files = false;
  const std::string written = expect_round_trip(spec, options);
  EXPECT_NE(written.find("median_radius: "), std::string::npos) << written;
}

// A log-normal median is written so that its logarithm is log_mean exactly, and as short as
// that allows: the round trip of many medians, as a deck gives them.
TEST(DeckWriter, LogNormalMediansRoundTrip) {
  SimulationSpec spec;
  spec.simulation.end_time = 1.0;
  Aabb domain;
  domain.lo = Vec3{0, 0, 0};
  domain.hi = Vec3{1, 1, 1};
  spec.simulation.domain = domain;
  MaterialSpec material;
  material.name = std::string("m");
  material.density = 1000.0;
  material.youngs_modulus = 1e6;
  material.poisson_ratio = 0.3;
  spec.materials.push_back(material);
  for (int index = 1; index <= 200; ++index) {
    const double median = index * 1.7e-4;
    ParticleTypeSpec particle_type;
    particle_type.name = fmt::format("p{}", index);
    particle_type.material = std::string("m");
    particle_type.size.kind = SizeDistributionKind::log_normal;
    particle_type.size.log_mean = std::log(median);
    particle_type.size.log_std = 0.1;
    particle_type.size.min_radius = median / 2;
    particle_type.size.max_radius = median * 2;
    spec.particle_types.push_back(particle_type);
  }
  InteractionSpec interaction;
  interaction.material_a = std::string("m");
  interaction.material_b = std::string("m");
  spec.interactions.push_back(interaction);
  const std::string written = expect_round_trip(spec);
  EXPECT_NE(written.find("median_radius: 0.0017, "), std::string::npos) << written;
}

}  // namespace
}  // namespace quarry
