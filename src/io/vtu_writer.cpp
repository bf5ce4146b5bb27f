// VTU writers (ParaView XML UnstructuredGrid, appended raw binary, UInt64 headers, little
// endian). Each array is one appended block: an 8-byte byte count, then the values.
#include "io/vtu_writer.h"
#include "io/xml_text.h"

#include <fmt/format.h>

#include <array>
#include <bit>
#include <cstdint>
#include <deque>
#include <span>
#include <stdexcept>
#include <string_view>
#include <type_traits>
#include <vector>

namespace quarry {

namespace {

constexpr std::uint8_t vtk_vertex = 1;    // VTK cell type id of a single point
constexpr std::uint8_t vtk_line = 3;      // VTK cell type id of a linear line segment
constexpr std::uint8_t vtk_triangle = 5;  // VTK cell type id of a linear triangle

// Appends `value` as little-endian bytes whatever the host byte order, so the file always
// matches its byte_order="LittleEndian" declaration.
template <class T>
void append_little_endian(std::string& out, T value) {
  static_assert(std::is_arithmetic_v<T>);
  using Bits = std::conditional_t<
      sizeof(T) == 8, std::uint64_t,
      std::conditional_t<sizeof(T) == 4, std::uint32_t,
                         std::conditional_t<sizeof(T) == 2, std::uint16_t, std::uint8_t>>>;
  auto bits = std::bit_cast<Bits>(value);
  if constexpr (std::endian::native == std::endian::little) {
    out.append(reinterpret_cast<const char*>(&bits), sizeof(T));  // the bytes as they lie
  } else {
    for (std::size_t byte = 0; byte < sizeof(T); ++byte) {
      out.push_back(static_cast<char>(bits & 0xFFu));
      bits = static_cast<Bits>(bits >> 8);
    }
  }
}

// A Vec3 as its three components: the layout its array has in memory (three packed doubles).
// Called on big-endian hosts only; a little-endian one copies whole arrays.
[[maybe_unused]] void append_little_endian(std::string& out, const Vec3& value) {
  static_assert(sizeof(Vec3) == 3 * sizeof(double));
  append_little_endian(out, value.x);
  append_little_endian(out, value.y);
  append_little_endian(out, value.z);
}

// The bytes of `count` values of T at `data` in little-endian order, for a big-endian host (a
// little-endian one writes the arrays as they lie: AppendedArrays).
template <class T>
std::string little_endian_bytes(const T* data, std::size_t count) {
  static_assert(std::is_trivially_copyable_v<T>);
  std::string payload;
  payload.reserve(count * sizeof(T));
  for (std::size_t k = 0; k < count; ++k) append_little_endian(payload, data[k]);
  return payload;
}

// Collects the XML of one Piece section and where the bytes of each appended block are; the
// file is assembled once at the end (assemble_vtu), every array copied straight from its own
// memory into a string of the file's size. Building each block as a string of its own, then
// appending it to a growing string of blocks and that to the file, copied a frame's megabyte
// three times into fresh memory (docs/performance.md, "The output stage of the rigid
// flagship"). The arrays given must outlive the assembly.
class AppendedArrays {
 public:
  // One <DataArray .../> element whose data is the `values` (components interleaved).
  template <class T>
  std::string element(std::string_view vtk_type, std::string_view name, int components,
                      std::span<const T> values, std::string_view extra_attributes = {}) {
    static_assert(std::is_trivially_copyable_v<T>);
    if constexpr (std::endian::native == std::endian::little) {
      return add(vtk_type, name, components,
                 {reinterpret_cast<const char*>(values.data()), values.size_bytes()},
                 extra_attributes);
    } else {
      return element(vtk_type, name, components, little_endian_bytes(values.data(), values.size()),
                     extra_attributes);
    }
  }
  template <class T>
  std::string element(std::string_view vtk_type, std::string_view name, int components,
                      const std::vector<T>& values, std::string_view extra_attributes = {}) {
    return element(vtk_type, name, components, std::span<const T>(values), extra_attributes);
  }
  // The same with bytes made for this file (VTK string arrays, a big-endian host's copies),
  // which the collection keeps until the assembly.
  std::string element(std::string_view vtk_type, std::string_view name, int components,
                      std::string&& payload, std::string_view extra_attributes = {}) {
    const std::string& kept = owned_.emplace_back(std::move(payload));
    return add(vtk_type, name, components, kept, extra_attributes);
  }

  // The raw appended data: each block's 8-byte byte count, then its bytes.
  std::size_t size() const { return size_; }
  void append_to(std::string& out) const {
    for (const std::string_view block : blocks_) {
      append_little_endian(out, static_cast<std::uint64_t>(block.size()));
      out.append(block);
    }
  }

 private:
  std::string add(std::string_view vtk_type, std::string_view name, int components,
                  std::string_view bytes, std::string_view extra_attributes) {
    const std::size_t offset = size_;
    blocks_.push_back(bytes);
    size_ += sizeof(std::uint64_t) + bytes.size();
    return fmt::format(
        "<DataArray type=\"{}\" Name=\"{}\" NumberOfComponents=\"{}\"{} format=\"appended\" "
        "offset=\"{}\"/>\n",
        vtk_type, xml_escaped(name), components, extra_attributes, offset);
  }

  std::vector<std::string_view> blocks_;
  std::deque<std::string> owned_;  // a deque: its strings never move
  std::size_t size_ = 0;           // bytes of the appended data so far
};

// The cells' three arrays (Int64 connectivity and offsets, UInt8 types) for cells of `corners`
// points each: the offsets and types are set here, the caller fills the connectivity.
struct CellBlocks {
  std::vector<std::int64_t> connectivity, offsets;
  std::vector<std::uint8_t> types;
  CellBlocks(std::size_t cells, int corners, std::uint8_t type)
      : connectivity(cells * corners), offsets(cells), types(cells, type) {
    for (std::size_t c = 0; c < cells; ++c)
      offsets[c] = static_cast<std::int64_t>(corners * (c + 1));
  }
  std::string elements(AppendedArrays& arrays) const {
    std::string xml = arrays.element("Int64", "connectivity", 1, connectivity);
    xml += arrays.element("Int64", "offsets", 1, offsets);
    xml += arrays.element("UInt8", "types", 1, types);
    return xml;
  }
};

std::string assemble_vtu(const std::string& field_data, std::size_t point_count,
                         std::size_t cell_count, const std::string& point_data,
                         const std::string& cell_data, const std::string& points,
                         const std::string& cells, const AppendedArrays& arrays) {
  std::string head;
  head += "<?xml version=\"1.0\"?>\n";
  head +=
      "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" "
      "header_type=\"UInt64\">\n";
  head += "<UnstructuredGrid>\n";
  head += field_data;
  head +=
      fmt::format("<Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">\n", point_count, cell_count);
  head += "<PointData>\n" + point_data + "</PointData>\n";
  head += "<CellData>\n" + cell_data + "</CellData>\n";
  head += "<Points>\n" + points + "</Points>\n";
  head += "<Cells>\n" + cells + "</Cells>\n";
  head += "</Piece>\n</UnstructuredGrid>\n";
  // Raw appended data starts right after the underscore; offsets count from there.
  head += "<AppendedData encoding=\"raw\">\n_";
  constexpr std::string_view tail = "\n</AppendedData>\n</VTKFile>\n";
  std::string file;
  file.reserve(head.size() + arrays.size() + tail.size());
  file += head;
  arrays.append_to(file);
  file += tail;
  return file;
}

template <class Array>
void require_size(const Array& array, std::size_t expected, std::string_view what) {
  if (array.size() != expected) {
    throw std::invalid_argument(
        fmt::format("VTU writer: {} has {} entries, expected {}", what, array.size(), expected));
  }
}

}  // namespace

std::string particles_vtu(const ParticleStore& particles,
                          const std::vector<std::string>& type_names,
                          const ParticleContactFields* contacts) {
  const std::size_t count = particles.size();
  require_size(particles.velocity, count, "particle velocity");
  require_size(particles.angular_velocity, count, "particle angular_velocity");
  require_size(particles.force, count, "particle force");
  require_size(particles.radius, count, "particle radius");
  require_size(particles.inv_mass, count, "particle inv_mass");
  require_size(particles.id, count, "particle id");
  require_size(particles.type, count, "particle type");
  require_size(particles.torque, count, "particle torque");
  if (contacts) {
    require_size(contacts->coordination_number, count, "particle coordination_number");
    require_size(contacts->max_overlap_ratio, count, "particle max_overlap_ratio");
  }

  static constexpr std::array<std::string_view, 11> built_in_names = {
      "id",    "type",   "type_name", "radius", "mass", "velocity", "angular_velocity",
      "force", "torque", "coordination_number", "max_overlap_ratio"};
  for (const auto& property : particles.custom) {
    require_size(property.values, count * property.components, "custom property " + property.name);
    for (const std::string_view built_in : built_in_names) {
      if (property.name == built_in) {
        throw std::invalid_argument(fmt::format(
            "VTU writer: custom property '{}' clashes with a built-in array name", built_in));
      }
    }
  }

  AppendedArrays arrays;
  std::string field_data;
  if (!type_names.empty()) {
    // VTK string arrays in binary form: the strings back to back, each ending in a NUL.
    std::string names_payload;
    for (const std::string& name : type_names) {
      names_payload += name;
      names_payload.push_back('\0');
    }
    field_data = "<FieldData>\n" +
                 arrays.element("String", "type_names", 1, std::move(names_payload),
                                fmt::format(" NumberOfTuples=\"{}\"", type_names.size())) +
                 "</FieldData>\n";
  }

  std::vector<std::int32_t> type_index(count);
  std::vector<double> mass(count);
  for (std::size_t i = 0; i < count; ++i) {
    type_index[i] = particles.type[i];
    mass[i] = 1.0 / particles.inv_mass[i];  // kg; inv_mass 0 (fixed particle) gives +inf
  }

  std::string point_data;
  point_data += arrays.element("UInt64", "id", 1, particles.id);
  point_data += arrays.element("Int32", "type", 1, type_index);
  if (!type_names.empty()) {
    // The type's name per particle as a VTK string array (NUL-terminated strings back to back):
    // ParaView colours points by a string array directly, one colour per name.
    std::string names_payload;
    for (std::size_t i = 0; i < count; ++i) {
      if (particles.type[i] >= type_names.size())
        throw std::invalid_argument(fmt::format("VTU writer: particle {} has type {} but there are {} type names", i,
                                                particles.type[i], type_names.size()));
      names_payload += type_names[particles.type[i]];
      names_payload.push_back('\0');
    }
    point_data += arrays.element("String", "type_name", 1, std::move(names_payload),
                                 fmt::format(" NumberOfTuples=\"{}\"", count));
  }
  point_data += arrays.element("Float64", "radius", 1, particles.radius);
  point_data += arrays.element("Float64", "mass", 1, mass);
  point_data += arrays.element("Float64", "velocity", 3, particles.velocity);
  point_data +=
      arrays.element("Float64", "angular_velocity", 3, particles.angular_velocity);
  point_data += arrays.element("Float64", "force", 3, particles.force);
  point_data += arrays.element("Float64", "torque", 3, particles.torque);
  if (contacts) {
    point_data += arrays.element("Int32", "coordination_number", 1,
                                 contacts->coordination_number);
    point_data += arrays.element("Float64", "max_overlap_ratio", 1,
                                 contacts->max_overlap_ratio);
  }
  for (const auto& property : particles.custom)
    point_data += arrays.element("Float64", property.name, static_cast<int>(property.components),
                                 property.values);

  const std::string points =
      arrays.element("Float64", "Points", 3, particles.position);

  CellBlocks cell_blocks(count, 1, vtk_vertex);
  for (std::size_t i = 0; i < count; ++i)
    cell_blocks.connectivity[i] = static_cast<std::int64_t>(i);
  const std::string cells = cell_blocks.elements(arrays);

  return assemble_vtu(field_data, count, count, point_data, {}, points, cells, arrays);
}

std::string contacts_vtu(std::span<const ContactLine> contacts) {
  const std::size_t count = contacts.size();
  AppendedArrays arrays;
  std::vector<Vec3> ends, normal_force, tangential_force;
  std::vector<double> magnitude, overlap;
  std::vector<std::uint8_t> kind;
  ends.reserve(2 * count);
  CellBlocks cell_blocks(count, 2, vtk_line);
  for (std::size_t c = 0; c < count; ++c) {
    const ContactLine& line = contacts[c];
    ends.push_back(line.from);
    ends.push_back(line.to);
    normal_force.push_back(line.normal_force);
    tangential_force.push_back(line.tangential_force);
    magnitude.push_back(norm(line.normal_force));
    overlap.push_back(line.overlap);
    kind.push_back(static_cast<std::uint8_t>(line.kind));
    cell_blocks.connectivity[2 * c] = static_cast<std::int64_t>(2 * c);
    cell_blocks.connectivity[2 * c + 1] = static_cast<std::int64_t>(2 * c + 1);
  }
  std::string cell_data;
  cell_data += arrays.element("Float64", "normal_force", 3, normal_force);
  cell_data += arrays.element("Float64", "tangential_force", 3, tangential_force);
  cell_data += arrays.element("Float64", "normal_force_magnitude", 1, magnitude);
  cell_data += arrays.element("Float64", "overlap", 1, overlap);
  cell_data += arrays.element("UInt8", "kind", 1, kind);
  const std::string points = arrays.element("Float64", "Points", 3, ends);
  const std::string cells = cell_blocks.elements(arrays);
  return assemble_vtu({}, ends.size(), count, {}, cell_data, points, cells, arrays);
}

std::string surface_vtu(const Surface& surface, std::span<const double> pressure,
                        std::span<const Vec3> shear, std::span<const Vec3> force,
                        std::span<const Vec3> nodal_force,
                        std::span<const double> pressure_nodal,
                        std::span<const double> pressure_smoothed,
                        std::span<const Vec3> displacement) {
  const std::size_t triangle_count = surface.triangle_count();
  const std::size_t vertex_count = surface.vertex_count();
  require_size(pressure, triangle_count, "surface pressure");
  require_size(shear, triangle_count, "surface shear");
  require_size(force, triangle_count, "surface force");
  require_size(surface.triangle_normals, triangle_count,
               "surface triangle_normals (call update_normals_and_areas)");
  if (!nodal_force.empty()) require_size(nodal_force, vertex_count, "surface nodal_force");
  if (!pressure_nodal.empty()) require_size(pressure_nodal, vertex_count, "surface pressure_nodal");
  if (!pressure_smoothed.empty()) require_size(pressure_smoothed, vertex_count, "surface pressure_smoothed");
  if (!displacement.empty()) require_size(displacement, vertex_count, "surface displacement");
  if (!surface.vertex_velocities.empty()) {
    require_size(surface.vertex_velocities, vertex_count, "surface vertex_velocities");
  }

  AppendedArrays arrays;
  std::vector<std::int64_t> element_id(triangle_count);
  std::vector<double> shear_magnitude(triangle_count);
  CellBlocks cell_blocks(triangle_count, 3, vtk_triangle);
  for (std::size_t t = 0; t < triangle_count; ++t) {
    element_id[t] = static_cast<std::int64_t>(t);
    shear_magnitude[t] = norm(shear[t]);  // Pa
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t vertex = surface.triangles[t][k];
      if (vertex >= vertex_count) {
        throw std::invalid_argument(fmt::format(
            "VTU writer: triangle {} of surface '{}' uses vertex {} but there are only {}", t,
            surface.name, vertex, vertex_count));
      }
      cell_blocks.connectivity[3 * t + k] = vertex;
    }
  }

  std::string cell_data;
  cell_data += arrays.element("Int64", "element_id", 1, element_id);
  cell_data += arrays.element("Float64", "pressure", 1, pressure);
  cell_data += arrays.element("Float64", "shear_stress", 3, shear);
  cell_data +=
      arrays.element("Float64", "shear_magnitude", 1, shear_magnitude);
  cell_data += arrays.element("Float64", "force", 3, force);
  cell_data += arrays.element("Float64", "normal", 3, surface.triangle_normals);

  std::string point_data;
  // Zeros for an optional per-vertex array never sized.
  const std::vector<Vec3> zeros(
      nodal_force.empty() || surface.vertex_velocities.empty() ? vertex_count : 0);
  const auto or_zeros = [&zeros](std::span<const Vec3> values) {
    return values.empty() ? zeros : values;
  };
  point_data += arrays.element("Float64", "vertex_force", 3, or_zeros(nodal_force));
  point_data += arrays.element("Float64", "velocity", 3, or_zeros(surface.vertex_velocities));
  if (!pressure_nodal.empty())
    point_data += arrays.element("Float64", "pressure_nodal", 1, pressure_nodal);
  if (!pressure_smoothed.empty())
    point_data += arrays.element("Float64", "pressure_smoothed", 1, pressure_smoothed);
  if (!displacement.empty())
    point_data += arrays.element("Float64", "displacement", 3, displacement);

  const std::string points = arrays.element("Float64", "Points", 3, surface.vertices);

  const std::string cells = cell_blocks.elements(arrays);

  return assemble_vtu({}, vertex_count, triangle_count, point_data, cell_data, points, cells,
                      arrays);
}

}  // namespace quarry
