// Helpers for the user-defined drag tests: a temporary folder per test, the quarry binary run
// with its output collected, and a UDF built from a source string with `quarry udf build` or,
// for a library that command refuses to write, with the C compiler directly.
#pragma once

#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace quarry::udf_testing {

namespace fs = std::filesystem;

inline std::string source_dir() {
  return QUARRY_SOURCE_DIR;
}

inline std::string read_text(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

inline void write_text(const fs::path& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

// A fresh folder under the system's temporary folder, removed with the object.
class TemporaryFolder {
 public:
  TemporaryFolder() {
    std::string pattern = (fs::temp_directory_path() / "quarry_udf_test_XXXXXX").string();
    if (::mkdtemp(pattern.data()) == nullptr) ADD_FAILURE() << "mkdtemp failed: " << errno;
    path_ = pattern;
  }
  ~TemporaryFolder() {
    std::error_code ignored;
    fs::remove_all(path_, ignored);
  }
  TemporaryFolder(const TemporaryFolder&) = delete;
  TemporaryFolder& operator=(const TemporaryFolder&) = delete;
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

struct Finished {
  int exit_code = -1;  // 128 + signal if a signal ended it
  std::string output;  // stdout and stderr, merged
};

// Runs argv[0] (a path, or a name searched for in PATH) with argv and collects its output.
inline Finished run(const std::vector<std::string>& argv) {
  std::vector<char*> args;
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  int ends[2];
  if (::pipe(ends) != 0) return {};
  const pid_t child = ::fork();
  if (child == 0) {
    ::dup2(ends[1], 1);
    ::dup2(ends[1], 2);
    ::close(ends[0]);
    ::close(ends[1]);
    ::execvp(args[0], args.data());
    ::_exit(127);
  }
  ::close(ends[1]);
  Finished finished;
  char buffer[4096];
  for (ssize_t n; (n = ::read(ends[0], buffer, sizeof buffer)) != 0;) {
    if (n > 0)
      finished.output.append(buffer, static_cast<std::size_t>(n));
    else if (errno != EINTR)
      break;
  }
  ::close(ends[0]);
  int status = 0;
  while (::waitpid(child, &status, 0) < 0 && errno == EINTR) {
  }
  finished.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  return finished;
}

// `quarry udf build` with these arguments.
inline Finished quarry_udf_build(const std::vector<std::string>& arguments) {
  std::vector<std::string> argv = {QUARRY_BIN, "udf", "build"};
  argv.insert(argv.end(), arguments.begin(), arguments.end());
  return run(argv);
}

// Writes `source` to folder/NAME.c and builds folder/NAME.so with `quarry udf build` (which must
// succeed); returns the library's path.
inline std::string build_udf(const fs::path& folder, const std::string& name,
                             const std::string& source) {
  const fs::path source_path = folder / (name + ".c");
  write_text(source_path, source);
  const Finished built = quarry_udf_build({source_path.string()});
  EXPECT_EQ(built.exit_code, 0) << built.output;
  return (folder / (name + ".so")).string();
}

// Writes `source` to folder/NAME.c and compiles folder/NAME.so with `cc` and the flags of
// `quarry udf build`, without its load check (a library without the ABI function, or with a
// symbol nobody defines, for the loader's own errors); returns the library's path.
inline std::string compile_directly(const fs::path& folder, const std::string& name,
                                    const std::string& source) {
  const fs::path source_path = folder / (name + ".c");
  const fs::path library = folder / (name + ".so");
  write_text(source_path, source);
  const Finished built = run({"cc", "-shared", "-fPIC", "-O2", "-I", source_dir() + "/include",
                              "-o", library.string(), source_path.string(), "-lm"});
  EXPECT_EQ(built.exit_code, 0) << built.output;
  return library.string();
}

// The example copied into `folder` and built there by `quarry udf build`: usrStokesDrag.so beside
// the copy (the source tree is not written to).
inline std::string build_stokes_example(const fs::path& folder) {
  const std::string source = read_text(source_dir() + "/examples/stokes_settling/usrStokesDrag.c");
  EXPECT_FALSE(source.empty());
  return build_udf(folder, "usrStokesDrag", source);
}

}  // namespace quarry::udf_testing
