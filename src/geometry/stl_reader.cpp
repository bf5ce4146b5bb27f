// STL reader/writer. Binary layout: 80-byte header, uint32 facet count, then per facet 12
// float32 (normal, 3 vertices) and a uint16 attribute, all little-endian (50 bytes a facet).
#include "geometry/stl_reader.h"

#include <fmt/format.h>

#include <bit>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <algorithm>
#include <array>
#include <fstream>
#include <set>
#include <iterator>
#include <vector>

#include "core/diagnostics.h"
#include "geometry/vertex_welder.h"

namespace quarry {

namespace {

constexpr std::size_t binary_header_bytes = 84;
constexpr std::size_t binary_facet_bytes = 50;

std::uint32_t read_u32_le(const char* bytes) {
  std::uint32_t value = 0;
  for (int b = 3; b >= 0; --b) value = (value << 8) | static_cast<unsigned char>(bytes[b]);
  return value;
}

float read_f32_le(const char* bytes) {
  const std::uint32_t bits = read_u32_le(bytes);
  return std::bit_cast<float>(bits);
}

void append_u32_le(std::string& out, std::uint32_t value) {
  for (int b = 0; b < 4; ++b) out.push_back(static_cast<char>((value >> (8 * b)) & 0xFFu));
}

void append_f32_le(std::string& out, float value) { append_u32_le(out, std::bit_cast<std::uint32_t>(value)); }

bool is_text(const std::string& bytes) {
  for (const char ch : bytes) {
    const auto c = static_cast<unsigned char>(ch);
    const bool whitespace = c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f';
    if (!whitespace && (c < 32 || c > 126)) return false;
  }
  return true;
}

// An ASCII STL whose text holds bytes outside printable ASCII (a solid or a comment named in
// UTF-8): it begins with "solid" and has the ASCII structure's keywords. Its size does not fit
// the binary layout (checked before), so reading it as binary would only fail.
bool looks_like_ascii_stl(const std::string& bytes) {
  const std::size_t first = bytes.find_first_not_of(" \t\r\n");
  if (first == std::string::npos || bytes.compare(first, 5, "solid") != 0) return false;
  return bytes.find("facet") != std::string::npos && bytes.find("vertex") != std::string::npos;
}

Vec3 transformed(double x, double y, double z, double scale, const Vec3& offset) {
  return Vec3{x, y, z} * scale + offset;
}

std::vector<Vec3> parse_binary(const std::string& bytes, const std::string& path, double scale,
                               const Vec3& offset) {
  const std::string hint = "the file is not a complete binary STL; re-export it from the CAD tool";
  if (bytes.size() < binary_header_bytes)
    throw UserError(SourceLocation{path, 0, 0},
                    fmt::format("binary STL truncated: the file ends at byte offset {} inside the "
                                "84-byte header",
                                bytes.size()),
                    hint);
  const std::uint32_t facet_count = read_u32_le(bytes.data() + 80);
  const std::size_t expected = binary_header_bytes + binary_facet_bytes * std::size_t{facet_count};
  if (bytes.size() < expected) {
    const std::size_t incomplete = (bytes.size() - binary_header_bytes) / binary_facet_bytes;
    throw UserError(SourceLocation{path, 0, 0},
                    fmt::format("binary STL truncated: the header announces {} facets ({} bytes) but "
                                "the file has {} bytes; facet {} starting at byte offset {} is incomplete",
                                facet_count, expected, bytes.size(), incomplete,
                                binary_header_bytes + binary_facet_bytes * incomplete),
                    hint);
  }
  if (bytes.size() > expected)
    throw UserError(SourceLocation{path, 0, 0},
                    fmt::format("binary STL has {} unexpected bytes after the last facet (from byte "
                                "offset {}); the header announces {} facets",
                                bytes.size() - expected, expected, facet_count),
                    hint);
  std::vector<Vec3> corners;
  corners.reserve(3 * std::size_t{facet_count});
  for (std::size_t f = 0; f < facet_count; ++f) {
    const std::size_t facet_offset = binary_header_bytes + binary_facet_bytes * f;
    for (int k = 0; k < 3; ++k) {
      const std::size_t vertex_offset = facet_offset + 12 + 12 * static_cast<std::size_t>(k);
      const double x = read_f32_le(bytes.data() + vertex_offset);
      const double y = read_f32_le(bytes.data() + vertex_offset + 4);
      const double z = read_f32_le(bytes.data() + vertex_offset + 8);
      if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z))
        throw UserError(SourceLocation{path, 0, 0},
                        fmt::format("binary STL: facet {} has a non-finite vertex coordinate at byte "
                                    "offset {}",
                                    f, vertex_offset),
                        hint);
      corners.push_back(transformed(x, y, z, scale, offset));
    }
  }
  return corners;
}

// Whitespace tokenizer that remembers the 1-based line and column of each token.
class AsciiTokens {
 public:
  AsciiTokens(const std::string& text, const std::string& path) : text_(text), path_(path) {}

  struct Token {
    std::string_view text;
    int line = 0, column = 0;
  };

  // Next token; empty text at end of file.
  Token next() {
    skip_whitespace();
    Token token{{}, line_, column_};
    const std::size_t start = position_;
    while (position_ < text_.size() && !is_space(text_[position_])) advance();
    token.text = std::string_view(text_).substr(start, position_ - start);
    return token;
  }

  // Skips the remainder of the current line (the free-form name after solid/endsolid).
  void skip_line() {
    while (position_ < text_.size() && text_[position_] != '\n') advance();
  }

  [[noreturn]] void fail(const Token& token, const std::string& message, const std::string& hint) const {
    throw UserError(SourceLocation{path_, token.line, token.column}, message, hint);
  }

  static bool keyword_is(std::string_view token, std::string_view keyword) {
    if (token.size() != keyword.size()) return false;
    for (std::size_t i = 0; i < token.size(); ++i) {
      char c = token[i];
      if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
      if (c != keyword[i]) return false;
    }
    return true;
  }

  void expect(std::string_view keyword) {
    const Token token = next();
    if (!keyword_is(token.text, keyword))
      fail(token,
           token.text.empty() ? fmt::format("ASCII STL ends where \"{}\" was expected", keyword)
                              : fmt::format("ASCII STL: expected \"{}\", found \"{}\"", keyword, token.text),
           "an ASCII STL facet reads: facet normal nx ny nz / outer loop / vertex x y z (3 times) / "
           "endloop / endfacet");
  }

  double number() {
    const Token token = next();
    double value = 0.0;
    const char* first = token.text.data();
    const char* last = first + token.text.size();
    // from_chars rejects a leading '+', which some exporters write.
    if (first != last && *first == '+') ++first;
    const auto [end, error] = std::from_chars(first, last, value);
    if (token.text.empty() || error != std::errc{} || end != last || !std::isfinite(value))
      fail(token,
           token.text.empty() ? std::string("ASCII STL ends where a number was expected")
                              : fmt::format("ASCII STL: \"{}\" is not a finite number", token.text),
           "coordinates are decimal numbers such as 1.25 or -3.5e-2");
    return value;
  }

 private:
  static bool is_space(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f'; }
  void advance() {
    if (text_[position_] == '\n') {
      ++line_;
      column_ = 1;
    } else {
      ++column_;
    }
    ++position_;
  }
  void skip_whitespace() {
    while (position_ < text_.size() && is_space(text_[position_])) advance();
  }

  const std::string& text_;
  const std::string& path_;
  std::size_t position_ = 0;
  int line_ = 1, column_ = 1;
};

std::vector<Vec3> parse_ascii(const std::string& text, const std::string& path, double scale,
                              const Vec3& offset) {
  AsciiTokens tokens(text, path);
  std::vector<Vec3> corners;
  // A file may hold several solids one after another.
  for (AsciiTokens::Token token = tokens.next(); !token.text.empty(); token = tokens.next()) {
    if (!AsciiTokens::keyword_is(token.text, "solid"))
      tokens.fail(token, fmt::format("ASCII STL: expected \"solid\", found \"{}\"", token.text),
                  "an ASCII STL starts with \"solid name\" and ends with \"endsolid name\"");
    tokens.skip_line();
    for (;;) {
      const AsciiTokens::Token keyword = tokens.next();
      if (AsciiTokens::keyword_is(keyword.text, "endsolid")) {
        tokens.skip_line();
        break;
      }
      if (!AsciiTokens::keyword_is(keyword.text, "facet"))
        tokens.fail(keyword,
                    keyword.text.empty() ? std::string("ASCII STL ends without \"endsolid\"")
                                         : fmt::format("ASCII STL: expected \"facet\" or \"endsolid\", "
                                                       "found \"{}\"",
                                                       keyword.text),
                    "each facet starts with \"facet normal nx ny nz\"");
      tokens.expect("normal");
      for (int k = 0; k < 3; ++k) tokens.number();  // the file's normal is not trusted
      tokens.expect("outer");
      tokens.expect("loop");
      for (int k = 0; k < 3; ++k) {
        tokens.expect("vertex");
        const double x = tokens.number();
        const double y = tokens.number();
        const double z = tokens.number();
        corners.push_back(transformed(x, y, z, scale, offset));
      }
      tokens.expect("endloop");
      tokens.expect("endfacet");
    }
  }
  return corners;
}

}  // namespace

Surface read_stl(const std::string& path, double scale, const Vec3& offset, std::vector<std::string>* notes) {
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw UserError(SourceLocation{path, 0, 0}, fmt::format("cannot open STL file \"{}\"", path),
                    "check the file name; a relative path is taken from the deck's folder");
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad())
    throw UserError(SourceLocation{path, 0, 0}, fmt::format("cannot read STL file \"{}\"", path));

  bool binary = true;
  if (bytes.size() >= binary_header_bytes &&
      bytes.size() == binary_header_bytes + binary_facet_bytes * std::size_t{read_u32_le(bytes.data() + 80)})
    binary = true;  // exact size match: binary, even when the header begins with "solid"
  else if (is_text(bytes) || looks_like_ascii_stl(bytes))
    binary = false;  // text, or "solid …" with facets whose name line has non-ASCII bytes (UTF-8)

  std::vector<Vec3> corners =
      binary ? parse_binary(bytes, path, scale, offset) : parse_ascii(bytes, path, scale, offset);
  if (corners.empty())
    throw UserError(SourceLocation{path, 0, 0}, fmt::format("STL file \"{}\" contains no facets", path),
                    "export the surface again; an empty STL is usually a failed export");
  for (const Vec3& p : corners)
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      throw UserError(SourceLocation{path, 0, 0},
                      "STL coordinates overflow after applying scale and offset",
                      "check the scale factor");
  Surface surface = surface_from_triangle_soup(corners, std::string{});
  const StlCleanup cleanup = drop_degenerate_and_duplicate_facets(surface);
  if (surface.triangle_count() == 0)
    throw UserError(SourceLocation{path, 0, 0},
                    fmt::format("STL file \"{}\" has no facet with an area: its {} facets are degenerate or "
                                "copies of one another",
                                path, corners.size() / 3),
                    "export the surface again; check the units and the export tolerance");
  if (notes && (cleanup.degenerate > 0 || cleanup.duplicates > 0))
    notes->push_back(fmt::format("STL file \"{}\": {} degenerate facet(s) (no area after merging "
                                 "coincident corners) and {} duplicate facet(s) (the same three corners "
                                 "again) removed; element ids count the {} facets kept, in file order",
                                 path, cleanup.degenerate, cleanup.duplicates, surface.triangle_count()));
  return surface;
}

StlCleanup drop_degenerate_and_duplicate_facets(Surface& surface) {
  StlCleanup cleanup;
  std::set<std::array<std::uint32_t, 3>> seen;  // sorted corners of the facets kept
  std::vector<std::array<std::uint32_t, 3>> kept;
  for (std::size_t t = 0; t < surface.triangles.size(); ++t) {
    const auto& tri = surface.triangles[t];
    if (tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2] || !(surface.triangle_areas[t] > 0.0)) {
      ++cleanup.degenerate;
      continue;
    }
    std::array<std::uint32_t, 3> key = tri;
    std::sort(key.begin(), key.end());
    if (!seen.insert(key).second) {
      ++cleanup.duplicates;  // either orientation: a second wall in the same place
      continue;
    }
    kept.push_back(tri);
  }
  if (cleanup.degenerate == 0 && cleanup.duplicates == 0) return cleanup;
  // Vertices no kept facet uses go too, so that node ids stay those of the mesh's own nodes.
  std::vector<std::uint32_t> new_index(surface.vertices.size(), ~0u);
  std::vector<Vec3> vertices;
  for (auto& tri : kept)
    for (auto& v : tri) {
      if (new_index[v] == ~0u) {
        new_index[v] = static_cast<std::uint32_t>(vertices.size());
        vertices.push_back(surface.vertices[v]);
      }
      v = new_index[v];
    }
  surface.vertices = std::move(vertices);
  surface.reference_vertices = surface.vertices;
  surface.vertex_velocities.assign(surface.vertices.size(), Vec3{});
  surface.triangles = std::move(kept);
  surface.update_normals_and_areas();
  surface.reset_loads();
  return cleanup;
}

void write_stl_binary(const std::string& path, const Surface& surface) {
  std::string bytes;
  bytes.reserve(binary_header_bytes + binary_facet_bytes * surface.triangle_count());
  // The header must not begin with "solid": some readers would take the file for ASCII.
  std::string header = fmt::format("Quarry binary STL: {}", surface.name);
  header.resize(80, ' ');
  bytes += header;
  append_u32_le(bytes, static_cast<std::uint32_t>(surface.triangle_count()));
  const bool have_normals = surface.triangle_normals.size() == surface.triangle_count();
  for (std::size_t t = 0; t < surface.triangle_count(); ++t) {
    const auto& tri = surface.triangles[t];
    Vec3 normal;
    if (have_normals) {
      normal = surface.triangle_normals[t];
    } else {
      const Vec3& a = surface.vertices[tri[0]];
      normal = normalized(cross(surface.vertices[tri[1]] - a, surface.vertices[tri[2]] - a));
    }
    append_f32_le(bytes, static_cast<float>(normal.x));
    append_f32_le(bytes, static_cast<float>(normal.y));
    append_f32_le(bytes, static_cast<float>(normal.z));
    for (int k = 0; k < 3; ++k) {
      const Vec3& p = surface.vertices[tri[k]];
      append_f32_le(bytes, static_cast<float>(p.x));
      append_f32_le(bytes, static_cast<float>(p.y));
      append_f32_le(bytes, static_cast<float>(p.z));
    }
    bytes.push_back('\0');
    bytes.push_back('\0');
  }
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) throw UserError(SourceLocation{path, 0, 0}, fmt::format("cannot write STL file \"{}\"", path));
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (!out) throw UserError(SourceLocation{path, 0, 0}, fmt::format("error while writing STL file \"{}\"", path));
}

}  // namespace quarry
