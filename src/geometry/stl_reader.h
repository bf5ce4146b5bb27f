// STL input/output: reads ASCII and binary STL (detected by content) into a welded Surface,
// writes binary STL. Used when the world is built, not inside the time step.
#pragma once

#include <string>
#include <vector>

#include "core/vec3.h"
#include "geometry/surface.h"

namespace quarry {

// Reads an STL file. Every coordinate is multiplied by `scale` (e.g. 0.001 for a file in mm)
// and then `offset` (m) is added. Coincident vertices (within 1e-9 × bounding-box diagonal) are
// welded. Facets without an area (a corner repeated after welding, or three corners on a line)
// and second copies of a facet (the same three corners in either orientation: two walls in one
// place would double every contact) are removed, and so are the vertices only they used; `notes`
// (if given) gets a line counting them. Triangle t of the result is the t-th facet kept, in file
// order (element ids). The result has reference_vertices = vertices, zero vertex velocities,
// normals (right-hand rule of the file's vertex order; the facet normal written in the file is
// ignored), areas and zeroed loads. Surface::name is left empty.
// Binary vs ASCII: a file whose size is exactly 84 + 50·n (n = the count in its header) is
// binary even if it begins with "solid"; otherwise a file made only of text, or one beginning
// with "solid" and holding "facet" and "vertex" (a name in UTF-8), is ASCII.
// Throws UserError: missing/unreadable file, empty mesh, non-finite coordinates, a truncated
// binary file (location line 0, the message names the byte offset), a bad ASCII token
// (location = line and column of that token), or no facet with an area left. Cost: O(n log n)
// in the facets.
Surface read_stl(const std::string& path, double scale, const Vec3& offset,
                 std::vector<std::string>* notes = nullptr);

// What drop_degenerate_and_duplicate_facets removed.
struct StlCleanup {
  std::size_t degenerate = 0;  // facets without an area
  std::size_t duplicates = 0;  // second copies of a facet
};
// Removes `surface`'s facets without an area and the second copies of a facet (same corner
// indices in any order), then the vertices no facet uses; the rest keep their order.
StlCleanup drop_degenerate_and_duplicate_facets(Surface& surface);

// Writes `surface` (its current vertices, as float32) as a binary STL with one facet per
// triangle in triangle order, facet normal = triangle_normals (recomputed if missing).
// Throws UserError if the file cannot be written.
void write_stl_binary(const std::string& path, const Surface& surface);

}  // namespace quarry
