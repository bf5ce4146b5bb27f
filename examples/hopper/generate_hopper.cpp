// Writes hopper.stl: a conical hopper (45° half-angle wall... see below) with a cylindrical
// bin above it, open at the outlet and at the top, normals pointing inward (towards the bulk).
// Geometry (m): outlet radius 0.03 at z = 0, cone up to radius 0.12 at z = 0.12 (half-angle
// from the vertical 36.9°), cylinder radius 0.12 from z = 0.12 to z = 0.35.
#include <cmath>
#include <numbers>
#include <string>

#include "geometry/stl_reader.h"

namespace {

using quarry::Surface;
using quarry::Vec3;

// Adds a ring of `segments` vertices at height z and radius r; returns the first index.
std::uint32_t add_ring(Surface& s, double z, double r, int segments) {
  const auto first = static_cast<std::uint32_t>(s.vertices.size());
  for (int k = 0; k < segments; ++k) {
    const double a = 2.0 * std::numbers::pi * k / segments;
    s.vertices.push_back({r * std::cos(a), r * std::sin(a), z});
  }
  return first;
}

// Joins two rings with triangles whose normals point towards the axis.
void join(Surface& s, std::uint32_t lower, std::uint32_t upper, int segments) {
  for (int k = 0; k < segments; ++k) {
    const std::uint32_t a = lower + k, b = lower + (k + 1) % segments;
    const std::uint32_t c = upper + k, d = upper + (k + 1) % segments;
    s.triangles.push_back({a, c, b});
    s.triangles.push_back({b, c, d});
  }
}

}  // namespace

int main(int argc, char** argv) {
  const std::string path = argc > 1 ? argv[1] : "hopper.stl";
  const int segments = 64;
  Surface s;
  std::uint32_t previous = add_ring(s, 0.0, 0.03, segments);
  for (int k = 1; k <= 6; ++k) {  // cone in 6 bands
    const double t = k / 6.0;
    const std::uint32_t ring = add_ring(s, 0.12 * t, 0.03 + 0.09 * t, segments);
    join(s, previous, ring, segments);
    previous = ring;
  }
  for (int k = 1; k <= 8; ++k) {  // cylinder in 8 bands
    const std::uint32_t ring = add_ring(s, 0.12 + 0.23 * k / 8.0, 0.12, segments);
    join(s, previous, ring, segments);
    previous = ring;
  }
  s.reference_vertices = s.vertices;
  s.update_normals_and_areas();
  quarry::write_stl_binary(path, s);
  return 0;
}
