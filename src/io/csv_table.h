// CsvTable: a monitor time series (first column usually time in s) kept in memory and
// rewritten atomically on flush() at output time; truncate_after() + load() serve restarts.
#pragma once

#include <filesystem>
#include <span>
#include <string>
#include <vector>

namespace quarry {

class CsvTable {
 public:
  // An empty table that will be written to `path` with one header line of `columns`.
  // Pre: at least one column. Throws std::invalid_argument otherwise. Writes nothing.
  CsvTable(std::filesystem::path path, std::vector<std::string> columns);

  // Reads a table written by flush() (header line, then one row of numbers per line).
  // Throws std::runtime_error "path:line: reason" if the file is missing or malformed.
  static CsvTable load(const std::filesystem::path& path);

  // Appends one row. Pre: values.size() == columns().size(), else std::invalid_argument.
  // Non-finite values are kept (printed as nan, inf, -inf). Cost: O(columns) formatting.
  void add_row(std::span<const double> values);

  // Rewrites the whole file atomically (header + every row). Cost: one atomic write of the
  // table's text (already formatted by add_row), so call it per output interval, not per step.
  // Throws std::runtime_error if the file cannot be written.
  void flush();

  // Restart: drops every row whose first column is greater than `first_column_value`
  // (e.g. the times after the checkpoint). Memory only; the file changes at the next flush().
  void truncate_after(double first_column_value);

  const std::vector<std::vector<double>>& rows() const { return rows_; }
  const std::vector<std::string>& columns() const { return columns_; }
  const std::filesystem::path& path() const { return path_; }

 private:
  void rebuild_text();

  std::filesystem::path path_;
  std::vector<std::string> columns_;
  std::vector<std::vector<double>> rows_;
  std::string text_;  // the file's content for the current rows, kept in step with rows_
};

}  // namespace quarry
