// Tests of the LAMMPS data-file reader (atom_style sphere, as write_data writes it; LAMMPS
// manual, read_data "Atoms" and "Velocities" sections) and of starting the settled-bed problem
// from such a file.
#include "bench/lammps_data.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>

#include "bench/settled_bed_scene.h"
#include "core/diagnostics.h"

namespace quarry::bench {
namespace {

namespace fs = std::filesystem;

std::string write_file(const std::string& name, const std::string& text) {
  const std::string path = (fs::path(testing::TempDir()) / name).string();
  std::ofstream(path) << text;
  return path;
}

std::string first_line(const std::string& text) { return text.substr(0, text.find('\n')); }

// The first diagnostic line of reading `text` ("file:line:col: error: …"), with the path
// written as {file}; fails the test if the file reads without error.
std::string first_error(const std::string& name, const std::string& text) {
  const std::string path = write_file(name, text);
  try {
    read_lammps_data(path);
  } catch (const UserError& error) {
    std::string line = first_line(error.diagnostics().format());
    if (line.compare(0, path.size(), path) == 0) line.replace(0, path.size(), "{file}");
    return line;
  }
  ADD_FAILURE() << name << " read without error";
  return {};
}

// Three 2 mm glass spheres, written in processor order (not by id) as write_data does.
const std::string kHeader =
    "LAMMPS data file via write_data, version 29 Sep 2021, timestep = 20000\n"
    "\n"
    "3 atoms\n"
    "1 atom types\n"
    "\n"
    "0 0.0084 xlo xhi\n"
    "0 0.0063 ylo yhi\n"
    "0 0.0105 zlo zhi\n"
    "\n";
const std::string kVelocities =
    "\n"
    "Velocities\n"
    "\n"
    "2 0.5 -0.25 1e-3 10 -20 30\n"
    "3 0 0 0 0 0 0\n"
    "1 -1.5e-05 2.5e-06 -3e-06 -0.0107 0.004 -0.296\n";

TEST(LammpsData, ReadsSphereAtomsWithImageFlagsAndVelocities) {
  const std::string path = write_file("three_image.data", kHeader +
      "Atoms # sphere\n"
      "\n"
      "2 1 0.002 2500 0.0030648395724573872 0.001006571736954091 0.0009986230502959806 0 0 0\n"
      "3 1 0.002 2500 0.005 0.003 0.002 0 0 1\n"
      "1 1 0.0019 2600 0.001091909857075494 0.0014818798990981945 0.000991755355429829 -1 0 0\n" +
      kVelocities);
  const LammpsData data = read_lammps_data(path);
  EXPECT_EQ(data.path, path);
  EXPECT_EQ(data.title, "LAMMPS data file via write_data, version 29 Sep 2021, timestep = 20000");
  EXPECT_EQ(data.atom_count, 3u);
  EXPECT_EQ(data.atom_types, 1);
  EXPECT_EQ(data.box_lo, (Vec3{0, 0, 0}));
  EXPECT_EQ(data.box_hi, (Vec3{0.0084, 0.0063, 0.0105}));
  EXPECT_TRUE(data.has_image_flags);
  EXPECT_TRUE(data.has_velocities);
  ASSERT_EQ(data.atoms.size(), 3u);
  // Ascending id whatever the file order; every digit as written (from_chars is exact).
  EXPECT_EQ(data.atoms[0].id, 1u);
  EXPECT_EQ(data.atoms[1].id, 2u);
  EXPECT_EQ(data.atoms[2].id, 3u);
  const LammpsAtom& a1 = data.atoms[0];
  EXPECT_EQ(a1.type, 1);
  EXPECT_EQ(a1.diameter, 0.0019);
  EXPECT_EQ(a1.density, 2600.0);
  EXPECT_EQ(a1.position, (Vec3{0.001091909857075494, 0.0014818798990981945, 0.000991755355429829}));
  EXPECT_EQ(a1.image, (std::array<int, 3>{-1, 0, 0}));
  EXPECT_EQ(a1.velocity, (Vec3{-1.5e-05, 2.5e-06, -3e-06}));
  EXPECT_EQ(a1.angular_velocity, (Vec3{-0.0107, 0.004, -0.296}));
  EXPECT_EQ(a1.line, 14);
  const LammpsAtom& a2 = data.atoms[1];
  EXPECT_EQ(a2.diameter, 0.002);
  EXPECT_EQ(a2.density, 2500.0);
  EXPECT_EQ(a2.velocity, (Vec3{0.5, -0.25, 1e-3}));
  EXPECT_EQ(a2.angular_velocity, (Vec3{10, -20, 30}));
  EXPECT_EQ(a2.line, 12);
  EXPECT_EQ(data.atoms[2].image, (std::array<int, 3>{0, 0, 1}));
  EXPECT_EQ(data.atoms[2].velocity, (Vec3{}));
}

TEST(LammpsData, ReadsSphereAtomsWithoutImageFlags) {
  // Also: comments ("#" anywhere), tabs, CRLF line ends and a blank-free section start.
  const std::string path = write_file("three_plain.data", kHeader +
      "Atoms # sphere\r\n"
      "\r\n"
      "1 1 0.002 2500 0.001 0.001 0.001   # bottom corner\r\n"
      "2\t1\t0.002\t2500\t0.003\t0.001\t0.001\r\n"
      "3 1 0.002 2500 0.005 0.003 0.002\r\n" +
      kVelocities);
  const LammpsData data = read_lammps_data(path);
  EXPECT_FALSE(data.has_image_flags);
  EXPECT_TRUE(data.has_velocities);
  ASSERT_EQ(data.atoms.size(), 3u);
  for (const LammpsAtom& atom : data.atoms) EXPECT_EQ(atom.image, (std::array<int, 3>{0, 0, 0}));
  EXPECT_EQ(data.atoms[0].position, (Vec3{0.001, 0.001, 0.001}));
  EXPECT_EQ(data.atoms[1].position, (Vec3{0.003, 0.001, 0.001}));
  EXPECT_EQ(data.atoms[1].angular_velocity, (Vec3{10, -20, 30}));
  EXPECT_EQ(data.atoms[2].velocity, (Vec3{}));
}

TEST(LammpsData, WithoutVelocitiesEverythingIsAtRest) {
  const LammpsData data = read_lammps_data(write_file("three_rest.data", kHeader +
      "Atoms # sphere\n\n"
      "1 1 0.002 2500 0.001 0.001 0.001\n"
      "2 1 0.002 2500 0.003 0.001 0.001\n"
      "3 1 0.002 2500 0.005 0.003 0.002\n"));
  EXPECT_FALSE(data.has_velocities);
  ASSERT_EQ(data.atoms.size(), 3u);
  for (const LammpsAtom& atom : data.atoms) {
    EXPECT_EQ(atom.velocity, (Vec3{}));
    EXPECT_EQ(atom.angular_velocity, (Vec3{}));
  }
}

// Each malformed file gives a UserError naming the line and column of the culprit.
TEST(LammpsData, MalformedFilesNameLineAndColumn) {
  const std::string atoms = "Atoms # sphere\n\n";
  const std::string good1 = "1 1 0.002 2500 0.001 0.001 0.001\n";
  const std::string good2 = "2 1 0.002 2500 0.003 0.001 0.001\n";
  const std::string good3 = "3 1 0.002 2500 0.005 0.003 0.002\n";
  // Line 12 is the first Atoms line, 13 the second.
  EXPECT_EQ(first_error("bad_number.data", kHeader + atoms + good1 + "2 1 0.0o2 2500 0.003 0.001 0.001\n" + good3),
            "{file}:13:5: error: expected a finite number for the diameter (m), got \"0.0o2\"");
  EXPECT_EQ(first_error("few_values.data", kHeader + atoms + good1 + good2 + "3 1 0.002 2500 0.005 0.003\n"),
            "{file}:14:27: error: expected 7 or 10 values in this Atoms line, found 6");
  EXPECT_EQ(first_error("mixed_image.data", kHeader + atoms + good1 + "2 1 0.002 2500 0.003 0.001 0.001 0 0 0\n" + good3),
            "{file}:13:34: error: image flags, where the first Atoms line has none");
  EXPECT_EQ(first_error("outside.data", kHeader + atoms + good1 + good2 + "3 1 0.002 2500 0.005 0.0071 0.002\n"),
            "{file}:14:22: error: y = 0.0071 m lies outside the box [0, 0.0063] of the header");
  EXPECT_EQ(first_error("twice.data", kHeader + atoms + good1 + good2 + "1 1 0.002 2500 0.005 0.003 0.002\n"),
            "{file}:14:1: error: atom-ID 1 appears twice in the Atoms section (also line 12)");
  EXPECT_EQ(first_error("short.data", kHeader + atoms + good1 + good2),
            "{file}:13: error: the file ends after 2 of the 3 lines of the Atoms section");
  EXPECT_EQ(first_error("early_section.data", kHeader + atoms + good1 + good2 + kVelocities),
            "{file}:15:1: error: the Atoms section ends after 2 of its 3 lines (found \"Velocities\")");
  EXPECT_EQ(first_error("unknown_velocity.data",
                        kHeader + atoms + good1 + good2 + good3 + "\nVelocities\n\n4 0 0 0 0 0 0\n"),
            "{file}:18:1: error: atom-ID 4 is not in the Atoms section");
  EXPECT_EQ(first_error("atomic.data", kHeader + "Atoms # atomic\n\n" + good1 + good2 + good3),
            "{file}:10:7: error: an Atoms section of atom_style \"atomic\": only atom_style sphere is supported");
  EXPECT_EQ(first_error("header.data", "title\n\n3 atomz\n"),
            "{file}:3:3: error: unknown header keyword \"atomz\"");
  EXPECT_EQ(first_error("section.data", kHeader + "Atom # sphere\n\n" + good1),
            "{file}:10:1: error: unsupported section \"Atom\"");
  EXPECT_EQ(first_error("no_box.data", "title\n\n3 atoms\n1 atom types\n\nAtoms # sphere\n\n" + good1),
            "{file}:6:1: error: the header has no \"xlo xhi\" line before the Atoms section");
}

// The whole message: the line echoed, a caret under the column, the hint.
TEST(LammpsData, ErrorEchoesTheLineWithACaretAndAHint) {
  const std::string path = write_file("typo.data", kHeader + "Atom # sphere\n");
  try {
    read_lammps_data(path);
    FAIL() << "no error";
  } catch (const UserError& error) {
    EXPECT_EQ(error.diagnostics().format(),
              path + ":10:1: error: unsupported section \"Atom\"\n"
                     "   10 | Atom # sphere\n"
                     "      | ^\n"
                     "  hint: did you mean \"Atoms\"?\n");
  }
}

TEST(LammpsData, MissingFileIsAUserError) {
  const std::string path = (fs::path(testing::TempDir()) / "no_such_bed.data").string();
  try {
    read_lammps_data(path);
    FAIL() << "no error";
  } catch (const UserError& error) {
    EXPECT_EQ(first_line(error.diagnostics().format()), path + ": error: cannot open the LAMMPS data file");
  }
}

// A 2×2×1 lattice world takes the file's particles: ids, sizes, masses and motion as written.
TEST(LammpsData, ReplacesTheLatticeParticles) {
  SettledBedParameters p;
  p.cells_x = 2;
  p.cells_y = 2;
  p.cells_z = 1;  // box 0.0042 × 0.0042 × 0.0063 m
  const std::string header =
      "title\n\n4 atoms\n1 atom types\n\n0 0.0042 xlo xhi\n0 0.0042 ylo yhi\n0 0.0063 zlo zhi\n\n"
      "Atoms # sphere\n\n";
  const std::string path = write_file("four.data", header +
      "7 1 0.002 2500 0.00105 0.00105 0.001 0 0 0\n"
      "5 1 0.002 2500 0.00315 0.00105 0.001 0 0 0\n"
      "6 1 0.0018 2400 0.00105 0.00315 0.0009 0 0 0\n"
      "8 1 0.002 2500 0.00315 0.00315 0.001 0 0 0\n"
      "\nVelocities\n\n"
      "5 0 0 -0.01 0 0 0\n6 0 0 0 1 2 3\n7 0 0 0 0 0 0\n8 0 0 0 0 0 0\n");
  World world = make_lattice_world(p);
  replace_particles(world, p, read_lammps_data(path));
  const ParticleStore& s = world.particles;
  ASSERT_EQ(s.size(), 4u);
  EXPECT_EQ(s.id[0], 5u);
  EXPECT_EQ(s.id[1], 6u);
  EXPECT_EQ(s.velocity[0], (Vec3{0, 0, -0.01}));
  EXPECT_EQ(s.radius[1], 0.0009);
  EXPECT_EQ(s.position[1], (Vec3{0.00105, 0.00315, 0.0009}));
  EXPECT_EQ(s.angular_velocity[1], (Vec3{1, 2, 3}));
  // m = ρ 4/3 π R³ from the file's density and diameter.
  EXPECT_NEAR(s.mass(1), 2400.0 * 4.0 / 3.0 * std::numbers::pi * std::pow(0.0009, 3), 1e-18);
  EXPECT_EQ(world.next_id, 9u);
  EXPECT_TRUE(world.lists_stale);
  prepare_first_step(world);
  EXPECT_EQ(world.particles.size(), 4u);  // nothing outside the domain

  // A file of another lattice (count) or another box is refused.
  World other = make_lattice_world(SettledBedParameters{});
  try {
    replace_particles(other, SettledBedParameters{}, read_lammps_data(path));
    FAIL() << "no error";
  } catch (const UserError& error) {
    EXPECT_EQ(first_line(error.diagnostics().format()),
              path + ": error: 4 atoms, but the lattice --nx 20 --ny 20 --nz 25 has 10000 particles");
  }
  SettledBedParameters wider = p;
  wider.lattice_spacing = 2.2e-3;
  World wide = make_lattice_world(wider);
  EXPECT_THROW(replace_particles(wide, wider, read_lammps_data(path)), UserError);
}

// The flowing benchmarks hand every code the same lattice through a data file: Quarry's own
// lattice written and read back must be the same particles, bit for bit (17 digits).
TEST(LammpsData, WrittenLatticeReadsBackBitForBit) {
  SettledBedParameters p;
  p.cells_x = 3;
  p.cells_y = 2;
  p.cells_z = 4;
  p.particle_radius = 2.0e-3;
  p.lattice_spacing = 5.0e-3;
  p.jitter = 1.0e-4;
  p.lift = 0.05;
  const World lattice = make_lattice_world(p);
  const std::string path = write_file("lattice.data", lammps_data_text(to_lammps_data(lattice, p)));
  const LammpsData data = read_lammps_data(path);
  EXPECT_EQ(data.atom_types, 1);
  EXPECT_EQ(data.box_hi, p.box_max());
  EXPECT_NEAR(p.box_max().z, 6 * 5.0e-3 + 0.05, 1e-15);
  World world = make_lattice_world(p);
  replace_particles(world, p, data);
  ASSERT_EQ(world.particles.size(), 24u);
  for (std::size_t i = 0; i < 24; ++i) {
    EXPECT_EQ(world.particles.id[i], lattice.particles.id[i]);
    EXPECT_EQ(world.particles.position[i], lattice.particles.position[i]);
    EXPECT_EQ(world.particles.radius[i], 2.0e-3);
    EXPECT_EQ(world.particles.mass(i), lattice.particles.mass(i));
  }
  // The lift raises every site: the lowest centre is above lift + a/2 − jitter.
  double lowest = 1.0;
  for (const Vec3& x : world.particles.position) lowest = std::min(lowest, x.z);
  EXPECT_GE(lowest, 0.05 + 2.5e-3 - 1.0e-4);
}

}  // namespace
}  // namespace quarry::bench
