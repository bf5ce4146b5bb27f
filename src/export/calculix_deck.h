// CalculiX (.inp) deck of an exported surface, written when the run ends: the triangle mesh as
// 6-node shells (S6, mid-side nodes generated) with the deck's thickness and material, node sets
// of the supports, and the nodal forces of the load history — one static step at a chosen time or
// a dynamic step driven by *AMPLITUDE curves (CalculiX User's Manual, version 2.20).
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "core/simulation_spec.h"
#include "core/vec3.h"
#include "export/nodal_history.h"

namespace quarry::fem_export {

// Quadratic triangle shells. CalculiX expands shells into solids; its linear S3 (a 6-node wedge)
// locks in bending and came out ~7× too stiff on a clamped plate, while S6 (15-node wedge)
// converges to plate theory (tests/fem_export). Corner node n = surface vertex n; mid-side nodes
// follow, numbered by first appearance over the elements in input order (deterministic).
struct ShellMesh {
  std::vector<Vec3> nodes;                                // m
  std::size_t corner_count = 0;
  // 0-based: corners a, b, c, then the mid-side nodes of edges ab, bc, ca (CalculiX S6 order).
  std::vector<std::array<std::uint32_t, 6>> elements;
};

// Builds the S6 mesh; an edge shared by two triangles gets one mid-side node.
// Cost: O(triangles log triangles).
ShellMesh quadratic_shell_mesh(std::span<const Vec3> vertices,
                               std::span<const std::array<std::uint32_t, 3>> triangles);

// 0-based indices of the `nodes` inside the closed box [lower, upper] (m), ascending.
std::vector<std::uint32_t> nodes_in_box(std::span<const Vec3> nodes, const Vec3& lower,
                                        const Vec3& upper);

// What write_calculix_deck wrote, for the run's log and for tests.
struct CalculixDeckSummary {
  std::size_t frames = 0;                    // records of the history
  std::size_t static_frame = 0;              // record used by a static step
  double static_time = 0.0;                  // s, its time
  Vec3 static_total_load;                    // N, sum of its nodal forces
  // N, the part of it applied at supported nodes: CalculiX passes it straight into the
  // supports and leaves it out of the reported reaction forces (RF).
  Vec3 static_load_on_supports;
  std::vector<std::size_t> support_node_counts;  // per spec.supports entry
};

// Writes `inp_path` (through a temporary file and a rename) for the history `history` of the
// surface `name` meshed as `mesh` (its corner nodes are the history's nodes). Node numbers are
// 1-based: n+1 for node n; element e+1 for triangle e. Throws std::runtime_error when the history
// is empty or does not match the mesh, or the file cannot be written.
// Memory: O(nodes) plus at most ~32 MB of history columns at a time, whatever the run length.
CalculixDeckSummary write_calculix_deck(const std::filesystem::path& inp_path,
                                        const std::string& name, const ShellMesh& mesh,
                                        const CalculixSpec& spec, NodalHistoryReader& history);

}  // namespace quarry::fem_export
