// Primitive wall meshes (plane, box, cylinder) generated as welded triangle surfaces, built
// once when the world is set up. Every result has reference_vertices = vertices, zero vertex
// velocities, normals, areas and zeroed loads, exactly like a surface read from STL.
#pragma once

#include <cstdint>

#include "core/vec3.h"
#include "geometry/surface.h"

namespace quarry {

// A square of side `size` (m) centred at `point` (m), perpendicular to `normal` (any length > 0),
// split into divisions × divisions squares of 2 triangles. Every triangle normal equals
// normalized(normal): the side the particles are on. Throws UserError if size ≤ 0,
// divisions < 1 or normal is zero. Triangles: 2·divisions².
Surface make_plane(const Vec3& point, const Vec3& normal, double size, int divisions = 1);

// The closed box [lo, hi] (m, hi > lo in every component), each of its 6 faces split into
// divisions × divisions rectangles of 2 triangles; normals point INTO the box (particles live
// inside). Faces in the order −x, +x, −y, +y, −z, +z. Triangles: 12·divisions².
Surface make_box(const Vec3& lo, const Vec3& hi, int divisions = 1);

// The side of the cylinder of `radius` (m) around the axis from `base` (m) along `axis` (need not
// be unit) for `length` (m), with `segments` (≥ 3) facets around. The side is also split along the
// axis into max(1, round(length / facet width)) rings so that its triangles are close to square.
// capped adds the two end discs (concentric rings, a fan at the centre). inward = true: normals
// point towards the axis and into the closed volume (particles inside, e.g. a drum); false:
// normals point outwards (particles outside, e.g. a roller or pin). Throws UserError on
// radius ≤ 0, length ≤ 0, zero axis or segments < 3.
Surface make_cylinder(const Vec3& base, const Vec3& axis, double radius, double length, int segments,
                      bool capped, bool inward = true);

// The number of triangles make_cylinder makes for these values, without making them (the
// memory estimate of `check`). Pre: radius, length > 0, segments ≥ 3.
std::int64_t cylinder_triangle_count(double radius, double length, int segments, bool capped);

}  // namespace quarry
