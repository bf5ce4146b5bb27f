// CalculiX deck writer (calculix_deck.h). Card syntax after the CalculiX User's Manual 2.20:
// *NODE, *ELEMENT TYPE=S6, *NSET, *MATERIAL/*ELASTIC/*DENSITY, *SHELL SECTION, *BOUNDARY,
// *AMPLITUDE, *STEP/*STATIC or *DYNAMIC, *CLOAD, *NODE PRINT TOTALS=ONLY, *NODE FILE, *EL FILE.
#include "export/calculix_deck.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <stdexcept>

namespace quarry::fem_export {

namespace {

// At most this many bytes of history columns are held while writing amplitudes (B).
constexpr std::size_t kColumnBudgetBytes = std::size_t{32} << 20;

// CalculiX set names: letters, digits and underscores, upper case (the reader folds case).
std::string set_name(const std::string& name) {
  std::string result;
  for (char c : name)
    result += std::isalnum(static_cast<unsigned char>(c)) ? static_cast<char>(std::toupper(c)) : '_';
  return result.empty() ? std::string("SET") : result;
}

double component(const Vec3& v, int axis) { return v[axis]; }

}  // namespace

ShellMesh quadratic_shell_mesh(std::span<const Vec3> vertices,
                               std::span<const std::array<std::uint32_t, 3>> triangles) {
  ShellMesh mesh;
  mesh.nodes.assign(vertices.begin(), vertices.end());
  mesh.corner_count = vertices.size();
  std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> midside_of_edge;
  mesh.elements.reserve(triangles.size());
  for (const auto& triangle : triangles) {
    std::array<std::uint32_t, 6> element{triangle[0], triangle[1], triangle[2], 0, 0, 0};
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = triangle[k], b = triangle[(k + 1) % 3];
      const auto key = std::minmax(a, b);
      auto [entry, inserted] =
          midside_of_edge.emplace(key, static_cast<std::uint32_t>(mesh.nodes.size()));
      if (inserted) mesh.nodes.push_back(0.5 * (vertices[a] + vertices[b]));
      element[3 + k] = entry->second;
    }
    mesh.elements.push_back(element);
  }
  return mesh;
}

std::vector<std::uint32_t> nodes_in_box(std::span<const Vec3> nodes, const Vec3& lower,
                                        const Vec3& upper) {
  Aabb box;
  box.lo = lower;
  box.hi = upper;
  std::vector<std::uint32_t> inside;
  for (std::size_t n = 0; n < nodes.size(); ++n)
    if (box.contains(nodes[n])) inside.push_back(static_cast<std::uint32_t>(n));
  return inside;
}

CalculixDeckSummary write_calculix_deck(const std::filesystem::path& inp_path,
                                        const std::string& name, const ShellMesh& mesh,
                                        const CalculixSpec& spec, NodalHistoryReader& history) {
  const auto fail = [&](const std::string& what) {
    throw std::runtime_error("CalculiX deck " + inp_path.string() + ": " + what);
  };
  if (history.node_count() != mesh.corner_count) fail("history and mesh have different nodes");
  if (history.frame_count() == 0) fail("no export interval has ended yet; nothing to load");
  CalculixDeckSummary summary;
  summary.frames = history.frame_count();
  const std::vector<double> times = history.times();  // s

  std::filesystem::path temporary = inp_path;
  temporary += ".tmp";
  std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
  if (!out) fail("cannot open " + temporary.string());
  const std::string element_set = "E" + set_name(name);
  const bool dynamic = spec.analysis.value == CalculixAnalysis::dynamic;

  out << "*HEADING\n"
      << fmt::format("Quarry DEM loads on surface {} ({} export intervals, S6 shells)\n", name,
                     summary.frames)
      << "** Units: SI (m, N, Pa, kg, s). Node n+1 = mesh vertex n (corners first, then the\n"
      << "** generated mid-side nodes); element e+1 = input triangle e.\n";
  out << "*NODE, NSET=NALL\n";
  for (std::size_t n = 0; n < mesh.nodes.size(); ++n)
    out << fmt::format("{}, {:.12g}, {:.12g}, {:.12g}\n", n + 1, mesh.nodes[n].x, mesh.nodes[n].y,
                       mesh.nodes[n].z);
  out << fmt::format("*ELEMENT, TYPE=S6, ELSET={}\n", element_set);
  for (std::size_t e = 0; e < mesh.elements.size(); ++e) {
    const auto& el = mesh.elements[e];
    out << fmt::format("{}, {}, {}, {}, {}, {}, {}\n", e + 1, el[0] + 1, el[1] + 1, el[2] + 1,
                       el[3] + 1, el[4] + 1, el[5] + 1);
  }

  // Supports: node sets (16 numbers a line at most, as CalculiX reads them) and their DOFs.
  std::vector<char> supported(mesh.nodes.size(), 0);
  for (const SupportSpec& support : spec.supports) {
    const std::vector<std::uint32_t> nodes = nodes_in_box(mesh.nodes, support.min.value, support.max.value);
    summary.support_node_counts.push_back(nodes.size());
    if (nodes.empty()) continue;
    out << fmt::format("*NSET, NSET={}\n", set_name(support.name.value));
    for (std::size_t k = 0; k < nodes.size(); ++k) {
      supported[nodes[k]] = 1;
      out << nodes[k] + 1 << ((k + 1) % 16 == 0 || k + 1 == nodes.size() ? ",\n" : ", ");
    }
  }
  out << "*MATERIAL, NAME=SHELL_MATERIAL\n*ELASTIC\n"
      << fmt::format("{:.12g}, {:.12g}\n", spec.youngs_modulus.value, spec.poisson_ratio.value);
  if (spec.density.value > 0.0) out << fmt::format("*DENSITY\n{:.12g}\n", spec.density.value);
  out << fmt::format("*SHELL SECTION, ELSET={}, MATERIAL=SHELL_MATERIAL\n{:.12g}\n", element_set,
                     spec.thickness.value);
  bool any_support = false;
  for (std::size_t s = 0; s < spec.supports.size(); ++s) {
    if (summary.support_node_counts[s] == 0) continue;
    if (!any_support) out << "*BOUNDARY\n";
    any_support = true;
    const int last_dof = spec.supports[s].fix.value == SupportFixity::clamped ? 6 : 3;
    out << fmt::format("{}, 1, {}\n", set_name(spec.supports[s].name.value), last_dof);
  }

  // Static load case: the record whose interval contains the chosen time (the first record
  // ending at or after it), else the last record.
  summary.static_frame = times.size() - 1;
  if (!dynamic && spec.static_time) {
    const auto later = std::lower_bound(times.begin(), times.end(),
                                        spec.static_time->value - 1e-9 * std::max(1.0, spec.static_time->value));
    if (later != times.end()) summary.static_frame = static_cast<std::size_t>(later - times.begin());
  }
  summary.static_time = times[summary.static_frame];
  std::vector<Vec3> static_loads;
  history.read_frame(summary.static_frame, static_loads);
  for (std::size_t n = 0; n < static_loads.size(); ++n) {
    summary.static_total_load += static_loads[n];
    if (supported[n]) summary.static_load_on_supports += static_loads[n];
  }

  // Dynamic: one amplitude per loaded node DOF (value = force in N at each record's time),
  // read a block of nodes at a time so memory stays bounded for any number of records.
  std::vector<std::pair<std::uint32_t, int>> amplified;  // node, dof (1..3)
  if (dynamic) {
    const std::size_t per_node = std::max<std::size_t>(1, summary.frames * sizeof(Vec3));
    const std::size_t block = std::max<std::size_t>(1, kColumnBudgetBytes / per_node);
    std::vector<Vec3> columns;
    for (std::size_t first = 0; first < mesh.corner_count; first += block) {
      const std::size_t count = std::min(block, mesh.corner_count - first);
      history.read_nodes(first, count, columns);
      for (std::size_t k = 0; k < count; ++k) {
        for (int axis = 0; axis < 3; ++axis) {
          bool loaded = false;
          for (std::size_t f = 0; f < summary.frames && !loaded; ++f)
            loaded = component(columns[f * count + k], axis) != 0.0;
          if (!loaded) continue;
          const auto node = static_cast<std::uint32_t>(first + k);
          amplified.emplace_back(node, axis + 1);
          out << fmt::format("*AMPLITUDE, NAME=F{}_{}\n", node + 1, axis + 1);
          for (std::size_t f = 0; f < summary.frames; ++f)
            out << fmt::format("{:.9g}, {:.9g}\n", times[f], component(columns[f * count + k], axis));
        }
      }
    }
  }

  if (dynamic) {
    // Direct integration over the whole history; the first increment is one export interval.
    const double first_increment = summary.frames > 1 ? times[1] - times[0] : times[0];
    out << "*STEP, INC=1000000\n*DYNAMIC, DIRECT\n"
        << fmt::format("{:.9g}, {:.9g}\n", first_increment, times.back());
    for (const auto& [node, dof] : amplified)
      out << fmt::format("*CLOAD, AMPLITUDE=F{}_{}\n{}, {}, 1.0\n", node + 1, dof, node + 1, dof);
  } else {
    out << fmt::format("** Static load case: the export interval ending at t = {:.9g} s (record {}).\n",
                       summary.static_time, summary.static_frame)
        << fmt::format("** Total nodal load {:.9g}, {:.9g}, {:.9g} N; of it {:.9g}, {:.9g}, {:.9g} N sit\n",
                       summary.static_total_load.x, summary.static_total_load.y,
                       summary.static_total_load.z, summary.static_load_on_supports.x,
                       summary.static_load_on_supports.y, summary.static_load_on_supports.z)
        << "** on supported nodes and go straight into the supports (not part of RF below).\n"
        << "*STEP\n*STATIC\n*CLOAD\n";
    for (std::size_t n = 0; n < static_loads.size(); ++n)
      for (int axis = 0; axis < 3; ++axis)
        if (component(static_loads[n], axis) != 0.0)
          out << fmt::format("{}, {}, {:.12g}\n", n + 1, axis + 1, component(static_loads[n], axis));
  }
  out << "*NODE FILE\nU\n*EL FILE\nS\n";
  for (std::size_t s = 0; s < spec.supports.size(); ++s)
    if (summary.support_node_counts[s] > 0)
      out << fmt::format("*NODE PRINT, NSET={}, TOTALS=ONLY\nRF\n", set_name(spec.supports[s].name.value));
  out << "*END STEP\n";
  out.close();
  if (!out) fail("write failed (disk full?)");
  std::filesystem::rename(temporary, inp_path);
  return summary;
}

}  // namespace quarry::fem_export
