// Helpers shared by the io tests: the source folder, small text utilities and the golden
// first-error-line check of the broken-input folders (tests/bad_decks, tests/bad_models).
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <string>
#include <vector>

#include "io/atomic_file.h"

namespace quarry::io_testing {

namespace fs = std::filesystem;

inline fs::path source_dir() {
  const char* from_environment = std::getenv("QUARRY_SOURCE_DIR");
  return fs::path(from_environment ? from_environment : QUARRY_SOURCE_DIR);
}

inline std::string read_text(const fs::path& path) {
  return read_file(path).value_or("");
}

inline std::string first_line(const std::string& text) {
  return text.substr(0, text.find('\n'));
}

inline std::string replace_all(std::string text, const std::string& from, const std::string& to) {
  for (std::size_t at = text.find(from); at != std::string::npos;
       at = text.find(from, at + to.size()))
    text.replace(at, from.size(), to);
  return text;
}

// The files of `folder` with one of `extensions` (".yaml"), sorted by name.
inline std::vector<fs::path> files_with_extensions(const fs::path& folder,
                                                   std::initializer_list<const char*> extensions) {
  std::vector<fs::path> files;
  for (const auto& entry : fs::directory_iterator(folder))
    for (const char* extension : extensions)
      if (entry.path().extension() == extension) files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  return files;
}

// `actual`, the first error line for `input`, must equal the first line of input's
// NN_name.expected, where the input's path is written as `placeholder` ("{deck}"). With
// `update`, the .expected file is rewritten from `actual` instead (review the diff). `context`
// is printed with a mismatch (e.g. the whole output).
inline void expect_first_line_matches_golden(const fs::path& input, const std::string& actual,
                                             const std::string& placeholder, bool update,
                                             const std::string& context = {}) {
  fs::path expected_path = input;
  expected_path.replace_extension(".expected");
  if (update) {
    std::ofstream(expected_path, std::ios::binary)
        << replace_all(actual, input.string(), placeholder) << "\n";
    return;
  }
  ASSERT_TRUE(fs::exists(expected_path)) << "missing " << expected_path;
  EXPECT_EQ(actual, replace_all(first_line(read_text(expected_path)), placeholder, input.string()))
      << context;
}

}  // namespace quarry::io_testing
