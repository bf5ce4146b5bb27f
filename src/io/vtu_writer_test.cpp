// Tests of the VTU writers: a tiny reader in this file parses the XML header and the appended
// raw blocks (UInt64 byte counts, little endian) and checks counts and values bit-exactly.
#include "io/vtu_writer.h"

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

struct ArrayInfo {
  std::string type;
  int components = 1;
  std::string payload;  // raw little-endian bytes of the block
};

// Reads what a VTU consumer needs: Piece counts and every appended DataArray by Name
// (a name used twice, e.g. "force" in point and cell data, is keyed "section/name").
struct VtuContent {
  std::size_t point_count = 0, cell_count = 0;
  std::map<std::string, ArrayInfo> arrays;
};

std::uint64_t read_uint64_little_endian(const std::string& bytes, std::size_t at) {
  std::uint64_t value = 0;
  for (int byte = 7; byte >= 0; --byte) {
    value =
        (value << 8) | static_cast<unsigned char>(bytes.at(at + static_cast<std::size_t>(byte)));
  }
  return value;
}

std::string attribute(const std::string& tag, const std::string& name) {
  const std::string key = " " + name + "=\"";
  const std::size_t start = tag.find(key);
  if (start == std::string::npos) return {};
  const std::size_t value_start = start + key.size();
  return tag.substr(value_start, tag.find('"', value_start) - value_start);
}

VtuContent read_vtu(const std::string& file) {
  const std::string appended_marker = "<AppendedData encoding=\"raw\">\n_";
  const std::size_t marker = file.find(appended_marker);
  if (marker == std::string::npos) throw std::runtime_error("no raw AppendedData");
  const std::string xml = file.substr(0, marker);
  const std::size_t data_start = marker + appended_marker.size();
  EXPECT_NE(xml.find("byte_order=\"LittleEndian\" header_type=\"UInt64\""), std::string::npos);

  VtuContent content;
  const std::size_t piece = xml.find("<Piece ");
  if (piece == std::string::npos) throw std::runtime_error("no Piece");
  const std::string piece_tag = xml.substr(piece, xml.find('>', piece) - piece);
  content.point_count = std::stoull(attribute(piece_tag, "NumberOfPoints"));
  content.cell_count = std::stoull(attribute(piece_tag, "NumberOfCells"));

  // Walk the elements in order, remembering the enclosing section for repeated names.
  std::size_t end_of_blocks = data_start;
  std::string section;
  for (std::size_t at = xml.find('<'); at != std::string::npos; at = xml.find('<', at + 1)) {
    const std::size_t tag_end = xml.find('>', at);
    const std::string tag = xml.substr(at, tag_end - at + 1);
    for (const char* name : {"PointData", "CellData", "Points", "Cells", "FieldData"}) {
      if (tag == std::string("<") + name + ">") section = name;
    }
    if (tag.rfind("<DataArray ", 0) != 0) continue;
    EXPECT_EQ(attribute(tag, "format"), "appended") << tag;
    ArrayInfo info;
    info.type = attribute(tag, "type");
    info.components = std::stoi(attribute(tag, "NumberOfComponents"));
    const std::size_t block = data_start + std::stoull(attribute(tag, "offset"));
    const std::uint64_t byte_count = read_uint64_little_endian(file, block);
    info.payload = file.substr(block + 8, byte_count);
    EXPECT_EQ(info.payload.size(), byte_count) << "block runs past the end of the file";
    end_of_blocks = std::max<std::size_t>(end_of_blocks, block + 8 + byte_count);
    std::string name = attribute(tag, "Name");
    if (content.arrays.count(name) != 0) name = section + "/" + name;
    content.arrays[name] = std::move(info);
  }
  // The last block ends exactly where the closing tags begin: no stray or missing bytes.
  EXPECT_EQ(file.substr(end_of_blocks), "\n</AppendedData>\n</VTKFile>\n");
  return content;
}

template <class T>
std::vector<T> values_of(const ArrayInfo& info) {
  EXPECT_EQ(info.payload.size() % sizeof(T), 0u);
  std::vector<T> values(info.payload.size() / sizeof(T));
  // The test machine is little endian (x86-64, arm64), so a byte copy decodes the file.
  std::memcpy(values.data(), info.payload.data(), info.payload.size());
  return values;
}

std::vector<Vec3> vectors_of(const ArrayInfo& info) {
  EXPECT_EQ(info.type, "Float64");
  EXPECT_EQ(info.components, 3);
  const std::vector<double> flat = values_of<double>(info);
  std::vector<Vec3> vectors;
  for (std::size_t k = 0; k + 2 < flat.size(); k += 3)
    vectors.push_back({flat[k], flat[k + 1], flat[k + 2]});
  return vectors;
}

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
  const VtuContent vtu = read_vtu(surface_vtu(surface, pressure, shear, force, surface.vertex_force));
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
}

TEST(SurfaceVtu, RejectsMismatchedSizesAndBadVertexIndices) {
  Surface surface = unit_square();
  const std::vector<double> pressure(2, 0.0);
  const std::vector<Vec3> zeros(2);
  EXPECT_THROW((void)surface_vtu(surface, std::vector<double>(1, 0.0), zeros, zeros, {}),
               std::invalid_argument);
  EXPECT_THROW((void)surface_vtu(surface, pressure, zeros, zeros, std::vector<Vec3>(3)), std::invalid_argument);
  surface.triangles[1][2] = 9;
  EXPECT_THROW((void)surface_vtu(surface, pressure, zeros, zeros, {}), std::invalid_argument);
}

}  // namespace
}  // namespace quarry
