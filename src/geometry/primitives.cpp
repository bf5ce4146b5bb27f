// Primitive meshes: each is generated as a triangle soup with the required orientation and
// welded by the same routine as STL files, so shared edges share vertices.
#include "geometry/primitives.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "core/diagnostics.h"
#include "geometry/vertex_welder.h"

namespace quarry {

namespace {

// Two unit vectors u, v with u × v = unit_normal (right-handed frame). The helper axis is the
// coordinate axis least aligned with the normal, so the frame is well conditioned and fixed.
void perpendicular_frame(const Vec3& unit_normal, Vec3& u, Vec3& v) {
  const double ax = std::abs(unit_normal.x), ay = std::abs(unit_normal.y),
               az = std::abs(unit_normal.z);
  const Vec3 helper =
      (ax <= ay && ax <= az) ? Vec3{1, 0, 0} : (ay <= az ? Vec3{0, 1, 0} : Vec3{0, 0, 1});
  u = normalized(cross(helper, unit_normal));
  v = cross(unit_normal, u);
}

// Appends a parallelogram origin + s·edge_s + t·edge_t (s, t ∈ [0, 1]) split into
// divisions_s × divisions_t cells of two triangles whose normal is along edge_s × edge_t.
void append_grid(std::vector<Vec3>& corners, const Vec3& origin, const Vec3& edge_s,
                 const Vec3& edge_t, int divisions_s, int divisions_t) {
  auto node = [&](int i, int j) {
    return origin + edge_s * (static_cast<double>(i) / divisions_s) +
           edge_t * (static_cast<double>(j) / divisions_t);
  };
  for (int j = 0; j < divisions_t; ++j)
    for (int i = 0; i < divisions_s; ++i) {
      const Vec3 a = node(i, j), b = node(i + 1, j), c = node(i + 1, j + 1), d = node(i, j + 1);
      corners.insert(corners.end(), {a, b, c, a, c, d});
    }
}

void require(bool condition, const std::string& message, const std::string& hint = {}) {
  if (!condition) throw UserError(SourceLocation{}, message, hint);
}

}  // namespace

Surface make_plane(const Vec3& point, const Vec3& normal, double size, int divisions) {
  require(size > 0.0, fmt::format("plane size must be positive (got {} m)", size));
  require(divisions >= 1, fmt::format("plane divisions must be at least 1 (got {})", divisions));
  require(norm(normal) > 0.0, "plane normal is the zero vector",
          "give the direction particles are on");
  const Vec3 unit_normal = normalized(normal);
  Vec3 u, v;
  perpendicular_frame(unit_normal, u, v);
  std::vector<Vec3> corners;
  corners.reserve(6 * static_cast<std::size_t>(divisions) * divisions);
  append_grid(corners, point - (u + v) * (0.5 * size), u * size, v * size, divisions, divisions);
  Surface surface = surface_from_triangle_soup(corners, "plane");
  // Round-off in the cross products could tilt a normal by 1e-16; the plane is exactly flat.
  for (auto& n : surface.triangle_normals) n = unit_normal;
  return surface;
}

Surface make_box(const Vec3& lo, const Vec3& hi, int divisions) {
  require(hi.x > lo.x && hi.y > lo.y && hi.z > lo.z,
          fmt::format("box max ({}, {}, {}) must exceed min ({}, {}, {}) in every component", hi.x,
                      hi.y, hi.z, lo.x, lo.y, lo.z));
  require(divisions >= 1, fmt::format("box divisions must be at least 1 (got {})", divisions));
  const Vec3 dx{hi.x - lo.x, 0, 0}, dy{0, hi.y - lo.y, 0}, dz{0, 0, hi.z - lo.z};
  std::vector<Vec3> corners;
  corners.reserve(36 * static_cast<std::size_t>(divisions) * divisions);
  // For each face: edge_s × edge_t must point into the box.
  append_grid(corners, lo, dy, dz, divisions, divisions);       // x = lo.x, normal +x
  append_grid(corners, lo + dx, dz, dy, divisions, divisions);  // x = hi.x, normal −x
  append_grid(corners, lo, dz, dx, divisions, divisions);       // y = lo.y, normal +y
  append_grid(corners, lo + dy, dx, dz, divisions, divisions);  // y = hi.y, normal −y
  append_grid(corners, lo, dx, dy, divisions, divisions);       // z = lo.z, normal +z
  append_grid(corners, lo + dz, dy, dx, divisions, divisions);  // z = hi.z, normal −z
  return surface_from_triangle_soup(corners, "box");
}

namespace {

// The cylinder's side is split along the axis into rings about one facet wide (close to square
// triangles), each cap into concentric rings of the same width.
struct CylinderRings {
  double facet_width;  // m, chord of one segment
  int along;           // rings along the side
  int cap;             // rings in each cap
};

CylinderRings cylinder_rings(double radius, double length, int segments) {
  const double facet_width = 2.0 * radius * std::sin(std::numbers::pi / segments);
  return {facet_width, std::clamp(static_cast<int>(std::lround(length / facet_width)), 1, 100000),
          std::max(1, static_cast<int>(std::lround(radius / facet_width)))};
}

}  // namespace

std::int64_t cylinder_triangle_count(double radius, double length, int segments, bool capped) {
  const CylinderRings rings = cylinder_rings(radius, length, segments);
  // Side: 2 per segment and ring; each cap: a fan (1 per segment) and 2 per segment per outer ring.
  const std::int64_t side = 2 * std::int64_t{segments} * rings.along;
  const std::int64_t cap = std::int64_t{segments} * (1 + 2 * std::int64_t{rings.cap - 1});
  return side + (capped ? 2 * cap : 0);
}

Surface make_cylinder(const Vec3& base, const Vec3& axis, double radius, double length,
                      int segments, bool capped, bool inward) {
  require(radius > 0.0, fmt::format("cylinder radius must be positive (got {} m)", radius));
  require(length > 0.0, fmt::format("cylinder length must be positive (got {} m)", length));
  require(norm(axis) > 0.0, "cylinder axis is the zero vector");
  require(segments >= 3,
          fmt::format("cylinder needs at least 3 segments around (got {})", segments));
  const Vec3 unit_axis = normalized(axis);
  Vec3 u, v;
  perpendicular_frame(unit_axis, u, v);  // u × v = unit_axis
  const CylinderRings rings = cylinder_rings(radius, length, segments);
  const int rings_along = rings.along;
  auto around = [&](int k) {  // unit radial direction of the k-th meridian
    const double angle = 2.0 * std::numbers::pi * (k % segments) / segments;
    return u * std::cos(angle) + v * std::sin(angle);
  };
  auto side_node = [&](int k, int ring) {
    return base + around(k) * radius + unit_axis * (length * ring / rings_along);
  };
  std::vector<Vec3> corners;
  // Side: a = (k, r), b = (k+1, r), c = (k+1, r+1), d = (k, r+1); (b − a) × (d − a) points
  // outward because (tangent) × (axis) = radial for the frame u × v = axis.
  for (int ring = 0; ring < rings_along; ++ring)
    for (int k = 0; k < segments; ++k) {
      const Vec3 a = side_node(k, ring), b = side_node(k + 1, ring), c = side_node(k + 1, ring + 1),
                 d = side_node(k, ring + 1);
      if (inward)
        corners.insert(corners.end(), {a, c, b, a, d, c});
      else
        corners.insert(corners.end(), {a, b, c, a, c, d});
    }
  if (capped) {
    const int cap_rings = rings.cap;
    for (int end = 0; end < 2; ++end) {
      const Vec3 centre = base + unit_axis * (end == 0 ? 0.0 : length);
      // Winding (k, k+1) around the axis gives a normal along +axis; the inside of the closed
      // cylinder is +axis from the base cap and −axis from the far cap.
      const bool normal_along_axis = (end == 0) == inward;
      auto cap_node = [&](int k, int ring) {
        return centre + around(k) * (radius * ring / cap_rings);
      };
      auto emit = [&](const Vec3& a, const Vec3& b, const Vec3& c) {
        if (normal_along_axis)
          corners.insert(corners.end(), {a, b, c});
        else
          corners.insert(corners.end(), {a, c, b});
      };
      for (int k = 0; k < segments; ++k) {
        emit(centre, cap_node(k, 1), cap_node(k + 1, 1));
        for (int ring = 1; ring < cap_rings; ++ring) {
          const Vec3 a = cap_node(k, ring), b = cap_node(k + 1, ring),
                     c = cap_node(k + 1, ring + 1), d = cap_node(k, ring + 1);
          emit(a, c, b);
          emit(a, d, c);
        }
      }
    }
  }
  return surface_from_triangle_soup(corners, "cylinder");
}

}  // namespace quarry
