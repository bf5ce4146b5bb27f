// Tests of the VTU writers: a tiny reader (io/vtu_test_reader.h) parses the XML header and the
// appended raw blocks (UInt64 byte counts, little endian) and checks counts and values bit-exactly.
#include "io/vtu_writer.h"
#include "io/vtu_test_reader.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace quarry {
namespace {

using vtu_test::read_vtu;
using vtu_test::values_of;
using vtu_test::vectors_of;
using vtu_test::VtuContent;

ParticleStore three_particles() {
  ParticleStore particles;
  particles.register_custom("temperature", 1, 293.15, "K");
  particles.register_custom("fluid_velocity", 3, 0.0, "m/s");
  particles.add(101, 0, 0, {0.1, 0.2, 0.3}, {1.0, -2.0, 0.5}, 0.005, 2500.0, 0.0);
  particles.add(7, 1, 0, {-1.0 / 3.0, 0.0, 1e-9}, {}, 0.004, 2500.0, 0.0);
  particles.add(~std::uint64_t{0}, 1, 1, {5.0, 6.0, 7.0}, {}, 0.003, 7800.0, 0.1);
  particles.angular_velocity[1] = {10.0, 20.0, 30.0};
  particles.force[2] = {0.0, 0.0, -9.81};
  particles.custom[0].values = {300.0, 310.5, -1.0};
  particles.custom[1].values = {1, 2, 3, 4, 5, 6, 7, 8, 9};
  return particles;
}

TEST(ParticlesVtu, RoundTripsEveryArrayExactly) {
  const ParticleStore particles = three_particles();
  const VtuContent vtu = read_vtu(particles_vtu(particles, {"gravel", "sand"}));
  EXPECT_EQ(vtu.point_count, 3u);
  EXPECT_EQ(vtu.cell_count, 3u);

  EXPECT_EQ(vtu.arrays.at("id").type, "UInt64");
  EXPECT_EQ(values_of<std::uint64_t>(vtu.arrays.at("id")), particles.id);
  EXPECT_EQ(vtu.arrays.at("type").type, "Int32");
  EXPECT_EQ(values_of<std::int32_t>(vtu.arrays.at("type")), (std::vector<std::int32_t>{0, 1, 1}));
  EXPECT_EQ(values_of<double>(vtu.arrays.at("radius")), particles.radius);
  const std::vector<double> mass = values_of<double>(vtu.arrays.at("mass"));
  for (std::size_t i = 0; i < 3; ++i) EXPECT_EQ(mass[i], particles.mass(i));
  EXPECT_EQ(vectors_of(vtu.arrays.at("Points")), particles.position);
  EXPECT_EQ(vectors_of(vtu.arrays.at("velocity")), particles.velocity);
  EXPECT_EQ(vectors_of(vtu.arrays.at("angular_velocity")), particles.angular_velocity);
  EXPECT_EQ(vectors_of(vtu.arrays.at("force")), particles.force);
  EXPECT_EQ(values_of<double>(vtu.arrays.at("temperature")), particles.custom[0].values);
  EXPECT_EQ(vtu.arrays.at("fluid_velocity").components, 3);  // a vector property, one tuple per particle
  EXPECT_EQ(values_of<double>(vtu.arrays.at("fluid_velocity")), particles.custom[1].values);

  // One VTK_VERTEX (type 1) per particle.
  EXPECT_EQ(values_of<std::int64_t>(vtu.arrays.at("connectivity")),
            (std::vector<std::int64_t>{0, 1, 2}));
  EXPECT_EQ(values_of<std::int64_t>(vtu.arrays.at("offsets")),
            (std::vector<std::int64_t>{1, 2, 3}));
  EXPECT_EQ(values_of<std::uint8_t>(vtu.arrays.at("types")), (std::vector<std::uint8_t>{1, 1, 1}));

  // Type names as a VTK string array: NUL-terminated strings back to back.
  EXPECT_EQ(vtu.arrays.at("type_names").type, "String");
  EXPECT_EQ(vtu.arrays.at("type_names").payload, std::string("gravel\0sand\0", 12));
  // And per particle, for colouring by name.
  EXPECT_EQ(vtu.arrays.at("type_name").type, "String");
  EXPECT_EQ(vtu.arrays.at("type_name").payload, std::string("gravel\0sand\0sand\0", 17));
}

TEST(ParticlesVtu, WritesTorqueAndTheFramesContactFields) {
  ParticleStore particles = three_particles();
  particles.torque[1] = {0.5, -0.25, 1e-7};
  ParticleContactFields fields;
  fields.coordination_number = {0, 3, 1};
  fields.max_overlap_ratio = {0.0, 0.0125, 1.0 / 3.0};
  const VtuContent vtu = read_vtu(particles_vtu(particles, {"gravel", "sand"}, &fields));
  EXPECT_EQ(vectors_of(vtu.arrays.at("torque")), particles.torque);
  EXPECT_EQ(vtu.arrays.at("coordination_number").type, "Int32");
  EXPECT_EQ(values_of<std::int32_t>(vtu.arrays.at("coordination_number")), fields.coordination_number);
  EXPECT_EQ(values_of<double>(vtu.arrays.at("max_overlap_ratio")), fields.max_overlap_ratio);
  // Without contact fields the two arrays are left out rather than written as zeros.
  const VtuContent without = read_vtu(particles_vtu(particles, {}));
  EXPECT_EQ(without.arrays.count("coordination_number"), 0u);
  EXPECT_EQ(without.arrays.count("torque"), 1u);
  fields.max_overlap_ratio.pop_back();
  EXPECT_THROW((void)particles_vtu(particles, {}, &fields), std::invalid_argument);
}

TEST(ContactsVtu, OneLineOfTwoOwnPointsPerContact) {
  std::vector<ContactLine> lines(2);
  lines[0] = {{0, 0, 0.01}, {0, 0, 0.029}, {0, 0, 2.5}, {0.1, 0, 0}, 1e-3, ContactLineKind::particle_particle};
  lines[1] = {{1, 2, 3}, {1, 2, 2.99}, {0, 0, 7}, {}, 1e-4, ContactLineKind::particle_surface};
  const VtuContent vtu = read_vtu(contacts_vtu(lines));
  EXPECT_EQ(vtu.point_count, 4u);
  EXPECT_EQ(vtu.cell_count, 2u);
  EXPECT_EQ(vectors_of(vtu.arrays.at("Points")),
            (std::vector<Vec3>{lines[0].from, lines[0].to, lines[1].from, lines[1].to}));
  EXPECT_EQ(vectors_of(vtu.arrays.at("normal_force")), (std::vector<Vec3>{{0, 0, 2.5}, {0, 0, 7}}));
  EXPECT_EQ(vectors_of(vtu.arrays.at("tangential_force")), (std::vector<Vec3>{{0.1, 0, 0}, {}}));
  EXPECT_EQ(values_of<double>(vtu.arrays.at("normal_force_magnitude")), (std::vector<double>{2.5, 7}));
  EXPECT_EQ(values_of<double>(vtu.arrays.at("overlap")), (std::vector<double>{1e-3, 1e-4}));
  EXPECT_EQ(values_of<std::uint8_t>(vtu.arrays.at("kind")), (std::vector<std::uint8_t>{0, 1}));
  // VTK_LINE is cell type 3.
  EXPECT_EQ(values_of<std::int64_t>(vtu.arrays.at("connectivity")), (std::vector<std::int64_t>{0, 1, 2, 3}));
  EXPECT_EQ(values_of<std::int64_t>(vtu.arrays.at("offsets")), (std::vector<std::int64_t>{2, 4}));
  EXPECT_EQ(values_of<std::uint8_t>(vtu.arrays.at("types")), (std::vector<std::uint8_t>{3, 3}));
  const VtuContent none = read_vtu(contacts_vtu({}));
  EXPECT_EQ(none.cell_count, 0u);
}

TEST(ParticlesVtu, EmptyStoreGivesAValidEmptyPiece) {
  const VtuContent vtu = read_vtu(particles_vtu(ParticleStore{}, {}));
  EXPECT_EQ(vtu.point_count, 0u);
  EXPECT_EQ(vtu.cell_count, 0u);
  EXPECT_TRUE(vtu.arrays.at("Points").payload.empty());
  EXPECT_EQ(vtu.arrays.count("type_names"), 0u);
}

TEST(ParticlesVtu, RejectsInconsistentStoresAndClashingNames) {
  ParticleStore broken = three_particles();
  broken.velocity.pop_back();
  EXPECT_THROW((void)particles_vtu(broken, {}), std::invalid_argument);
  ParticleStore clashing = three_particles();
  clashing.register_custom("radius");
  EXPECT_THROW((void)particles_vtu(clashing, {}), std::invalid_argument);
}

// A unit square in the z = 0 plane split into two triangles (element ids 0 and 1).
Surface unit_square() {
  Surface surface;
  surface.name = "floor";
  surface.vertices = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  surface.reference_vertices = surface.vertices;
  surface.triangles = {{0, 1, 2}, {0, 2, 3}};
  surface.update_normals_and_areas();
  surface.reset_loads();
  surface.vertex_force = {{0, 0, -1}, {0, 0, -2}, {0.5, 0, -3}, {0, 0, -4}};
  surface.vertex_velocities = {{0.1, 0, 0}, {0.1, 0, 0}, {0.1, 0, 0}, {0.1, 0, 0}};
  return surface;
}

TEST(SurfaceVtu, RoundTripsCellAndPointData) {
  const Surface surface = unit_square();
  const std::vector<double> pressure = {1200.0, 0.25};                   // Pa
  const std::vector<Vec3> shear = {{3.0, 4.0, 0.0}, {0.0, -1e-3, 0}};    // Pa
  const std::vector<Vec3> force = {{1.5, 2.0, -600.0}, {0, 0, -0.125}};  // N
  const std::vector<double> nodal = {10.0, 20.0, 30.0, 40.0};        // Pa
  const std::vector<double> smoothed = {11.0, 21.0, 31.0, 41.5};     // Pa
  const VtuContent vtu =
      read_vtu(surface_vtu(surface, pressure, shear, force, surface.vertex_force, nodal, smoothed));
  EXPECT_EQ(values_of<double>(vtu.arrays.at("pressure_nodal")), nodal);
  EXPECT_EQ(values_of<double>(vtu.arrays.at("pressure_smoothed")), smoothed);
  EXPECT_EQ(vtu.point_count, 4u);
  EXPECT_EQ(vtu.cell_count, 2u);
  EXPECT_EQ(vtu.arrays.at("element_id").type, "Int64");
  EXPECT_EQ(values_of<std::int64_t>(vtu.arrays.at("element_id")),
            (std::vector<std::int64_t>{0, 1}));
  EXPECT_EQ(values_of<double>(vtu.arrays.at("pressure")), pressure);
  EXPECT_EQ(vectors_of(vtu.arrays.at("shear_stress")), shear);
  // |(3, 4, 0)| = 5 Pa exactly.
  EXPECT_EQ(values_of<double>(vtu.arrays.at("shear_magnitude")), (std::vector<double>{5.0, 1e-3}));
  EXPECT_EQ(vectors_of(vtu.arrays.at("force")), force);
  EXPECT_EQ(vectors_of(vtu.arrays.at("normal")), (std::vector<Vec3>{{0, 0, 1}, {0, 0, 1}}));
  EXPECT_EQ(vectors_of(vtu.arrays.at("vertex_force")), surface.vertex_force);
  EXPECT_EQ(vectors_of(vtu.arrays.at("velocity")), surface.vertex_velocities);
  EXPECT_EQ(vectors_of(vtu.arrays.at("Points")), surface.vertices);
  // VTK_TRIANGLE is type 5; connectivity keeps the input vertex order.
  EXPECT_EQ(values_of<std::int64_t>(vtu.arrays.at("connectivity")),
            (std::vector<std::int64_t>{0, 1, 2, 0, 2, 3}));
  EXPECT_EQ(values_of<std::int64_t>(vtu.arrays.at("offsets")), (std::vector<std::int64_t>{3, 6}));
  EXPECT_EQ(values_of<std::uint8_t>(vtu.arrays.at("types")), (std::vector<std::uint8_t>{5, 5}));
}

TEST(SurfaceVtu, UnsetPerVertexLoadsAreWrittenAsZeros) {
  Surface surface = unit_square();
  surface.vertex_velocities.clear();
  const std::vector<double> pressure(2, 0.0);
  const std::vector<Vec3> zeros(2);
  const VtuContent vtu = read_vtu(surface_vtu(surface, pressure, zeros, zeros, {}));
  EXPECT_EQ(vectors_of(vtu.arrays.at("vertex_force")), std::vector<Vec3>(4));
  EXPECT_EQ(vectors_of(vtu.arrays.at("velocity")), std::vector<Vec3>(4));
  EXPECT_EQ(vtu.arrays.count("pressure_smoothed"), 0u);  // written only when given
}

TEST(SurfaceVtu, RejectsMismatchedSizesAndBadVertexIndices) {
  Surface surface = unit_square();
  const std::vector<double> pressure(2, 0.0);
  const std::vector<Vec3> zeros(2);
  EXPECT_THROW((void)surface_vtu(surface, std::vector<double>(1, 0.0), zeros, zeros, {}),
               std::invalid_argument);
  EXPECT_THROW((void)surface_vtu(surface, pressure, zeros, zeros, std::vector<Vec3>(3)), std::invalid_argument);
  EXPECT_THROW((void)surface_vtu(surface, pressure, zeros, zeros, {}, {}, std::vector<double>(3)),
               std::invalid_argument);
  surface.triangles[1][2] = 9;
  EXPECT_THROW((void)surface_vtu(surface, pressure, zeros, zeros, {}), std::invalid_argument);
}

}  // namespace
}  // namespace quarry
