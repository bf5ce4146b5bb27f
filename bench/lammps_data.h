// Reader of the LAMMPS data files that the peer benchmark's settling writes (bench/peers/
// in.lmp.settle: `write_data FILE nocoeff` of an atom_style sphere system in `units si`), so
// that Quarry can start from the very particles LAMMPS and LIGGGHTS start from.
//
// Format (LAMMPS manual, read_data and write_data commands): the first line is a title and is
// skipped; then header lines "<numbers> <keyword>" ("50000 atoms", "1 atom types",
// "0 0.084 xlo xhi", ...); then sections, each a keyword line ("Atoms # sphere", "Velocities"),
// a blank line and one line per atom. For atom_style sphere:
//   Atoms:      atom-ID atom-type diameter density x y z [ix iy iz]   (image flags optional)
//   Velocities: atom-ID vx vy vz wx wy wz                             (w: angular velocity)
// "#" starts a comment anywhere. Units are those of the writing run: SI here (m, kg/m³, m/s,
// rad/s). Only atom_style sphere files of an orthogonal box are accepted.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "core/vec3.h"

namespace quarry::bench {

struct LammpsAtom {
  std::uint64_t id = 0;         // LAMMPS atom-ID (≥ 1)
  int type = 1;                 // LAMMPS atom-type (1 … atom types)
  double diameter = 0.0;        // m
  double density = 0.0;         // kg/m³
  Vec3 position;                // m, as written (write_data writes positions wrapped into the box)
  std::array<int, 3> image{};   // image flags (periodic crossings); 0 when the file has none
  Vec3 velocity;                // m/s; zero when the file has no Velocities section
  Vec3 angular_velocity;        // rad/s; zero when the file has no Velocities section
  int line = 0;                 // line of the atom in the Atoms section (1-based), for messages
};

struct LammpsData {
  std::string path;
  std::string title;             // the first line
  std::size_t atom_count = 0;    // header "N atoms"
  int atom_types = 0;            // header "N atom types"
  Vec3 box_lo, box_hi;           // m, header "xlo xhi", "ylo yhi", "zlo zhi"
  bool has_velocities = false;   // a Velocities section was read
  bool has_image_flags = false;  // the Atoms lines carry ix iy iz
  // Ascending atom-ID (write_data writes them in processor order, so the file order depends on
  // how many ranks wrote it); every ID once.
  std::vector<LammpsAtom> atoms;
};

// Reads the file line by line (no whole-file buffer: the 1M-particle bed is ~200 MB). Throws
// quarry::UserError "file:line:col: error: …" with a hint for anything it cannot read: a
// missing or unexpected header line or section, a bad number, a wrong count of values or of
// lines, an atom outside the box, a repeated or unknown atom-ID.
LammpsData read_lammps_data(const std::string& path);

// The text of an atom_style sphere data file of these atoms (Atoms and Velocities sections,
// every number with 17 significant digits, so that read_lammps_data returns the same bits), as
// LAMMPS' and LIGGGHTS' read_data take it: the flowing benchmarks' shared starting lattice.
std::string lammps_data_text(const LammpsData& data);

}  // namespace quarry::bench
