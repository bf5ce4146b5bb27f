// PVD series: format, atomic rewrite, and a small reader of the DataSet entries for restart.
#include "io/pvd_series.h"
#include "io/xml_text.h"

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <fstream>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string_view>
#include <system_error>
#include <utility>

#include "io/atomic_file.h"

namespace quarry {

namespace {

// Value of attribute `name` inside one tag's text, or nothing if absent. Attributes are
// matched on a leading space so that e.g. "file" never matches inside "myfile".
std::optional<std::string_view> attribute(std::string_view tag, std::string_view name) {
  for (const char quote : {'"', '\''}) {
    const std::string key = fmt::format(" {}={}", name, quote);
    const std::size_t start = tag.find(key);
    if (start == std::string_view::npos) continue;
    const std::size_t value_start = start + key.size();
    const std::size_t value_end = tag.find(quote, value_start);
    if (value_end == std::string_view::npos) return std::nullopt;
    return tag.substr(value_start, value_end - value_start);
  }
  return std::nullopt;
}

}  // namespace

PvdSeries::PvdSeries(std::filesystem::path pvd_path) : pvd_path_(std::move(pvd_path)) {}

PvdSeries PvdSeries::resume(std::filesystem::path pvd_path, double restart_time) {
  PvdSeries series(std::move(pvd_path));
  series.load_existing(restart_time);
  return series;
}

std::string PvdSeries::to_xml() const {
  std::string xml;
  xml += "<?xml version=\"1.0\"?>\n";
  xml += "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n";
  xml += "  <Collection>\n";
  for (const PvdEntry& entry : entries_) {
    // "{}" prints the shortest text that reads back to the same double, so restart
    // comparisons against checkpoint times are exact.
    xml += fmt::format("    <DataSet timestep=\"{}\" group=\"\" part=\"0\" file=\"{}\"/>\n",
                       entry.time, xml_escaped(entry.file));
  }
  xml += "  </Collection>\n";
  xml += "</VTKFile>\n";
  return xml;
}

void PvdSeries::add(double time, const std::string& relative_file) {
  entries_.push_back({time, relative_file});
  write_file_atomically(pvd_path_, to_xml());
}

void PvdSeries::load_existing(double up_to_time) {
  entries_.clear();
  std::error_code error;
  if (!std::filesystem::exists(pvd_path_, error)) return;
  std::ifstream input(pvd_path_, std::ios::binary);
  if (!input) {
    throw std::runtime_error(fmt::format("cannot read PVD series '{}'", pvd_path_.string()));
  }
  std::stringstream buffer;
  buffer << input.rdbuf();
  const std::string text = buffer.str();
  if (text.find("<Collection") == std::string::npos) {
    throw std::runtime_error(
        fmt::format("'{}' is not a PVD collection (no <Collection> element)", pvd_path_.string()));
  }

  for (std::size_t position = text.find("<DataSet"); position != std::string::npos;
       position = text.find("<DataSet", position + 1)) {
    const std::size_t tag_end = text.find('>', position);
    if (tag_end == std::string::npos) {
      throw std::runtime_error(
          fmt::format("'{}': unterminated <DataSet> element", pvd_path_.string()));
    }
    const std::string_view tag(text.data() + position, tag_end - position);
    const auto time_text = attribute(tag, "timestep");
    const auto file_text = attribute(tag, "file");
    const auto line =
        1 + std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(position), '\n');
    if (!time_text || !file_text) {
      throw std::runtime_error(fmt::format(
          "{}:{}: <DataSet> needs both timestep and file attributes", pvd_path_.string(), line));
    }
    double time = 0.0;
    const auto [end, status] =
        std::from_chars(time_text->data(), time_text->data() + time_text->size(), time);
    if (status != std::errc() || end != time_text->data() + time_text->size()) {
      throw std::runtime_error(fmt::format("{}:{}: timestep \"{}\" is not a number",
                                           pvd_path_.string(), line, *time_text));
    }
    if (time <= up_to_time) entries_.push_back({time, xml_unescaped(*file_text)});
  }
}

}  // namespace quarry
