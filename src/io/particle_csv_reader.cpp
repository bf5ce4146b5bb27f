// The CSV particle table of the deck's `particles:` section (particle_file_reader.h): a header
// naming the columns, then one particle per line; every problem located at line:col.
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <array>
#include <charconv>
#include <cmath>
#include <fstream>
#include <optional>
#include <sstream>
#include <string_view>
#include <unordered_map>

#include "io/particle_file_reader.h"

namespace quarry {

namespace {

constexpr int kMaxProblems = 20;  // per file: a wrong file would otherwise print every line

enum Column { x, y, z, radius, type, vx, vy, vz, wx, wy, wz, id, column_count };
constexpr std::array<std::string_view, column_count> kColumnNames = {
    "x", "y", "z", "radius", "type", "vx", "vy", "vz", "wx", "wy", "wz", "id"};
constexpr std::string_view kHeaderHint =
    "the header names the columns: x,y,z,radius,type (required), vx,vy,vz and wx,wy,wz "
    "(optional, each three together), id (optional)";

struct Field {
  std::string_view text;
  int column = 1;  // 1-based, of the field's first character
};

std::string_view trimmed(std::string_view s, int& column) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1), ++column;
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  return s;
}

// Splits a line at commas (no quoting: names and numbers hold no commas); fields trimmed.
std::vector<Field> split(std::string_view line) {
  std::vector<Field> fields;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = line.find(',', start);
    const std::size_t end = comma == std::string_view::npos ? line.size() : comma;
    int column = static_cast<int>(start) + 1;
    const std::string_view text = trimmed(line.substr(start, end - start), column);
    fields.push_back({text, column});
    if (comma == std::string_view::npos) return fields;
    start = comma + 1;
  }
}

class CsvReading {
 public:
  CsvReading(const std::string& path, Diagnostics& problems) : path_(path), problems_(problems) {}
  bool full() const { return count_ >= kMaxProblems; }
  void error(int line, int column, std::string message, std::string hint) {
    if (full()) return;
    problems_.error({path_, line, column}, std::move(message), std::move(hint));
    ++count_;
  }
  int count() const { return count_; }

 private:
  const std::string& path_;
  Diagnostics& problems_;
  int count_ = 0;
};

std::optional<double> parse_number(std::string_view text) {
  if (!text.empty() && text.front() == '+') text.remove_prefix(1);
  double value = 0.0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc{} || end != text.data() + text.size() || text.empty()) return std::nullopt;
  return value;
}

std::optional<std::uint64_t> parse_id(std::string_view text) {
  std::uint64_t value = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc{} || end != text.data() + text.size() || text.empty()) return std::nullopt;
  return value;
}

}  // namespace

std::vector<InitialParticle> read_particle_csv(const std::string& path,
                                               const std::vector<std::string>& type_names,
                                               std::uint32_t source, Diagnostics& problems) {
  std::vector<InitialParticle> particles;
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    problems.error({path, 0, 0}, "cannot open the particle file",
                   "check the path and its permissions");
    return particles;
  }
  CsvReading reading(path, problems);
  std::string line;
  int number = 0;
  // Header: the first line that is not blank.
  std::array<int, column_count> where{};  // field index + 1 of each column (0: absent)
  std::size_t field_count = 0;
  bool have_header = false;
  while (!have_header && std::getline(in, line)) {
    ++number;
    if (number == 1 && line.rfind("\xEF\xBB\xBF", 0) == 0)
      line.erase(0, 3);  // UTF-8 byte-order mark
    if (!line.empty() && line.back() == '\r') line.pop_back();
    int ignored = 1;
    if (trimmed(line, ignored).empty()) continue;
    have_header = true;
    const std::vector<Field> fields = split(line);
    field_count = fields.size();
    for (std::size_t f = 0; f < fields.size(); ++f) {
      std::size_t c = 0;
      while (c < column_count && kColumnNames[c] != fields[f].text) ++c;
      if (c == column_count) {
        std::vector<std::string> names(kColumnNames.begin(), kColumnNames.end());
        const std::string guess = closest_match(std::string(fields[f].text), names);
        reading.error(
            number, fields[f].column, fmt::format("unknown column \"{}\"", fields[f].text),
            guess.empty() ? std::string(kHeaderHint) : fmt::format("did you mean \"{}\"?", guess));
      } else if (where[c] != 0) {
        reading.error(number, fields[f].column,
                      fmt::format("column \"{}\" appears twice", fields[f].text),
                      fmt::format("it is column {} already; remove one", where[c]));
      } else {
        where[c] = static_cast<int>(f) + 1;
      }
    }
    for (const Column c : {x, y, z, radius, type})
      if (where[c] == 0)
        reading.error(number, 1, fmt::format("missing column \"{}\"", kColumnNames[c]),
                      std::string(kHeaderHint));
    for (const Column first : {vx, wx}) {
      const int present = (where[first] != 0) + (where[first + 1] != 0) + (where[first + 2] != 0);
      if (present != 0 && present != 3)
        reading.error(
            number, 1,
            fmt::format("columns {}, {} and {} go together: {} of them given", kColumnNames[first],
                        kColumnNames[first + 1], kColumnNames[first + 2], present),
            std::string(kHeaderHint));
    }
  }
  if (!have_header) {
    reading.error(number > 0 ? 1 : 0, 0, "the particle file is empty", std::string(kHeaderHint));
    return particles;
  }
  if (reading.count() > 0) return particles;  // the rows cannot be read without their columns

  std::unordered_map<std::uint64_t, int> line_of_id;
  while (!reading.full() && std::getline(in, line)) {
    ++number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    int ignored = 1;
    if (trimmed(line, ignored).empty()) continue;
    const std::vector<Field> fields = split(line);
    if (fields.size() != field_count) {
      reading.error(
          number, 1,
          fmt::format("{} fields on this line, the header has {}", fields.size(), field_count),
          "one value per column, separated by commas");
      continue;
    }
    InitialParticle p;
    p.source = source;
    p.line = static_cast<std::uint32_t>(number);
    bool valid = true;
    std::array<double, column_count> value{};
    for (std::size_t c = 0; c < column_count; ++c) {
      if (where[c] == 0 || c == type || c == id) continue;
      const Field& field = fields[static_cast<std::size_t>(where[c] - 1)];
      const std::optional<double> parsed = parse_number(field.text);
      if (!parsed || !std::isfinite(*parsed)) {
        reading.error(number, field.column,
                      fmt::format("{} \"{}\" is not a finite number", kColumnNames[c], field.text),
                      c == radius ? "a radius in m, e.g. 0.002"
                                  : "a number in SI units, e.g. 0.25 or -1.5e-3");
        valid = false;
        continue;
      }
      value[c] = *parsed;
    }
    if (valid && !(value[radius] > 0.0)) {
      const Field& field = fields[static_cast<std::size_t>(where[radius] - 1)];
      reading.error(number, field.column, fmt::format("radius must be > 0 m, got {} m", field.text),
                    "the particle's radius in m, e.g. 0.002");
      valid = false;
    }
    const Field& type_field = fields[static_cast<std::size_t>(where[type] - 1)];
    std::size_t t = 0;
    while (t < type_names.size() && type_names[t] != type_field.text) ++t;
    if (t == type_names.size()) {
      const std::string guess = closest_match(std::string(type_field.text), type_names);
      reading.error(
          number, type_field.column, fmt::format("unknown particle type \"{}\"", type_field.text),
          guess.empty() ? fmt::format("the deck's particle types are: {}", fmt::join(type_names, ", "))
                        : fmt::format("did you mean \"{}\"?", guess));
      valid = false;
    }
    if (where[id] != 0) {
      const Field& field = fields[static_cast<std::size_t>(where[id] - 1)];
      const std::optional<std::uint64_t> parsed = parse_id(field.text);
      if (!parsed || *parsed == 0) {
        reading.error(number, field.column,
                      fmt::format("id \"{}\" is not an integer ≥ 1", field.text),
                      "ids are whole numbers from 1 up, each particle its own");
        valid = false;
      } else if (const auto [entry, inserted] = line_of_id.emplace(*parsed, number); !inserted) {
        reading.error(
            number, field.column, fmt::format("id {} is given twice", *parsed),
            fmt::format("first on line {}; each particle needs its own id", entry->second));
        valid = false;
      } else {
        p.id = *parsed;
      }
    }
    if (!valid) continue;
    p.type = static_cast<std::uint16_t>(t);
    p.position = {value[x], value[y], value[z]};
    p.radius = value[radius];
    p.velocity = {value[vx], value[vy], value[vz]};
    p.angular_velocity = {value[wx], value[wy], value[wz]};
    particles.push_back(p);
  }
  return particles;
}

}  // namespace quarry
