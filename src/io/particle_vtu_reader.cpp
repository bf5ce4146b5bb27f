// A particle frame of an earlier run read back (particle_file_reader.h): exactly the format
// io/vtu_writer.cpp writes (XML header, then `<AppendedData encoding="raw">` and `_`, then one
// block per array: a UInt64 byte count and the little-endian values). Arrays are found by
// name; the ones not needed are skipped.
#include <fmt/format.h>

#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <optional>
#include <string_view>
#include <unordered_map>

#include "io/atomic_file.h"
#include "io/particle_file_reader.h"

namespace quarry {

namespace {

constexpr std::string_view kNotAFrame =
    "give a particles_NNNNNN.vtu frame written by Quarry (binary appended raw data), or a CSV "
    "table";

struct ArrayTag {
  std::string name, type;
  int components = 1;
  std::uint64_t offset = 0;
  std::size_t position = 0;  // of the tag in the text
};

// The value of attribute `name` in the tag text, or nullopt.
std::optional<std::string> attribute(std::string_view tag, std::string_view name) {
  std::size_t from = 0;
  while (true) {
    const std::size_t at = tag.find(name, from);
    if (at == std::string_view::npos) return std::nullopt;
    from = at + name.size();
    const bool starts_word =
        at > 0 && (tag[at - 1] == ' ' || tag[at - 1] == '\n' || tag[at - 1] == '\t');
    if (!starts_word || tag.substr(from, 2) != "=\"") continue;
    const std::size_t end = tag.find('"', from + 2);
    if (end == std::string_view::npos) return std::nullopt;
    return std::string(tag.substr(from + 2, end - from - 2));
  }
}

std::uint64_t little_endian_u64(const char* bytes) {
  std::uint64_t value = 0;
  for (int k = 7; k >= 0; --k) value = (value << 8) | static_cast<unsigned char>(bytes[k]);
  return value;
}

class FrameReading {
 public:
  FrameReading(const std::string& path, const std::string& text, Diagnostics& problems)
      : path_(path), text_(text), problems_(problems) {}

  SourceLocation at(std::size_t position) const {
    const std::size_t begin = std::min(position, text_.size());
    int line = 1;
    std::size_t line_start = 0;
    for (std::size_t k = 0; k < begin; ++k)
      if (text_[k] == '\n') ++line, line_start = k + 1;
    return {path_, line, static_cast<int>(begin - line_start) + 1};
  }
  void error(std::size_t position, std::string message,
             std::string hint = std::string(kNotAFrame)) {
    problems_.error(at(position), std::move(message), std::move(hint));
    failed = true;
  }
  bool failed = false;

 private:
  const std::string& path_;
  const std::string& text_;
  Diagnostics& problems_;
};

}  // namespace

std::vector<InitialParticle> read_particle_vtu(const std::string& path,
                                               const std::vector<std::string>& type_names,
                                               std::uint32_t source, Diagnostics& problems) {
  std::vector<InitialParticle> particles;
  const std::optional<std::string> file = read_file(path);
  if (!file) {
    problems.error({path, 0, 0}, "cannot open the particle file",
                   "check the path and its permissions");
    return particles;
  }
  const std::string& text = *file;
  FrameReading reading(path, text, problems);

  const std::size_t data_tag = text.find("<AppendedData");
  const std::size_t file_tag = text.find("<VTKFile");
  if (file_tag == std::string::npos || data_tag == std::string::npos) {
    reading.error(0, "not a VTU file with appended data (no <VTKFile> or <AppendedData> element)");
    return particles;
  }
  const std::string_view header(text.data(), data_tag);
  const std::string_view file_element =
      header.substr(file_tag, header.find('>', file_tag) - file_tag);
  if (attribute(file_element, "type") != "UnstructuredGrid" ||
      attribute(file_element, "byte_order") != "LittleEndian" ||
      attribute(file_element, "header_type") != "UInt64") {
    reading.error(file_tag,
                  "not a particle frame of Quarry's format: an UnstructuredGrid, LittleEndian, "
                  "header_type UInt64 is expected");
    return particles;
  }
  const std::string_view data_element =
      std::string_view(text).substr(data_tag, text.find('>', data_tag) - data_tag);
  if (attribute(data_element, "encoding") != "raw") {
    reading.error(data_tag,
                  "the appended data is not raw (base64 or compressed frames are not read)");
    return particles;
  }
  const std::size_t underscore = text.find('_', data_tag);
  if (underscore == std::string::npos) {
    reading.error(data_tag, "the appended data has no '_' start marker");
    return particles;
  }
  const std::size_t base = underscore + 1;

  const std::size_t piece = header.find("<Piece");
  std::uint64_t count = 0;
  if (piece == std::string_view::npos) {
    reading.error(file_tag, "the file has no <Piece> element");
    return particles;
  }
  {
    const std::string_view piece_element = header.substr(piece, header.find('>', piece) - piece);
    const std::optional<std::string> points = attribute(piece_element, "NumberOfPoints");
    const auto parsed =
        points ? std::from_chars(points->data(), points->data() + points->size(), count)
               : std::from_chars_result{nullptr, std::errc::invalid_argument};
    if (parsed.ec != std::errc{}) {
      reading.error(piece, "the <Piece> element has no NumberOfPoints");
      return particles;
    }
    // Each particle takes 24 bytes of Points alone: a larger count cannot be in this file (and
    // would overflow the byte counts below).
    if (count > text.size() / 24) {
      reading.error(
          piece, fmt::format("NumberOfPoints {} is more than the file's {} bytes can hold", count,
                             text.size()));
      return particles;
    }
  }

  std::unordered_map<std::string, ArrayTag> arrays;
  for (std::size_t at = header.find("<DataArray"); at != std::string_view::npos;
       at = header.find("<DataArray", at + 1)) {
    const std::string_view tag = header.substr(at, header.find('>', at) - at);
    ArrayTag array;
    array.position = at;
    array.name = attribute(tag, "Name").value_or("");
    array.type = attribute(tag, "type").value_or("");
    const std::string components = attribute(tag, "NumberOfComponents").value_or("1");
    const std::string offset = attribute(tag, "offset").value_or("");
    if (attribute(tag, "format") != "appended" || offset.empty()) {
      reading.error(at, fmt::format("array \"{}\" is not in the appended data", array.name));
      return particles;
    }
    array.components = std::atoi(components.c_str());
    array.offset = std::strtoull(offset.c_str(), nullptr, 10);
    arrays.emplace(array.name, array);
  }

  // The bytes of array `name`, checked to hold `values` values of `bytes_each` bytes.
  const auto block = [&](const std::string& name, std::string_view type, int components,
                         std::uint64_t values, std::size_t bytes_each) -> const char* {
    const auto found = arrays.find(name);
    if (found == arrays.end()) return nullptr;
    const ArrayTag& array = found->second;
    if (array.type != type || array.components != components) {
      reading.error(array.position, fmt::format("array \"{}\" is {} × {}, expected {} × {}", name,
                                                array.type, array.components, type, components));
      return nullptr;
    }
    if (array.offset > text.size() - base || text.size() - base - array.offset < 8) {
      reading.error(array.position,
                    fmt::format("array \"{}\" starts past the end of the file (truncated?)", name));
      return nullptr;
    }
    const char* start = text.data() + base + array.offset;
    const std::uint64_t bytes = little_endian_u64(start);
    if (values != ~std::uint64_t{0} &&
        bytes != values * bytes_each * static_cast<std::uint64_t>(components)) {
      reading.error(
          array.position,
          fmt::format("array \"{}\" holds {} bytes, {} particles need {}", name, bytes, values,
                      values * bytes_each * static_cast<std::uint64_t>(components)));
      return nullptr;
    }
    if (bytes > text.size() - (base + array.offset + 8)) {
      reading.error(array.position,
                    fmt::format("array \"{}\" runs past the end of the file (truncated?)", name));
      return nullptr;
    }
    return start + 8;
  };
  const auto required = [&](const std::string& name, std::string_view type,
                            int components) -> const char* {
    const char* data = block(name, type, components, count, type == "Int32" ? 4 : 8);
    if (!data && !reading.failed)
      reading.error(piece, fmt::format("the frame has no array \"{}\"", name),
                    "a frame written by Quarry has Points, radius, type and type_names");
    return data;
  };
  const char* points = required("Points", "Float64", 3);
  const char* radii = required("radius", "Float64", 1);
  const char* types = required("type", "Int32", 1);
  const char* ids = block("id", "UInt64", 1, count, 8);
  const char* velocities = block("velocity", "Float64", 3, count, 8);
  const char* spins = block("angular_velocity", "Float64", 3, count, 8);
  // The frame's type names (NUL-terminated strings back to back) mapped onto the deck's types.
  std::vector<std::string> frame_names;
  if (const char* names = block("type_names", "String", 1, ~std::uint64_t{0}, 1)) {
    const std::uint64_t bytes = little_endian_u64(names - 8);
    std::string current;
    for (std::uint64_t k = 0; k < bytes; ++k) {
      if (names[k] == '\0')
        frame_names.push_back(current), current.clear();
      else
        current.push_back(names[k]);
    }
  } else if (!reading.failed) {
    reading.error(
        piece, "the frame has no field data \"type_names\" to match its types to the deck's",
        "frames written by Quarry carry type_names; CSV tables name each particle's type");
  }
  if (reading.failed) return particles;

  const auto f64 = [](const char* data, std::uint64_t k) {
    return std::bit_cast<double>(little_endian_u64(data + 8 * k));
  };
  const auto vec = [&](const char* data, std::uint64_t i) {
    return Vec3{f64(data, 3 * i), f64(data, 3 * i + 1), f64(data, 3 * i + 2)};
  };
  const auto finite = [](const Vec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
  };
  std::vector<std::size_t> deck_type(frame_names.size(), type_names.size());
  for (std::size_t n = 0; n < frame_names.size(); ++n)
    for (std::size_t t = 0; t < type_names.size(); ++t)
      if (frame_names[n] == type_names[t]) deck_type[n] = t;
  std::vector<char> reported(frame_names.size(), 0);
  std::unordered_map<std::uint64_t, std::uint64_t> index_of_id;
  particles.reserve(count);
  for (std::uint64_t i = 0; i < count && !reading.failed; ++i) {
    InitialParticle p;
    p.source = source;
    std::uint32_t raw_type = 0;
    for (int k = 3; k >= 0; --k)
      raw_type = (raw_type << 8) | static_cast<unsigned char>(types[4 * i + k]);
    const auto type_index = static_cast<std::int32_t>(raw_type);
    const std::string who =
        ids ? fmt::format("particle {} (id {})", i, little_endian_u64(ids + 8 * i))
            : fmt::format("particle {}", i);
    if (type_index < 0 || static_cast<std::size_t>(type_index) >= frame_names.size()) {
      reading.error(arrays["type"].position,
                    fmt::format("{} has type {}, but type_names has {} names", who, type_index,
                                frame_names.size()));
      break;
    }
    const std::size_t t = deck_type[static_cast<std::size_t>(type_index)];
    if (t == type_names.size()) {
      if (!reported[static_cast<std::size_t>(type_index)]) {
        const std::string& name = frame_names[static_cast<std::size_t>(type_index)];
        const std::string guess = closest_match(name, type_names);
        reading.error(
            arrays["type_names"].position,
            fmt::format("particle type \"{}\" of the frame is not defined in the deck", name),
            guess.empty() ? fmt::format("add a particle type named \"{}\" to particle_types", name)
                          : fmt::format("did you mean \"{}\"? Types are matched by name", guess));
        reported[static_cast<std::size_t>(type_index)] = 1;
      }
      continue;
    }
    p.type = static_cast<std::uint16_t>(t);
    p.position = vec(points, i);
    p.radius = f64(radii, i);
    if (velocities) p.velocity = vec(velocities, i);
    if (spins) p.angular_velocity = vec(spins, i);
    if (!finite(p.position) || !finite(p.velocity) || !finite(p.angular_velocity))
      reading.error(arrays["Points"].position,
                    fmt::format("{} has a position, velocity or angular velocity "
                                "that is not a finite number",
                                who),
                    "the frame comes from a run that diverged; start from an earlier frame");
    else if (!(p.radius > 0.0) || !std::isfinite(p.radius))
      reading.error(arrays["radius"].position,
                    fmt::format("{} has radius {} m, not a positive number", who, p.radius),
                    "the frame is damaged; start from another frame");
    if (ids) {
      p.id = little_endian_u64(ids + 8 * i);
      const auto [entry, inserted] = index_of_id.emplace(p.id, i);
      if (p.id == 0 || !inserted)
        reading.error(arrays["id"].position,
                      p.id == 0 ? fmt::format("particle {} has id 0", i)
                                : fmt::format("particles {} and {} have the same id {}",
                                              entry->second, i, p.id),
                      "the frame is damaged; start from another frame");
    }
    particles.push_back(p);
  }
  return particles;
}

}  // namespace quarry
