// Validation of a ShellModel: every user error reported with the item's index and value.
#include "fem/shell_model.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include <fmt/format.h>

#include "fem/shell_element.h"

namespace quarry::fem {
namespace {

[[noreturn]] void fail(const std::string& message) { throw std::invalid_argument(message); }

}  // namespace

ElementShape element_shape(const std::array<Vec3, 4>& x, int node_count) {
  ElementShape shape;
  double longest = 0.0;  // m²
  for (int i = 0; i < node_count; ++i) {
    longest = std::max(longest, norm2(x[(i + 1) % node_count] - x[i]));
  }
  shape.longest_edge = std::sqrt(longest);
  shape.area = element_area(x, node_count);
  if (!(shape.area > 1e-12 * longest)) {
    shape.kind = ElementShape::degenerate;
    return shape;
  }
  if (node_count == 4) {
    // Each corner's triangle must keep the orientation of the whole (no bow-tie, convex).
    const ElementFrame frame = element_frame(x, 4);
    for (int i = 0; i < 4; ++i) {
      const Vec3 corner = cross(x[(i + 1) % 4] - x[i], x[(i + 3) % 4] - x[i]);
      if (!(dot(corner, frame.e3) > 0.0)) {
        shape.kind = ElementShape::not_convex;
        shape.corner = i;
        return shape;
      }
    }
  }
  return shape;
}

void validate_shell_model(const ShellModel& model) {
  const auto node_count = static_cast<std::int64_t>(model.nodes.size());
  for (std::size_t i = 0; i < model.nodes.size(); ++i) {
    const Vec3& p = model.nodes[i];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
      fail(fmt::format("shell model: node {} has a non-finite position", i));
    }
  }
  for (std::size_t m = 0; m < model.materials.size(); ++m) {
    const ShellMaterial& mat = model.materials[m];
    if (!(mat.youngs_modulus > 0.0) || !std::isfinite(mat.youngs_modulus)) {
      fail(fmt::format("shell model: material {}: Young's modulus {} Pa must be > 0", m,
                       mat.youngs_modulus));
    }
    if (!(mat.poisson_ratio > -1.0 && mat.poisson_ratio < 0.5)) {
      fail(fmt::format("shell model: material {}: Poisson's ratio {} must lie in (-1, 0.5)", m,
                       mat.poisson_ratio));
    }
    if (!(mat.density > 0.0) || !std::isfinite(mat.density)) {
      fail(fmt::format("shell model: material {}: density {} kg/m³ must be > 0", m, mat.density));
    }
    if (!(mat.yield_stress >= 0.0) || !(mat.hardening_modulus >= 0.0) ||
        !std::isfinite(mat.hardening_modulus)) {
      fail(fmt::format("shell model: material {}: yield stress {} Pa and hardening modulus {} Pa "
                       "must be ≥ 0",
                       m, mat.yield_stress, mat.hardening_modulus));
    }
  }
  for (std::size_t s = 0; s < model.sections.size(); ++s) {
    const ShellSection& sec = model.sections[s];
    if (!(sec.thickness > 0.0) || !std::isfinite(sec.thickness)) {
      fail(fmt::format("shell model: section {}: thickness {} m must be > 0", s, sec.thickness));
    }
    const int minimum = sec.rule == ThicknessRule::gauss ? 1 : 2;
    if (sec.integration_points < minimum || sec.integration_points > 16) {
      fail(fmt::format("shell model: section {}: {} through-thickness points; {} to 16 allowed",
                       s, sec.integration_points, minimum));
    }
    if (sec.material < 0 || sec.material >= static_cast<int>(model.materials.size())) {
      fail(fmt::format("shell model: section {}: material {} does not exist ({} materials)", s,
                       sec.material, model.materials.size()));
    }
  }
  for (std::size_t e = 0; e < model.elements.size(); ++e) {
    const ShellElement& el = model.elements[e];
    if (el.node_count != 3 && el.node_count != 4) {
      fail(fmt::format("shell model: element {}: {} nodes; shells have 3 or 4", e, el.node_count));
    }
    if (el.section < 0 || el.section >= static_cast<int>(model.sections.size())) {
      fail(fmt::format("shell model: element {}: section {} does not exist ({} sections)", e,
                       el.section, model.sections.size()));
    }
    std::array<Vec3, 4> x{};
    for (int i = 0; i < el.node_count; ++i) {
      if (el.nodes[i] < 0 || el.nodes[i] >= node_count) {
        fail(fmt::format("shell model: element {}: node {} does not exist ({} nodes)", e,
                         el.nodes[i], node_count));
      }
      for (int j = 0; j < i; ++j) {
        if (el.nodes[i] == el.nodes[j]) {
          fail(fmt::format("shell model: element {}: node {} appears twice (degenerate element; "
                           "give a triangle node_count 3)",
                           e, el.nodes[i]));
        }
      }
      x[i] = model.nodes[el.nodes[i]];
    }
    const ElementShape shape = element_shape(x, el.node_count);
    if (shape.kind == ElementShape::degenerate) {
      fail(fmt::format("shell model: element {}: degenerate (area {} m², longest edge {} m); "
                       "check the node order and coincident nodes",
                       e, shape.area, shape.longest_edge));
    }
    if (shape.kind == ElementShape::not_convex) {
      fail(fmt::format("shell model: element {}: not convex at its node {} (node {})", e,
                       shape.corner, el.nodes[shape.corner]));
    }
  }
  for (std::size_t b = 0; b < model.boundary_conditions.size(); ++b) {
    const BoundaryCondition& bc = model.boundary_conditions[b];
    if ((bc.dofs & ~dof::all) != 0) {
      fail(fmt::format("shell model: boundary condition {}: DOF mask {} has bits beyond the six "
                       "DOFs",
                       b, static_cast<int>(bc.dofs)));
    }
    for (const std::int32_t n : bc.nodes) {
      if (n < 0 || n >= node_count) {
        fail(fmt::format("shell model: boundary condition {}: node {} does not exist ({} nodes)",
                         b, n, node_count));
      }
    }
    for (const double value : bc.velocity) {
      if (!std::isfinite(value)) {
        fail(fmt::format("shell model: boundary condition {}: non-finite velocity", b));
      }
    }
  }
}

std::vector<std::vector<std::int32_t>> support_groups(const ShellModel& model) {
  const std::size_t nodes = model.nodes.size();
  std::vector<char> held(nodes, 0);
  for (const BoundaryCondition& bc : model.boundary_conditions)
    if (bc.dofs != 0)
      for (const std::int32_t n : bc.nodes) held[static_cast<std::size_t>(n)] = 1;
  // Union–find over the held nodes, joined along element edges; the root is the smallest node.
  std::vector<std::int32_t> parent(nodes);
  for (std::size_t n = 0; n < nodes; ++n) parent[n] = static_cast<std::int32_t>(n);
  const auto root = [&parent](std::int32_t n) {
    auto up = [&parent](std::int32_t k) -> std::int32_t& { return parent[static_cast<std::size_t>(k)]; };
    while (up(n) != n) {
      up(n) = up(up(n));  // path halving
      n = up(n);
    }
    return n;
  };
  for (const ShellElement& e : model.elements)
    for (int i = 0; i < e.node_count; ++i) {
      const std::int32_t a = e.nodes[static_cast<std::size_t>(i)], b = e.nodes[static_cast<std::size_t>((i + 1) % e.node_count)];
      if (!held[static_cast<std::size_t>(a)] || !held[static_cast<std::size_t>(b)]) continue;
      const std::int32_t ra = root(a), rb = root(b);
      if (ra != rb) parent[static_cast<std::size_t>(std::max(ra, rb))] = std::min(ra, rb);
    }
  std::vector<std::vector<std::int32_t>> groups;
  std::vector<std::int32_t> group_of_root(nodes, -1);
  for (std::size_t n = 0; n < nodes; ++n) {
    if (!held[n]) continue;
    const auto r = static_cast<std::size_t>(root(static_cast<std::int32_t>(n)));
    if (group_of_root[r] < 0) {
      group_of_root[r] = static_cast<std::int32_t>(groups.size());
      groups.emplace_back();
    }
    groups[static_cast<std::size_t>(group_of_root[r])].push_back(static_cast<std::int32_t>(n));
  }
  return groups;
}

WarpedQuads warped_quads(const ShellModel& model) {
  WarpedQuads out;
  for (std::size_t e = 0; e < model.elements.size(); ++e) {
    const ShellElement& element = model.elements[e];
    if (element.node_count != 4) continue;
    std::array<Vec3, 4> x;
    for (int k = 0; k < 4; ++k) x[k] = model.nodes[static_cast<std::size_t>(element.nodes[k])];
    const double warpage = quad_warpage_degrees(x);
    if (!(warpage > kWarpageLimitDegrees)) continue;
    ++out.count;
    if (warpage > out.worst_degrees) {
      out.worst_degrees = warpage;
      out.worst_element = static_cast<int>(e);
    }
  }
  return out;
}

}  // namespace quarry::fem
