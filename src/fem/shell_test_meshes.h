// Test helpers: flat rectangular shell meshes (quads, or each quad split into two triangles)
// and node selections. Used by the fem tests only.
#pragma once

#include <cmath>
#include <cstdint>
#include <functional>
#include <vector>

#include "core/vec3.h"
#include "fem/shell_element.h"
#include "fem/shell_model.h"

namespace quarry::fem::testing {

enum class MeshKind { quads, triangles };

inline ShellMaterial steel(double yield_stress = 0.0, double hardening = 0.0) {
  return {210e9, 0.3, 7850.0, yield_stress, hardening};
}

// nx × ny cells on [0, length_x] × [0, length_y] in the plane z = 0; node (i, j) has index
// j (nx + 1) + i. Triangles: each cell cut along alternating diagonals ((i + j) even: 0-2).
inline ShellModel rectangle(int nx, int ny, double length_x, double length_y, double thickness,
                            MeshKind kind = MeshKind::quads, int points = 5,
                            ThicknessRule rule = ThicknessRule::lobatto,
                            ShellMaterial material = steel()) {
  ShellModel model;
  for (int j = 0; j <= ny; ++j) {
    for (int i = 0; i <= nx; ++i) {
      model.nodes.push_back({length_x * i / nx, length_y * j / ny, 0.0});
    }
  }
  auto id = [nx](int i, int j) { return static_cast<std::int32_t>(j * (nx + 1) + i); };
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      const std::int32_t a = id(i, j), b = id(i + 1, j), c = id(i + 1, j + 1), d = id(i, j + 1);
      if (kind == MeshKind::quads) {
        model.elements.push_back({{a, b, c, d}, 4, 0});
      } else if ((i + j) % 2 == 0) {
        model.elements.push_back({{a, b, c, 0}, 3, 0});
        model.elements.push_back({{a, c, d, 0}, 3, 0});
      } else {
        model.elements.push_back({{a, b, d, 0}, 3, 0});
        model.elements.push_back({{b, c, d, 0}, 3, 0});
      }
    }
  }
  model.sections.push_back({thickness, points, rule, 0});
  model.materials.push_back(material);
  return model;
}

// Indices of the nodes whose position satisfies `select`.
inline std::vector<std::int32_t> nodes_where(const ShellModel& model,
                                             const std::function<bool(const Vec3&)>& select) {
  std::vector<std::int32_t> out;
  for (std::size_t n = 0; n < model.nodes.size(); ++n) {
    if (select(model.nodes[n])) out.push_back(static_cast<std::int32_t>(n));
  }
  return out;
}

inline bool near(double a, double b) { return std::abs(a - b) < 1e-9; }

// One element's history, owned: `points` through-thickness points, all zero, or filled by the
// caller (3 stresses and one plastic strain per point, 3 shear and 5 hourglass resultants).
struct History {
  std::vector<double> stress, plastic, shear, hourglass;
  static History zero(int points) {
    return {std::vector<double>(3 * points, 0.0), std::vector<double>(points, 0.0),
            std::vector<double>(3, 0.0), std::vector<double>(5, 0.0)};
  }
  ElementState state() { return {stress.data(), plastic.data(), shear.data(), hourglass.data()}; }
};

// Rodrigues: p cos + (k × p) sin + k (k·p)(1 − cos), k a unit axis.
inline Vec3 rotate(const Vec3& p, const Vec3& axis, double angle) {
  return p * std::cos(angle) + cross(axis, p) * std::sin(angle) +
         axis * (dot(axis, p) * (1.0 - std::cos(angle)));
}

}  // namespace quarry::fem::testing
