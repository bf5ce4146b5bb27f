// Tests of write_file_atomically: content, overwrite, created folders, no temporaries left,
// and failures that name the path.
#include "io/atomic_file.h"

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>

namespace quarry {
namespace {

namespace fs = std::filesystem;

fs::path fresh_folder(const std::string& name) {
  const fs::path folder = fs::path(testing::TempDir()) / ("quarry_atomic_file_" + name);
  fs::remove_all(folder);
  fs::create_directories(folder);
  return folder;
}

std::string read_all(const fs::path& path) {
  return read_file(path).value_or("");
}

std::size_t entries_in(const fs::path& folder) {
  std::size_t count = 0;
  for ([[maybe_unused]] const auto& entry : fs::directory_iterator(folder)) ++count;
  return count;
}

TEST(AtomicFile, WritesExactBytesAndLeavesNoTemporary) {
  const fs::path folder = fresh_folder("exact");
  const fs::path target = folder / "out.bin";
  std::string bytes = "header\n";
  bytes.push_back('\0');  // binary content must survive unchanged
  bytes += std::string(1 << 20, 'x');
  write_file_atomically(target, bytes);
  EXPECT_EQ(read_all(target), bytes);
  EXPECT_EQ(entries_in(folder), 1u);
}

TEST(AtomicFile, ReplacesAnExistingFileCompletely) {
  const fs::path folder = fresh_folder("replace");
  const fs::path target = folder / "table.csv";
  write_file_atomically(target, std::string(1000, 'a'));
  write_file_atomically(target, "short");
  EXPECT_EQ(read_all(target), "short");  // no tail of the longer old content
  write_file_atomically(target, "");
  EXPECT_EQ(read_all(target), "");
  EXPECT_EQ(entries_in(folder), 1u);
}

TEST(AtomicFile, CreatesMissingParentFolders) {
  const fs::path folder = fresh_folder("parents");
  const fs::path target = folder / "a" / "b" / "c.txt";
  write_file_atomically(target, "deep");
  EXPECT_EQ(read_all(target), "deep");
}

TEST(AtomicFile, ParentThatIsAFileThrowsNamingThePath) {
  // Tests run as root in CI containers, so permission bits cannot make a path unwritable;
  // a regular file used as a folder fails for every user.
  const fs::path folder = fresh_folder("parent_is_file");
  write_file_atomically(folder / "plain", "x");
  const fs::path target = folder / "plain" / "out.txt";
  try {
    write_file_atomically(target, "data");
    FAIL() << "expected std::runtime_error";
  } catch (const std::runtime_error& error) {
    EXPECT_NE(std::string(error.what()).find(target.string()), std::string::npos) << error.what();
  }
}

TEST(AtomicFile, TargetThatIsAFolderThrowsAndLeavesNoTemporary) {
  const fs::path folder = fresh_folder("target_is_folder");
  const fs::path target = folder / "occupied";
  fs::create_directories(target / "inside");
  try {
    write_file_atomically(target, "data");
    FAIL() << "expected std::runtime_error";
  } catch (const std::runtime_error& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find(target.string()), std::string::npos) << message;
    EXPECT_NE(message.find("directory"), std::string::npos) << "strerror missing: " << message;
  }
  EXPECT_EQ(entries_in(folder), 1u);  // only the folder itself; the temporary was removed
  EXPECT_TRUE(fs::is_directory(target / "inside"));
}

}  // namespace
}  // namespace quarry
