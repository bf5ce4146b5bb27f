// VTU writers: particles and surfaces as ParaView XML UnstructuredGrid files (VTK file-format
// documentation, "XML File Formats"), binary appended raw data, UInt64 block headers, little
// endian. Called by the output stage at the end of a step when an output is due.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "core/particle_store.h"
#include "core/vec3.h"
#include "geometry/surface.h"

namespace quarry {

// Per-particle contact figures of one frame (sim/frame_contacts.h computes them).
struct ParticleContactFields {
  std::vector<std::int32_t> coordination_number;  // contacts of the particle, surfaces included
  std::vector<double> max_overlap_ratio;          // largest overlap / own radius (1), 0 if none
};

// One VTK_VERTEX cell per particle at its position (m). Point data: id (UInt64), type (Int32,
// index into `type_names`), type_name (String, when `type_names` is given), radius (m), mass (kg), velocity (m/s), angular_velocity (rad/s),
// force (N), torque (N·m), coordination_number (Int32) and max_overlap_ratio (1) when
// `contacts` is given, then every custom property (Float64, under its own name). Field data:
// type_names (String), so ParaView users can map type indices to names.
// Pre: all arrays of `particles` (and of `contacts`) have size() entries; custom names differ
// from the built-in names; every type index has a name (when names are given). Throws std::invalid_argument otherwise. Cost: O(n), about 170 bytes
// per particle.
std::string particles_vtu(const ParticleStore& particles,
                          const std::vector<std::string>& type_names,
                          const ParticleContactFields* contacts = nullptr);

// One contact of a frame as a line: particle–particle from centre i to centre j, particle–surface
// from the centre to the contact point on the surface.
enum class ContactLineKind : std::uint8_t { particle_particle = 0, particle_surface = 1 };
struct ContactLine {
  Vec3 from, to;          // m
  Vec3 normal_force;      // N on the particle at `from` (along the contact normal)
  Vec3 tangential_force;  // N on the particle at `from` (in the tangent plane)
  double overlap = 0.0;   // m
  ContactLineKind kind = ContactLineKind::particle_particle;
};

// One VTK_LINE cell per contact (two points of its own each). Cell data: normal_force (N, 3),
// tangential_force (N, 3), normal_force_magnitude (N), overlap (m), kind (UInt8: 0
// particle–particle, 1 particle–surface). Cost: O(contacts), about 150 bytes per contact.
std::string contacts_vtu(std::span<const ContactLine> contacts);

// One VTK_TRIANGLE cell per triangle of `surface` at its current vertices (m). Cell data:
// element_id (Int64, = triangle index = input mesh order), pressure (Pa), shear_stress (Pa, 3),
// shear_magnitude (Pa), force (N, 3), normal (unit, 3). Point data: vertex_force (N, 3, from
// `nodal_force`), velocity (m/s, 3, from surface.vertex_velocities).
// `pressure`, `shear`, `force`, `nodal_force` are the window means of a LoadWindow. When
// given (vertex_count() entries), `pressure_nodal` and `pressure_smoothed` (Pa, from
// geometry/surface_pressure.h) and `displacement` (m, 3) become point data of those names.
// Pre: the three per-triangle spans have triangle_count() entries; triangle_normals has
// triangle_count() entries; nodal_force and vertex_velocities have vertex_count() entries or are
// empty (then zeros are written); every vertex index is in range. Throws std::invalid_argument
// otherwise. Cost: O(triangles + vertices).
std::string surface_vtu(const Surface& surface, std::span<const double> pressure,
                        std::span<const Vec3> shear, std::span<const Vec3> force,
                        std::span<const Vec3> nodal_force,
                        std::span<const double> pressure_nodal = {},
                        std::span<const double> pressure_smoothed = {},
                        std::span<const Vec3> displacement = {});

}  // namespace quarry
