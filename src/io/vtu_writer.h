// VTU writers: particles and surfaces as ParaView XML UnstructuredGrid files (VTK file-format
// documentation, "XML File Formats"), binary appended raw data, UInt64 block headers, little
// endian. Called by the output stage at the end of a step when an output is due.
#pragma once

#include <span>
#include <string>
#include <vector>

#include "core/particle_store.h"
#include "core/vec3.h"
#include "geometry/surface.h"

namespace quarry {

// One VTK_VERTEX cell per particle at its position (m). Point data: id (UInt64), type (Int32,
// index into `type_names`), radius (m), mass (kg), velocity (m/s), angular_velocity (rad/s),
// force (N), then every custom property (Float64, under its own name). Field data:
// type_names (String), so ParaView users can map type indices to names.
// Pre: all arrays of `particles` have size() entries; custom names differ from the built-in
// names. Throws std::invalid_argument otherwise. Cost: O(n), about 130 bytes per particle.
std::string particles_vtu(const ParticleStore& particles,
                          const std::vector<std::string>& type_names);

// One VTK_TRIANGLE cell per triangle of `surface` at its current vertices (m). Cell data:
// element_id (Int64, = triangle index = input mesh order), pressure (Pa), shear_stress (Pa, 3),
// shear_magnitude (Pa), force (N, 3), normal (unit, 3). Point data: vertex_force (N, 3, from
// `nodal_force`), velocity (m/s, 3, from surface.vertex_velocities).
// `pressure`, `shear`, `force`, `nodal_force` are the window means of a LoadWindow.
// Pre: the three per-triangle spans have triangle_count() entries; triangle_normals has
// triangle_count() entries; nodal_force and vertex_velocities have vertex_count() entries or are
// empty (then zeros are written); every vertex index is in range. Throws std::invalid_argument
// otherwise. Cost: O(triangles + vertices).
std::string surface_vtu(const Surface& surface, std::span<const double> pressure,
                        std::span<const Vec3> shear, std::span<const Vec3> force,
                        std::span<const Vec3> nodal_force);

}  // namespace quarry
