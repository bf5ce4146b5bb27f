// `quarry udf build` (issue #18 §4): the seed's `acuMakeLib -src usrStokesDrag.c` — a library
// beside the source, the command printed, extra flags passed on, a compile error exit 2 with
// gcc's file:line:col, a library that would not load exit 2 with the loader's error, a missing
// source exit 2, the header's folder and the compiler from the environment; and docs/cfd.md's
// example is the example file.
#include <gtest/gtest.h>

#include <string>

#include "udf/udf_test_support.h"

namespace quarry::udf_testing {
namespace {

const std::string kStokesSource = "/examples/stokes_settling/usrStokesDrag.c";

// Whether `output` holds a compiler diagnostic "FILE:LINE:COL: error: " for `file` (no
// std::regex: GCC 12's <regex> trips -Wmaybe-uninitialized in the sanitizer build).
bool has_compiler_error_line(const std::string& output, const std::string& file) {
  const auto digits = [&](std::size_t& at) {
    const std::size_t start = at;
    while (at < output.size() && output[at] >= '0' && output[at] <= '9') ++at;
    return at > start;
  };
  for (std::size_t at = output.find(file + ":"); at != std::string::npos;
       at = output.find(file + ":", at + 1)) {
    std::size_t k = at + file.size() + 1;
    if (!digits(k) || k >= output.size() || output[k] != ':') continue;
    ++k;
    if (digits(k) && output.compare(k, 9, ": error: ") == 0) return true;
  }
  return false;
}

TEST(UdfBuild, WritesTheLibraryBesideTheSource) {
  TemporaryFolder folder;
  const fs::path source = folder.path() / "usrStokesDrag.c";
  fs::copy_file(source_dir() + kStokesSource, source);
  const Finished built = quarry_udf_build({source.string()});
  ASSERT_EQ(built.exit_code, 0) << built.output;
  EXPECT_TRUE(fs::is_regular_file(folder.path() / "usrStokesDrag.so"));
  // The command, then what it wrote and the functions it exports.
  const std::size_t command =
      built.output.find("quarry udf build: cc -shared -fPIC -O2 -ffp-contract=off -Wall -I ");
  ASSERT_NE(command, std::string::npos) << built.output;
  EXPECT_NE(built.output.find("/include -o ", command), std::string::npos) << built.output;
  EXPECT_NE(built.output.find("-o " + (folder.path() / "usrStokesDrag.so").string() + " " +
                              source.string() + " -lm\n"),
            std::string::npos)
      << built.output;
  EXPECT_NE(
      built.output.find("quarry udf build: wrote " + (folder.path() / "usrStokesDrag.so").string() +
                        " (drag UDF ABI 1.0)\n"),
      std::string::npos)
      << built.output;
  EXPECT_EQ(built.output.find("warning"), std::string::npos)
      << "the example compiles cleanly with -Wall";
}

TEST(UdfBuild, OutputAndCompilerFlags) {
  TemporaryFolder folder;
  const fs::path source = folder.path() / "scaled.c";
  write_text(source, R"(
#include <quarry/drag_udf.h>
#ifndef SCALE
#error SCALE is not defined
#endif
QUARRY_DRAG_UDF_EXPORT_ABI()
QUARRY_DRAG_UDF_PROTOTYPE(usrScaled);
int usrScaled(const quarry_drag_input* in, quarry_drag_output* out, void* user) {
  (void)in; (void)user; out->force[0] = SCALE; return 0;
}
)");
  // A folder that does not exist yet is made.
  const fs::path output = folder.path() / "lib" / "other name.so";
  Finished built =
      quarry_udf_build({source.string(), "-o", output.string(), "--cflags=-DSCALE=2.5 -O1"});
  ASSERT_EQ(built.exit_code, 0) << built.output;
  EXPECT_TRUE(fs::is_regular_file(output));
  EXPECT_FALSE(fs::exists(folder.path() / "scaled.so"));
  // The printed command quotes the path with a space, and the flags come after the source.
  EXPECT_NE(built.output.find("-o '" + output.string() + "' " + source.string() +
                              " -DSCALE=2.5 -O1 -lm\n"),
            std::string::npos)
      << built.output;
  // Repeated, and as the next argument.
  built = quarry_udf_build({source.string(), "--cflags", "-DSCALE=1", "--cflags", "-Wextra"});
  EXPECT_EQ(built.exit_code, 0) << built.output;
  EXPECT_NE(built.output.find(" -DSCALE=1 -Wextra -lm\n"), std::string::npos) << built.output;
}

TEST(UdfBuild, CompileErrorExits2WithTheCompilersLine) {
  TemporaryFolder folder;
  const fs::path source = folder.path() / "broken.c";
  write_text(source,
             "#include <quarry/drag_udf.h>\nQUARRY_DRAG_UDF_EXPORT_ABI()\n"
             "int usrBroken(void) {\n  return 0\n}\n");
  const Finished built = quarry_udf_build({source.string()});
  EXPECT_EQ(built.exit_code, 2) << built.output;
  EXPECT_TRUE(has_compiler_error_line(built.output, "broken.c")) << built.output;
  EXPECT_NE(built.output.find("quarry: error: the C compiler failed (exit status 1); " +
                              (folder.path() / "broken.so").string() + " was not built"),
            std::string::npos)
      << built.output;
  EXPECT_FALSE(fs::exists(folder.path() / "broken.so"));
}

TEST(UdfBuild, MissingSourceExits2) {
  TemporaryFolder folder;
  const fs::path source = folder.path() / "usrNowhere.c";
  Finished built = quarry_udf_build({source.string()});
  EXPECT_EQ(built.exit_code, 2) << built.output;
  EXPECT_NE(built.output.find(source.string() +
                              ": error: no such file: the UDF's C source was not found"),
            std::string::npos)
      << built.output;
  EXPECT_NE(built.output.find("hint: "), std::string::npos) << built.output;
  built = quarry_udf_build({folder.path().string()});
  EXPECT_EQ(built.exit_code, 2) << built.output;
  EXPECT_NE(built.output.find("error: this is not a regular file"), std::string::npos)
      << built.output;
  built = run({QUARRY_BIN, "udf", "build"});
  EXPECT_EQ(built.exit_code, 2) << built.output;
  EXPECT_NE(built.output.find("source is required"), std::string::npos) << built.output;
}

// A library that compiles but would not load is refused now, not at the run: no ABI function, a
// symbol nobody defines.
TEST(UdfBuild, LibraryThatWouldNotLoadExits2) {
  TemporaryFolder folder;
  const fs::path no_abi = folder.path() / "noabi.c";
  write_text(no_abi,
             "#include <quarry/drag_udf.h>\nQUARRY_DRAG_UDF_PROTOTYPE(usrNoAbi);\n"
             "int usrNoAbi(const quarry_drag_input* in, quarry_drag_output* out, void* user) {\n"
             "  (void)in; (void)out; (void)user; return 0;\n}\n");
  Finished built = quarry_udf_build({no_abi.string()});
  EXPECT_EQ(built.exit_code, 2) << built.output;
  EXPECT_NE(built.output.find("quarry: error: drag UDF library \"" +
                              (folder.path() / "noabi.so").string() +
                              "\" has no function quarry_drag_udf_abi"),
            std::string::npos)
      << built.output;
  const fs::path unresolved = folder.path() / "unresolved.c";
  write_text(
      unresolved,
      "#include <quarry/drag_udf.h>\nQUARRY_DRAG_UDF_EXPORT_ABI()\n"
      "double usr_helper_nobody_defines(double);\nQUARRY_DRAG_UDF_PROTOTYPE(usrUnresolved);\n"
      "int usrUnresolved(const quarry_drag_input* in, quarry_drag_output* out, void* user) {\n"
      "  (void)user; out->force[0] = usr_helper_nobody_defines(in->porosity); return 0;\n}\n");
  built = quarry_udf_build({unresolved.string()});
  EXPECT_EQ(built.exit_code, 2) << built.output;
  EXPECT_NE(built.output.find("undefined symbol: usr_helper_nobody_defines"), std::string::npos)
      << built.output;
  EXPECT_NE(built.output.find("--cflags \"-lNAME\" links a library it needs"), std::string::npos)
      << built.output;
}

// QUARRY_UDF_INCLUDE_DIR replaces the header's folder: here one whose drag_udf.h announces ABI
// 2.0, so the library built is refused by this Quarry (ABI 1.x) and the build exits 2; a folder
// without the header is an error, not a fallback. QUARRY_UDF_CC replaces the compiler.
TEST(UdfBuild, HeaderFolderAndCompilerFromTheEnvironment) {
  TemporaryFolder folder;
  const fs::path future = folder.path() / "future";
  fs::create_directories(future / "quarry");
  std::string header = read_text(source_dir() + "/include/quarry/drag_udf.h");
  const std::string major = "#define QUARRY_DRAG_UDF_ABI_MAJOR 1\n";
  ASSERT_NE(header.find(major), std::string::npos);
  header.replace(header.find(major), major.size(), "#define QUARRY_DRAG_UDF_ABI_MAJOR 2\n");
  write_text(future / "quarry/drag_udf.h", header);
  const fs::path source = folder.path() / "usrStokesDrag.c";
  fs::copy_file(source_dir() + kStokesSource, source);

  Finished built = run({"env", "QUARRY_UDF_INCLUDE_DIR=" + future.string(), QUARRY_BIN, "udf",
                        "build", source.string()});
  EXPECT_EQ(built.exit_code, 2) << built.output;
  EXPECT_NE(built.output.find(" -I " + future.string() + " "), std::string::npos) << built.output;
  EXPECT_NE(built.output.find("was built for drag UDF ABI 2.0, this Quarry loads ABI 1.x"),
            std::string::npos)
      << built.output;

  built = run({"env", "QUARRY_UDF_INCLUDE_DIR=" + folder.path().string(), QUARRY_BIN, "udf",
               "build", source.string()});
  EXPECT_EQ(built.exit_code, 2) << built.output;
  EXPECT_NE(built.output.find("quarry: error: cannot find quarry/drag_udf.h: looked for " +
                              (folder.path() / "quarry/drag_udf.h").string()),
            std::string::npos)
      << built.output;

  built = run({"env", "QUARRY_UDF_CC=" + (folder.path() / "no-such-cc").string(), QUARRY_BIN, "udf",
               "build", source.string()});
  EXPECT_EQ(built.exit_code, 2) << built.output;
  EXPECT_NE(
      built.output.find("quarry: error: cannot run the C compiler \"" +
                        (folder.path() / "no-such-cc").string() + "\": No such file or directory"),
      std::string::npos)
      << built.output;
}

// docs/cfd.md shows the example in full: its C block is the file.
TEST(UdfBuild, DocsShowTheExample) {
  const std::string docs = read_text(source_dir() + "/docs/cfd.md");
  const std::size_t section = docs.find("## User-defined drag (UDF)");
  ASSERT_NE(section, std::string::npos);
  const std::size_t begin = docs.find("```c\n", section);
  ASSERT_NE(begin, std::string::npos);
  const std::size_t end = docs.find("```\n", begin + 5);
  ASSERT_NE(end, std::string::npos);
  EXPECT_EQ(docs.substr(begin + 5, end - begin - 5), read_text(source_dir() + kStokesSource));
}

}  // namespace
}  // namespace quarry::udf_testing
