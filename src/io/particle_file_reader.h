// Readers of the particle files a run may start from (deck `particles:` section, issue #20): a
// CSV table `x,y,z,radius,type[,vx,vy,vz,wx,wy,wz,id]`, and a particle frame written by an
// earlier Quarry run (io/vtu_writer.h: ParaView XML UnstructuredGrid, appended raw
// little-endian data, UInt64 block headers). Types are matched by name against the deck's.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/diagnostics.h"
#include "core/simulation_spec.h"

namespace quarry {

// Reads the CSV table at `path` (named `path` in messages). The header names the columns, in any
// order: x, y, z (m), radius (m, > 0), type (a name of `type_names`) are required; vx, vy, vz
// (m/s) and wx, wy, wz (rad/s) are optional, each triple complete or absent (absent: zero);
// id (integer ≥ 1, unique in the file) is optional (absent: new ids). Blank lines are skipped.
// Every problem is added to `problems` as `path:line:col` with a hint (at most 20, then the
// reading stops); the particles read so far are returned either way, with `source` set to
// `source` and `line` to their line. Cost: one pass over the text.
std::vector<InitialParticle> read_particle_csv(const std::string& path,
                                               const std::vector<std::string>& type_names,
                                               std::uint32_t source, Diagnostics& problems);

// Reads a particle frame (`particles_NNNNNN.vtu`) written by io/vtu_writer.h: positions (Points),
// radius, type with the field data type_names (matched by name), and, when present, id,
// velocity and angular_velocity; any other array is ignored, so frames with more arrays read
// too. Problems (not such a file, a missing array, a type name the deck does not define, a
// radius ≤ 0, a non-finite value, a repeated id) go to `problems` at the file's line:col of the
// XML element concerned; `line` of each particle is 0. Values are copied bit for bit.
// Cost: one pass over the file.
std::vector<InitialParticle> read_particle_vtu(const std::string& path,
                                               const std::vector<std::string>& type_names,
                                               std::uint32_t source, Diagnostics& problems);

}  // namespace quarry
