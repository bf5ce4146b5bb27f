// `quarry udf build`: the compiler command, run with posix_spawnp (no shell, so no quoting of
// the user's paths), its merged output read through a pipe; the header's folder from an
// environment variable, the installed tree or the source tree (src/cli/CMakeLists.txt).
#include "cli/udf_build.h"

#include <fmt/format.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <ostream>
#include <sstream>
#include <system_error>

#include "cfd/drag_udf.h"
#include "core/diagnostics.h"

extern char** environ;

#ifndef QUARRY_UDF_SOURCE_INCLUDE_DIR
#define QUARRY_UDF_SOURCE_INCLUDE_DIR ""
#endif

namespace quarry::cli {
namespace {

namespace fs = std::filesystem;

constexpr const char* kHeader = "quarry/drag_udf.h";
// Where the installed tree keeps the header, seen from the binary: the install() destinations
// bin (src/cli/CMakeLists.txt) and include/quarry (src/api/CMakeLists.txt).
constexpr const char* kIncludeFromBinary = "../include";

// The folders that may hold quarry/drag_udf.h, in the order tried: $QUARRY_UDF_INCLUDE_DIR, an
// installed tree's <prefix>/include beside <prefix>/bin/quarry, the source tree this binary was
// built from. A set variable is the only candidate: a wrong one is an error, not a fallback.
std::vector<fs::path> include_candidates() {
  if (const char* variable = std::getenv("QUARRY_UDF_INCLUDE_DIR"); variable && *variable)
    return {fs::path(variable)};
  std::vector<fs::path> folders;
  std::error_code error;
  const fs::path binary = fs::read_symlink("/proc/self/exe", error);
  if (!error) folders.push_back((binary.parent_path() / kIncludeFromBinary).lexically_normal());
  if (std::strlen(QUARRY_UDF_SOURCE_INCLUDE_DIR) > 0)
    folders.emplace_back(QUARRY_UDF_SOURCE_INCLUDE_DIR);
  return folders;
}

fs::path find_include_folder() {
  const std::vector<fs::path> folders = include_candidates();
  std::error_code error;
  for (const fs::path& folder : folders)
    if (fs::is_regular_file(folder / kHeader, error)) return folder;
  std::vector<std::string> names;
  for (const fs::path& folder : folders) names.push_back((folder / kHeader).string());
  throw UserError(
      SourceLocation{},
      fmt::format("cannot find {}: looked for {}", kHeader, fmt::join(names, " and ")),
      "install Quarry with \"cmake --install\" (the header goes to <prefix>/include), or "
      "set QUARRY_UDF_INCLUDE_DIR to the folder that holds quarry/drag_udf.h");
}

std::string compiler() {
  if (const char* variable = std::getenv("QUARRY_UDF_CC"); variable && *variable) return variable;
  return "cc";
}

std::vector<std::string> split_at_spaces(const std::string& text) {
  std::vector<std::string> words;
  std::istringstream stream(text);
  for (std::string word; stream >> word;) words.push_back(word);
  return words;
}

// The argument as a shell would need it, for the command line printed.
std::string quoted(const std::string& argument) {
  if (!argument.empty() && argument.find_first_of(" \t\n'\"\\$`*?;&|<>()#~") == std::string::npos)
    return argument;
  std::string text = "'";
  for (const char c : argument) text += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return text + "'";
}

struct Finished {
  int exit_code = 0;    // the command's exit status; 128 + signal if a signal ended it
  std::string output;   // its stdout and stderr, merged
  int spawn_error = 0;  // non-zero: it could not be started (an errno value)
};

// Runs argv (the program searched for in PATH) and collects its output.
Finished run(const std::vector<std::string>& argv) {
  Finished finished;
  std::vector<char*> args;
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  int pipe_ends[2];
  if (::pipe(pipe_ends) != 0)
    throw std::system_error(errno, std::generic_category(), "quarry udf build: pipe");
  posix_spawn_file_actions_t actions;
  ::posix_spawn_file_actions_init(&actions);
  ::posix_spawn_file_actions_adddup2(&actions, pipe_ends[1], 1);
  ::posix_spawn_file_actions_adddup2(&actions, pipe_ends[1], 2);
  ::posix_spawn_file_actions_addclose(&actions, pipe_ends[0]);
  ::posix_spawn_file_actions_addclose(&actions, pipe_ends[1]);
  pid_t child = 0;
  finished.spawn_error = ::posix_spawnp(&child, args[0], &actions, nullptr, args.data(), environ);
  ::posix_spawn_file_actions_destroy(&actions);
  ::close(pipe_ends[1]);
  if (finished.spawn_error != 0) {
    ::close(pipe_ends[0]);
    return finished;
  }
  char buffer[4096];
  for (;;) {
    const ssize_t n = ::read(pipe_ends[0], buffer, sizeof buffer);
    if (n > 0)
      finished.output.append(buffer, static_cast<std::size_t>(n));
    else if (n == 0 || errno != EINTR)
      break;
  }
  ::close(pipe_ends[0]);
  int status = 0;
  while (::waitpid(child, &status, 0) < 0 && errno == EINTR) {
  }
  finished.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  return finished;
}

}  // namespace

int udf_build(const UdfBuildOptions& options, std::ostream& out, std::ostream& err) {
  const fs::path source = options.source;
  std::error_code error;
  const fs::file_status status = fs::status(source, error);
  if (!fs::exists(status))
    throw UserError(SourceLocation{options.source},
                    "no such file: the UDF's C source was not found",
                    "give the path of the .c file that defines the drag function, e.g. "
                    "\"quarry udf build usrStokesDrag.c\"");
  if (!fs::is_regular_file(status))
    throw UserError(SourceLocation{options.source},
                    "this is not a regular file: give the UDF's C source");
  const fs::path output =
      options.output.empty() ? fs::path(source).replace_extension(".so") : fs::path(options.output);
  if (fs::equivalent(source, output, error))
    throw UserError(SourceLocation{options.source}, "the library would overwrite its own source",
                    "name the source NAME.c, or give another output with -o");
  if (output.has_parent_path()) {
    fs::create_directories(output.parent_path(), error);
    if (error)
      throw UserError(SourceLocation{output.string()},
                      fmt::format("cannot create the library's folder: {}", error.message()));
  }

  // -ffp-contract=off as Quarry's own build (CMakeLists.txt): no fused multiply-adds, so a UDF
  // and a built-in law that do the same operations round alike. The user's arguments come after
  // the source, so that -l libraries are linked and -O given there overrides ours.
  std::vector<std::string> argv = {compiler(),
                                   "-shared",
                                   "-fPIC",
                                   "-O2",
                                   "-ffp-contract=off",
                                   "-Wall",
                                   "-I",
                                   find_include_folder().string(),
                                   "-o",
                                   output.string(),
                                   source.string()};
  for (const std::string& flags : options.cflags)
    for (std::string& word : split_at_spaces(flags)) argv.push_back(std::move(word));
  argv.emplace_back("-lm");

  std::vector<std::string> shown;
  for (const std::string& a : argv) shown.push_back(quoted(a));
  out << fmt::format("quarry udf build: {}\n", fmt::join(shown, " ")) << std::flush;
  const Finished finished = run(argv);
  err << finished.output << std::flush;
  if (finished.spawn_error != 0) {
    err << fmt::format(
        "quarry: error: cannot run the C compiler \"{}\": {}\n"
        "  hint: install one (Debian: apt install gcc) so that \"cc\" is in PATH, or "
        "set QUARRY_UDF_CC\n",
        argv[0], std::strerror(finished.spawn_error));
    return 2;
  }
  if (finished.exit_code != 0) {
    err << fmt::format("quarry: error: the C compiler failed (exit status {}); {} was not built\n",
                       finished.exit_code, output.string());
    return 2;
  }

  // Loaded as a run would load it: an unresolved symbol or a missing ABI function is found now.
  std::uint32_t abi_version = 0;
  try {
    cfd::open_drag_udf_library(output.string(), abi_version);
  } catch (const UserError& e) {
    err << e.diagnostics().format();
    return 2;
  }
  out << fmt::format("quarry udf build: wrote {} (drag UDF ABI {}.{})\n", output.string(),
                     abi_version >> 16, abi_version & 0xffffu);
  return 0;
}

}  // namespace quarry::cli
