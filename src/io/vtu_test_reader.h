// A tiny reader of the VTU files the writers make, for tests only: the XML header and the
// appended raw blocks (UInt64 byte counts, little endian), every DataArray by name. Checks the
// layout with gtest expectations as it reads.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/vec3.h"

namespace quarry::vtu_test {

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

inline std::uint64_t read_uint64_little_endian(const std::string& bytes, std::size_t at) {
  std::uint64_t value = 0;
  for (int byte = 7; byte >= 0; --byte) {
    value =
        (value << 8) | static_cast<unsigned char>(bytes.at(at + static_cast<std::size_t>(byte)));
  }
  return value;
}

inline std::string attribute(const std::string& tag, const std::string& name) {
  const std::string key = " " + name + "=\"";
  const std::size_t start = tag.find(key);
  if (start == std::string::npos) return {};
  const std::size_t value_start = start + key.size();
  return tag.substr(value_start, tag.find('"', value_start) - value_start);
}

inline VtuContent read_vtu(const std::string& file) {
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

inline std::vector<Vec3> vectors_of(const ArrayInfo& info) {
  EXPECT_EQ(info.type, "Float64");
  EXPECT_EQ(info.components, 3);
  const std::vector<double> flat = values_of<double>(info);
  std::vector<Vec3> vectors;
  for (std::size_t k = 0; k + 2 < flat.size(); k += 3)
    vectors.push_back({flat[k], flat[k + 1], flat[k + 2]});
  return vectors;
}

}  // namespace quarry::vtu_test
