// Tests of the particle file readers: a CSV table and a frame of io/vtu_writer read back bit for
// bit, types matched by name, and every broken input reported at file:line:col (the golden cases
// in tests/bad_particle_files: NN_name.csv + NN_name.expected, the file's path written {file}).
#include "io/particle_file_reader.h"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>

#include "io/io_test_support.h"
#include "io/vtu_writer.h"

namespace quarry {
namespace {

namespace fs = std::filesystem;

const std::vector<std::string> kTypes = {"ore", "steel_ball"};

fs::path scratch(const std::string& name) {
  const fs::path folder = fs::temp_directory_path() / "quarry_particle_file_reader_test";
  fs::create_directories(folder);
  return folder / name;
}

void write(const fs::path& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

std::uint64_t bits(double value) {
  return std::bit_cast<std::uint64_t>(value);
}

void expect_same_bits(const Vec3& a, const Vec3& b) {
  EXPECT_EQ(bits(a.x), bits(b.x));
  EXPECT_EQ(bits(a.y), bits(b.y));
  EXPECT_EQ(bits(a.z), bits(b.z));
}

// Awkward doubles: not short decimals, a subnormal, a negative zero, extremes.
std::vector<double> awkward_values() {
  return {0.1 + 0.2,        -1.0 / 3.0,   5e-324, -0.0, 1.7976931348623157e308,
          2.0 / 7.0 * 1e-3, 123456.789e-9};
}

TEST(ParticleCsv, ReadsEveryColumnInAnyOrderBitForBit) {
  const std::vector<double> v = awkward_values();
  const fs::path path = scratch("round_trip.csv");
  // Shortest round-trip text ("{}"), as CsvTable writes numbers; columns shuffled, CRLF endings.
  std::string text = "id, type,radius,z,y,x,wx,wy,wz,vx,vy,vz\r\n";
  for (std::size_t k = 0; k < v.size(); ++k)
    text += fmt::format("{},{},{},{},{},{},{},{},{},{},{},{}\r\n", 10 + k, kTypes[k % 2],
                        1e-3 + 1e-6 * k, v[k], v[(k + 1) % v.size()], v[(k + 2) % v.size()],
                        v[(k + 3) % v.size()], -v[k], v[(k + 4) % v.size()], v[(k + 5) % v.size()],
                        v[(k + 6) % v.size()], -v[(k + 1) % v.size()]);
  text += "\n";  // a blank last line is skipped
  write(path, text);
  Diagnostics problems;
  const std::vector<InitialParticle> read = read_particle_csv(path.string(), kTypes, 3, problems);
  ASSERT_FALSE(problems.has_errors()) << problems.format();
  ASSERT_EQ(read.size(), v.size());
  for (std::size_t k = 0; k < v.size(); ++k) {
    SCOPED_TRACE(k);
    EXPECT_EQ(read[k].id, 10 + k);
    EXPECT_EQ(read[k].type, k % 2);
    EXPECT_EQ(read[k].source, 3u);
    EXPECT_EQ(read[k].line, k + 2);
    EXPECT_EQ(bits(read[k].radius), bits(1e-3 + 1e-6 * k));
    expect_same_bits(read[k].position, {v[(k + 2) % v.size()], v[(k + 1) % v.size()], v[k]});
    expect_same_bits(read[k].angular_velocity,
                     {v[(k + 3) % v.size()], -v[k], v[(k + 4) % v.size()]});
    expect_same_bits(read[k].velocity,
                     {v[(k + 5) % v.size()], v[(k + 6) % v.size()], -v[(k + 1) % v.size()]});
  }
}

TEST(ParticleCsv, OptionalColumnsDefaultToZeroAndNewIds) {
  const fs::path path = scratch("minimal.csv");
  write(path, "x,y,z,radius,type\n0.5,0,1e-2,0.002,steel_ball\n");
  Diagnostics problems;
  const std::vector<InitialParticle> read = read_particle_csv(path.string(), kTypes, 0, problems);
  ASSERT_FALSE(problems.has_errors()) << problems.format();
  ASSERT_EQ(read.size(), 1u);
  EXPECT_EQ(read[0].id, 0u);
  EXPECT_EQ(read[0].type, 1u);
  expect_same_bits(read[0].velocity, {0, 0, 0});
  expect_same_bits(read[0].angular_velocity, {0, 0, 0});
  expect_same_bits(read[0].position, {0.5, 0.0, 1e-2});
}

// Each tests/bad_particle_files/NN_name.csv fails with the first line in NN_name.expected;
// QUARRY_UPDATE_BAD_DECKS=1 rewrites the .expected files instead (review the diff).
TEST(ParticleCsv, BrokenTablesFirstErrorLineMatchesGolden) {
  const fs::path folder = io_testing::source_dir() / "tests" / "bad_particle_files";
  const std::vector<fs::path> files = io_testing::files_with_extensions(folder, {".csv"});
  ASSERT_GE(files.size(), 8u);
  const bool update = std::getenv("QUARRY_UPDATE_BAD_DECKS") != nullptr;
  for (const fs::path& file : files) {
    SCOPED_TRACE(file.filename().string());
    Diagnostics problems;
    read_particle_csv(file.string(), kTypes, 0, problems);
    ASSERT_TRUE(problems.has_errors()) << "the table was read without an error";
    io_testing::expect_first_line_matches_golden(file, io_testing::first_line(problems.format()),
                                                 "{file}", update, problems.format());
  }
}

TEST(ParticleCsv, StopsAfterTwentyProblems) {
  const fs::path path = scratch("many_bad.csv");
  std::string text = "x,y,z,radius,type\n";
  for (int k = 0; k < 100; ++k) text += "a,0,0,1,ore\n";
  write(path, text);
  Diagnostics problems;
  EXPECT_TRUE(read_particle_csv(path.string(), kTypes, 0, problems).empty());
  EXPECT_EQ(problems.all().size(), 20u);
}

ParticleStore frame_particles() {
  ParticleStore store;
  const std::vector<double> v = awkward_values();
  for (std::size_t k = 0; k < v.size(); ++k) {
    const std::size_t i = store.add(100 + 3 * k, static_cast<std::uint16_t>(k % 2), 0,
                                    {v[k], v[(k + 1) % v.size()], -v[(k + 2) % v.size()]},
                                    {v[(k + 3) % v.size()], -v[k], v[(k + 4) % v.size()]},
                                    1e-3 * (1.0 + 0.1 * k), 2500.0, 0.0);
    store.angular_velocity[i] = {-v[(k + 5) % v.size()], v[(k + 6) % v.size()], v[k]};
  }
  store.inv_mass[1] = 0.0;                               // a fixed particle: mass +inf in the frame
  store.register_custom("temperature", 1, 293.15, "K");  // an array the reader does not know
  return store;
}

TEST(ParticleVtu, FrameOfTheWriterReadsBackBitForBitWithTypesByName) {
  const ParticleStore store = frame_particles();
  const fs::path path = scratch("particles_000060.vtu");
  // The frame's type order differs from the deck's: types are matched by name, not index.
  write(path, particles_vtu(store, {"steel_ball", "ore"}));
  Diagnostics problems;
  const std::vector<InitialParticle> read = read_particle_vtu(path.string(), kTypes, 1, problems);
  ASSERT_FALSE(problems.has_errors()) << problems.format();
  ASSERT_EQ(read.size(), store.size());
  for (std::size_t i = 0; i < store.size(); ++i) {
    SCOPED_TRACE(i);
    EXPECT_EQ(read[i].id, store.id[i]);
    EXPECT_EQ(read[i].type, store.type[i] == 0 ? 1u : 0u);
    EXPECT_EQ(read[i].source, 1u);
    EXPECT_EQ(bits(read[i].radius), bits(store.radius[i]));
    expect_same_bits(read[i].position, store.position[i]);
    expect_same_bits(read[i].velocity, store.velocity[i]);
    expect_same_bits(read[i].angular_velocity, store.angular_velocity[i]);
  }
}

std::string first_error(const fs::path& path, const std::vector<std::string>& types = kTypes) {
  Diagnostics problems;
  read_particle_vtu(path.string(), types, 0, problems);
  return problems.has_errors() ? io_testing::replace_all(io_testing::first_line(problems.format()),
                                                         path.string(), "{file}")
                               : "no error";
}

TEST(ParticleVtu, ATypeNameTheDeckDoesNotDefineIsAnErrorNamingIt) {
  const fs::path path = scratch("unknown_type.vtu");
  write(path, particles_vtu(frame_particles(), {"ore", "steel_bal"}));
  EXPECT_EQ(
      first_error(path),
      "{file}:5:1: error: particle type \"steel_bal\" of the frame is not defined in the deck");
}

TEST(ParticleVtu, BrokenFramesAreReportedNotRead) {
  const std::string good = particles_vtu(frame_particles(), kTypes);
  const fs::path path = scratch("broken.vtu");
  write(path, good.substr(0, good.size() - 200));  // truncated inside the cell arrays' data
  EXPECT_NE(first_error(path).find("runs past the end of the file (truncated?)"), std::string::npos)
      << first_error(path);
  write(path, "x,y,z\n1,2,3\n");
  EXPECT_EQ(first_error(path),
            "{file}:1:1: error: not a VTU file with appended data (no <VTKFile> or <AppendedData> "
            "element)");
  write(path, io_testing::replace_all(good, "encoding=\"raw\"", "encoding=\"base64\""));
  EXPECT_NE(first_error(path).find("error: the appended data is not raw"), std::string::npos);
  write(path, io_testing::replace_all(good, "Name=\"radius\"", "Name=\"size\""));
  EXPECT_NE(first_error(path).find("error: the frame has no array \"radius\""), std::string::npos);
  write(path, particles_vtu(frame_particles(), {}));  // no type_names
  EXPECT_NE(first_error(path).find("no field data \"type_names\""), std::string::npos)
      << first_error(path);
  ParticleStore store = frame_particles();
  store.radius[2] = -1.0;
  write(path, particles_vtu(store, kTypes));
  EXPECT_NE(
      first_error(path).find("error: particle 2 (id 106) has radius -1 m, not a positive number"),
      std::string::npos)
      << first_error(path);
  store = frame_particles();
  store.id[3] = store.id[1];
  write(path, particles_vtu(store, kTypes));
  EXPECT_NE(first_error(path).find("error: particles 1 and 3 have the same id 103"),
            std::string::npos)
      << first_error(path);
  // Counts and offsets that do not fit the file (a damaged or hostile header) are refused, not
  // followed past the end of the data.
  write(path, io_testing::replace_all(good, "NumberOfPoints=\"7\"",
                                      "NumberOfPoints=\"2305843009213693952\""));
  EXPECT_NE(first_error(path).find("NumberOfPoints 2305843009213693952 is more than the file's"),
            std::string::npos)
      << first_error(path);
  write(path, io_testing::replace_all(good, "offset=\"0\"", "offset=\"18446744073709551615\""));
  EXPECT_NE(first_error(path).find("starts past the end of the file"), std::string::npos)
      << first_error(path);
  store = frame_particles();
  store.velocity[0].y = std::numeric_limits<double>::quiet_NaN();
  write(path, particles_vtu(store, kTypes));
  EXPECT_NE(
      first_error(path).find(
          "particle 0 (id 100) has a position, velocity or angular velocity that is not a finite"),
      std::string::npos)
      << first_error(path);
}

}  // namespace
}  // namespace quarry
