// CsvTable: comma-separated numbers with the shortest round-trip representation (fmt "{}"),
// header fields quoted per RFC 4180 only where needed.
#include "io/csv_table.h"

#include <fmt/format.h>

#include <charconv>
#include <fstream>
#include <stdexcept>
#include <string_view>
#include <system_error>
#include <utility>

#include "io/atomic_file.h"

namespace quarry {

namespace {

std::string quoted_if_needed(const std::string& field) {
  const bool needs_quotes = field.find_first_of(",\"\r\n") != std::string::npos ||
                            (!field.empty() && (field.front() == ' ' || field.back() == ' '));
  if (!needs_quotes) return field;
  std::string quoted = "\"";
  for (const char c : field) {
    if (c == '"') quoted += '"';  // RFC 4180: a quote inside a quoted field is doubled
    quoted += c;
  }
  quoted += '"';
  return quoted;
}

void append_row_text(std::string& text, std::span<const double> values) {
  for (std::size_t k = 0; k < values.size(); ++k) {
    if (k > 0) text += ',';
    fmt::format_to(std::back_inserter(text), "{}", values[k]);
  }
  text += '\n';
}

// Splits one line into fields; `line_number` only for messages.
std::vector<std::string> split_fields(std::string_view line, const std::filesystem::path& path,
                                      int line_number) {
  std::vector<std::string> fields;
  std::string field;
  bool in_quotes = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (in_quotes) {
      if (c == '"' && i + 1 < line.size() && line[i + 1] == '"') {
        field += '"';
        ++i;
      } else if (c == '"') {
        in_quotes = false;
      } else {
        field += c;
      }
    } else if (c == '"') {
      in_quotes = true;
    } else if (c == ',') {
      fields.push_back(std::move(field));
      field.clear();
    } else {
      field += c;
    }
  }
  if (in_quotes) {
    throw std::runtime_error(
        fmt::format("{}:{}: unterminated quoted field", path.string(), line_number));
  }
  fields.push_back(std::move(field));
  return fields;
}

double parse_number(std::string_view text, const std::filesystem::path& path, int line_number,
                    std::size_t column) {
  while (!text.empty() && text.front() == ' ') text.remove_prefix(1);
  while (!text.empty() && text.back() == ' ') text.remove_suffix(1);
  double value = 0.0;
  const auto [end, status] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (text.empty() || status != std::errc() || end != text.data() + text.size()) {
    throw std::runtime_error(fmt::format("{}:{}: column {}: \"{}\" is not a number", path.string(),
                                         line_number, column + 1, text));
  }
  return value;
}

}  // namespace

CsvTable::CsvTable(std::filesystem::path path, std::vector<std::string> columns)
    : path_(std::move(path)), columns_(std::move(columns)) {
  if (columns_.empty()) {
    throw std::invalid_argument(
        fmt::format("CSV table '{}' needs at least one column", path_.string()));
  }
  rebuild_text();
}

CsvTable CsvTable::load(const std::filesystem::path& path) {
  std::ifstream input(path, std::ios::binary);
  if (!input) {
    throw std::runtime_error(fmt::format("{}: cannot open CSV table", path.string()));
  }
  std::string line;
  int line_number = 0;
  std::vector<std::string> columns;
  std::vector<std::vector<double>> rows;
  while (std::getline(input, line)) {
    ++line_number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line_number == 1) {
      columns = split_fields(line, path, line_number);
      continue;
    }
    if (line.empty()) continue;
    const std::vector<std::string> fields = split_fields(line, path, line_number);
    if (fields.size() != columns.size()) {
      throw std::runtime_error(fmt::format("{}:{}: {} values, but the header has {} columns",
                                           path.string(), line_number, fields.size(),
                                           columns.size()));
    }
    std::vector<double> row(fields.size());
    for (std::size_t k = 0; k < fields.size(); ++k) {
      row[k] = parse_number(fields[k], path, line_number, k);
    }
    rows.push_back(std::move(row));
  }
  if (line_number == 0) {
    throw std::runtime_error(fmt::format("{}:1: empty CSV table (no header line)", path.string()));
  }
  CsvTable table(path, std::move(columns));
  table.rows_ = std::move(rows);
  table.rebuild_text();
  return table;
}

void CsvTable::add_row(std::span<const double> values) {
  if (values.size() != columns_.size()) {
    throw std::invalid_argument(fmt::format("CSV table '{}': row has {} values, expected {}",
                                            path_.string(), values.size(), columns_.size()));
  }
  rows_.emplace_back(values.begin(), values.end());
  append_row_text(text_, values);
}

void CsvTable::flush() {
  write_file_atomically(path_, text_);
}

void CsvTable::truncate_after(double first_column_value) {
  std::erase_if(rows_, [first_column_value](const std::vector<double>& row) {
    return row.front() > first_column_value;
  });
  rebuild_text();
}

void CsvTable::rebuild_text() {
  text_.clear();
  for (std::size_t k = 0; k < columns_.size(); ++k) {
    if (k > 0) text_ += ',';
    text_ += quoted_if_needed(columns_[k]);
  }
  text_ += '\n';
  for (const auto& row : rows_) append_row_text(text_, row);
}

}  // namespace quarry
