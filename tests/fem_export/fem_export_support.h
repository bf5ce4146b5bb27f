// Helpers for the FEM export tests: a flat square plate mesh, running CalculiX and mdump, and
// reading CalculiX's .dat output (displacement and reaction-force tables).
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "core/vec3.h"
#include "geometry/surface.h"
#include "io/atomic_file.h"
#include "sim/world.h"

namespace quarry::fem_export_testing {

// The square [0, side]² at z = 0 split into divisions² squares of two triangles each (normals
// +z, particles above), vertices row by row: vertex (i, j) = i·(divisions+1) + j at x = i·side/n.
inline Surface square_plate(double side, int divisions) {
  Surface plate;
  plate.name = "plate";
  const auto index = [&](int i, int j) { return static_cast<std::uint32_t>(i * (divisions + 1) + j); };
  for (int i = 0; i <= divisions; ++i)
    for (int j = 0; j <= divisions; ++j)
      plate.vertices.push_back({side * i / divisions, side * j / divisions, 0.0});
  for (int i = 0; i < divisions; ++i)
    for (int j = 0; j < divisions; ++j) {
      plate.triangles.push_back({index(i, j), index(i + 1, j), index(i + 1, j + 1)});
      plate.triangles.push_back({index(i, j), index(i + 1, j + 1), index(i, j + 1)});
    }
  plate.reference_vertices = plate.vertices;
  plate.update_normals_and_areas();
  plate.reset_loads();
  return plate;
}

// ASCII STL of a surface (for decks that read the plate as an STL file).
inline void write_ascii_stl(const Surface& surface, const std::filesystem::path& path) {
  std::ofstream out(path);
  out.precision(17);
  out << "solid plate\n";
  for (std::size_t t = 0; t < surface.triangle_count(); ++t) {
    const Vec3& n = surface.triangle_normals[t];
    out << "facet normal " << n.x << ' ' << n.y << ' ' << n.z << "\nouter loop\n";
    for (int k = 0; k < 3; ++k) {
      const Vec3& v = surface.vertices[surface.triangles[t][k]];
      out << "vertex " << v.x << ' ' << v.y << ' ' << v.z << '\n';
    }
    out << "endloop\nendfacet\n";
  }
  out << "endsolid plate\n";
}

// The deck of the settled-layer plate tests: spheres of ore (radius 9.5 mm) on a square steel
// plate of side `side` (m) read from `stl`, inside frictionless glass walls that carry no weight,
// output to `output`; `export_section` (the deck's `export:` map) is appended.
inline std::string settled_layer_deck(const std::filesystem::path& stl, const std::filesystem::path& output,
                                      double side, const std::string& export_section) {
  std::ostringstream deck;
  deck << R"(simulation:
  end_time: 0.5
  time_step: {rayleigh_fraction: 0.2}
  impact_speed: 0.5
  gravity: [0, 0, -9.81]
  domain: {min: [-0.05, -0.05, -0.1], max: [)" << side + 0.05 << ", " << side + 0.05 << R"(, 0.3]}
materials:
  - {name: ore, density: 2500, youngs_modulus: 5.0e6, poisson_ratio: 0.25}
  - {name: steel, density: 7850, youngs_modulus: 2.0e8, poisson_ratio: 0.3}
  - {name: glass, density: 2500, youngs_modulus: 2.0e8, poisson_ratio: 0.3}
interactions:
  - {materials: [ore, ore], restitution: 0.3, static_friction: 0.5, rolling_friction: 0.1}
  - {materials: [ore, steel], restitution: 0.3, static_friction: 0.5, rolling_friction: 0.1}
  - {materials: [ore, glass], restitution: 0.3, static_friction: 0.0}
particle_types:
  - {name: grain, material: ore, size: {distribution: fixed, radius: 0.0095}}
surfaces:
  - {name: plate, type: stl, file: ")" << stl.string() << R"(", material: steel, export: true}
  - {name: walls, type: box, min: [0, 0, -0.05], max: [)" << side << ", " << side << R"(, 0.2], material: glass}
output:
  directory: ")" << output.string() << R"("
  interval: 0
  plots: false
)" << export_section;
  return deck.str();
}

// Two layers of spheres of `radius` (m) and `density` (kg/m³): cells² on the square lattice of
// `pitch` p (one above the centre of each p² cell), 0.5 mm above resting on the plate, and
// (cells − 1)² in its hollows, which hold an upper sphere √(4r² − p²/2) above the lower ones,
// 1 mm above that. Ids from 1; the neighbour lists are rebuilt at the next step.
inline void add_two_layers(World& world, int cells, double pitch, double radius, double density) {
  const double upper_rise = std::sqrt(4.0 * radius * radius - 0.5 * pitch * pitch);  // m
  ParticleId id = 1;
  for (int i = 0; i < cells; ++i)
    for (int j = 0; j < cells; ++j)
      world.particles.add(id++, 0, 0, {pitch * (i + 0.5), pitch * (j + 0.5), radius + 5e-4}, {}, radius,
                          density, 0.0);
  for (int i = 1; i < cells; ++i)
    for (int j = 1; j < cells; ++j)
      world.particles.add(id++, 0, 0, {pitch * i, pitch * j, radius + upper_rise + 1e-3}, {}, radius, density,
                          0.0);
  world.next_id = id;
  world.lists_stale = true;
}

inline bool program_available(const std::string& name) {
  return std::system(("command -v " + name + " > /dev/null 2>&1").c_str()) == 0;
}

// Runs `ccx job` in `folder`; true when ccx exited with 0.
inline bool run_ccx(const std::filesystem::path& folder, const std::string& job) {
  const std::string command =
      "cd '" + folder.string() + "' && ccx " + job + " > " + job + ".log 2>&1";
  return std::system(command.c_str()) == 0;
}

// Numbers of the first data line after the line containing `title` in a CalculiX .dat file
// (e.g. "total force" → fx fy fz; "displacements" → node ux uy uz).
inline std::vector<double> dat_row_after(const std::filesystem::path& dat, const std::string& title) {
  std::ifstream in(dat);
  std::string line;
  bool found = false;
  while (std::getline(in, line)) {
    if (!found) {
      found = line.find(title) != std::string::npos;
      continue;
    }
    std::istringstream row(line);
    std::vector<double> numbers;
    double value;
    while (row >> value) numbers.push_back(value);
    if (!numbers.empty()) return numbers;
  }
  return {};
}

inline std::string read_text(const std::filesystem::path& path) {
  return read_file(path).value_or("");
}

// Inserts `cards` before the deck's *END STEP (extra output requests for a test).
inline void add_before_end_step(const std::filesystem::path& inp, const std::string& cards) {
  std::string text = read_text(inp);
  const std::size_t at = text.rfind("*END STEP");
  text.insert(at, cards);
  std::ofstream(inp, std::ios::binary | std::ios::trunc) << text;
}

// Resident set size of this process (bytes), from /proc/self/statm.
inline long resident_bytes() {
  std::ifstream statm("/proc/self/statm");
  long pages_total = 0, pages_resident = 0;
  statm >> pages_total >> pages_resident;
  return pages_resident * 4096;
}

}  // namespace quarry::fem_export_testing
