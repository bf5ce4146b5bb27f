// A closed triangle mesh of a sphere for tests and examples: the icosahedron subdivided `levels`
// times (each triangle into four, the new vertices pushed onto the sphere), outward-facing,
// 20 · 4^levels triangles. Header-only: plain data, no dependency beyond Vec3.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <utility>
#include <vector>

#include "core/vec3.h"

namespace quarry {

struct TriangleMesh {
  std::vector<Vec3> vertices;                           // m
  std::vector<std::array<std::uint32_t, 3>> triangles;  // counter-clockwise seen from outside
};

inline TriangleMesh icosphere(const Vec3& centre, double radius, int levels) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<Vec3> v = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                         {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  for (Vec3& p : v) p = p / std::sqrt(dot(p, p));
  std::vector<std::array<std::uint32_t, 3>> faces = {
      {0, 11, 5}, {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
      {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
      {3, 8, 9},  {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (int level = 0; level < levels; ++level) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> middle;
    const auto midpoint = [&](std::uint32_t a, std::uint32_t b) {
      const auto key = std::minmax(a, b);
      if (const auto found = middle.find(key); found != middle.end()) return found->second;
      const Vec3 m = (v[a] + v[b]) * 0.5;
      v.push_back(m / std::sqrt(dot(m, m)));
      return middle[key] = static_cast<std::uint32_t>(v.size() - 1);
    };
    std::vector<std::array<std::uint32_t, 3>> finer;
    for (const auto& f : faces) {
      const std::uint32_t a = midpoint(f[0], f[1]), b = midpoint(f[1], f[2]), c = midpoint(f[2], f[0]);
      finer.insert(finer.end(), {{f[0], a, c}, {f[1], b, a}, {f[2], c, b}, {a, b, c}});
    }
    faces = std::move(finer);
  }
  TriangleMesh mesh;
  for (const Vec3& p : v) mesh.vertices.push_back(centre + p * radius);
  mesh.triangles = std::move(faces);
  return mesh;
}

}  // namespace quarry
