// STL input/output: reads ASCII and binary STL (detected by content) into a welded Surface,
// writes binary STL. Used when the world is built, not inside the time step.
#pragma once

#include <string>

#include "core/vec3.h"
#include "geometry/surface.h"

namespace quarry {

// Reads an STL file. Every coordinate is multiplied by `scale` (e.g. 0.001 for a file in mm)
// and then `offset` (m) is added. Coincident vertices (within 1e-9 × bounding-box diagonal) are
// welded; triangle t of the result is the t-th facet of the file (element ids = file order);
// degenerate facets are kept with zero area. The result has reference_vertices = vertices, zero
// vertex velocities, normals (right-hand rule of the file's vertex order; the facet normal
// written in the file is ignored), areas and zeroed loads. Surface::name is left empty.
// Binary vs ASCII: a file whose size is exactly 84 + 50·n (n = the count in its header) is
// binary even if it begins with "solid"; otherwise a file made only of text is ASCII.
// Throws UserError: missing/unreadable file, empty mesh, non-finite coordinates, a truncated
// binary file (location line 0, the message names the byte offset), or a bad ASCII token
// (location = line and column of that token). Cost: O(n) in the file size.
Surface read_stl(const std::string& path, double scale, const Vec3& offset);

// Writes `surface` (its current vertices, as float32) as a binary STL with one facet per
// triangle in triangle order, facet normal = triangle_normals (recomputed if missing).
// Throws UserError if the file cannot be written.
void write_stl_binary(const std::string& path, const Surface& surface);

}  // namespace quarry
