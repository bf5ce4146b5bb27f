// User-defined drag failures (issue #18 §4): each way a library fails to load is a user error
// placed at the deck's key, with a hint (exit 2 in a run); each way a call fails is a
// DragUdfError naming the particle, every input and the UDF's message (exit 3 in a run).
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

#include "cfd/drag_laws.h"
#include "cfd/drag_udf.h"
#include "core/diagnostics.h"
#include "udf/udf_test_support.h"

namespace quarry::cfd {
namespace {

namespace fs = std::filesystem;
using udf_testing::build_stokes_example;
using udf_testing::build_udf;
using udf_testing::compile_directly;
using udf_testing::TemporaryFolder;

// The diagnostics of a UserError as the CLI prints them.
template <class Call>
std::string user_error_text(Call call) {
  try {
    call();
  } catch (const UserError& e) {
    return e.diagnostics().format();
  }
  ADD_FAILURE() << "no UserError";
  return {};
}

// A failed call's DragUdfError (a PhysicsError: exit 3 in a run).
template <class Call>
DragUdfError udf_error(Call call) {
  try {
    call();
  } catch (const DragUdfError& e) {
    return e;
  }
  ADD_FAILURE() << "no DragUdfError";
  return DragUdfError("", quarry_drag_input{}, "");
}

template <class Call>
std::string physics_error_text(Call call) {
  return udf_error(call).what();
}

// The input of the failing calls below, every value distinct so that the message shows each.
DragInput failing_input() {
  DragInput input;
  input.diameter = 1e-4;
  input.particle_velocity = {0.001, -0.002, -0.0027};
  input.fluid_velocity = {0.0, 0.0, 0.0005};
  input.porosity = 0.4;
  input.fluid_viscosity = 1e-3;
  input.fluid_density = 1000.0;
  return input;
}

DragUdfContext failing_context() {
  DragUdfContext context;
  context.pressure_gradient = {0.0, 0.0, -9810.0};
  context.particle_id = 42;
  context.particle_type = 3;
  context.time = 0.0125;
  return context;
}

// Every value of failing_input and failing_context in the message, with its unit. The volume and
// Re_p are derived (π d³/6 and ρ_f ε |u − v| d / μ = 0.156…), printed as fmt prints them.
void expect_every_input(const std::string& text) {
  const std::string volume = fmt::format("particle_volume {} m³", particle_volume(failing_input()));
  const std::string reynolds =
      fmt::format("reynolds_number {}\n", superficial_reynolds_number(failing_input()));
  for (const std::string& shown :
       {std::string("for particle id 42 (type 3)"), std::string("t = 0.0125 s: drag UDF"), volume,
        std::string("particle_diameter 0.0001 m"),
        std::string("particle_velocity (0.001, -0.002, -0.0027) m/s"),
        std::string("fluid_velocity (0, 0, 0.0005) m/s"), std::string("porosity 0.4,"),
        std::string("fluid_viscosity 0.001 Pa·s"), std::string("fluid_density 1000 kg/m³"),
        std::string("pressure_gradient (0, 0, -9810) Pa/m"), reynolds})
    EXPECT_NE(text.find(shown), std::string::npos) << "missing \"" << shown << "\" in:\n" << text;
  EXPECT_NEAR(superficial_reynolds_number(failing_input()), 0.15615, 1e-5);
}

TEST(DragUdfErrors, MissingLibrary) {
  TemporaryFolder folder;
  const std::string path = (folder.path() / "usrNowhere.so").string();
  const std::string text = user_error_text([&] { load_drag_udf(path, "usrNowhere"); });
  EXPECT_NE(text.find("quarry: error: drag UDF library \"" + path + "\" does not exist"),
            std::string::npos)
      << text;
  EXPECT_NE(
      text.find("hint: build the library from its C source with \"quarry udf build SOURCE.c\""),
      std::string::npos)
      << text;
}

// Given the deck's place, the error is the deck's `file:line:col: error:` with the line echoed.
TEST(DragUdfErrors, ErrorsPointAtTheDeck) {
  TemporaryFolder folder;
  const fs::path deck = folder.path() / "deck.yaml";
  udf_testing::write_text(
      deck, "fluid:\n  drag_udf:\n    library: usrMissing.so\n    function: usrMissing\n");
  const std::string path = (folder.path() / "usrMissing.so").string();
  const SourceLocation library_key{deck.string(), 3, 14}, function_key{deck.string(), 4, 15};
  std::string text =
      user_error_text([&] { load_drag_udf(path, "usrMissing", library_key, function_key); });
  EXPECT_EQ(text.rfind(deck.string() + ":3:14: error: drag UDF library \"", 0), 0u) << text;
  EXPECT_NE(text.find("    3 |     library: usrMissing.so\n"), std::string::npos) << text;
  // A missing function points at the function's key.
  const std::string library = build_stokes_example(folder.path());
  text = user_error_text([&] { load_drag_udf(library, "usrMissing", library_key, function_key); });
  EXPECT_EQ(text.rfind(deck.string() + ":4:15: error: drag UDF library", 0), 0u) << text;
}

TEST(DragUdfErrors, FolderAndFileThatIsNoLibrary) {
  TemporaryFolder folder;
  std::string text =
      user_error_text([&] { load_drag_udf(folder.path().string(), "usrStokesDrag"); });
  EXPECT_NE(text.find("is a folder, not a shared library"), std::string::npos) << text;
  // The C source given for the library, a likely slip.
  const fs::path fake = folder.path() / "usrStokesDrag.c";
  fs::copy_file(udf_testing::source_dir() + "/examples/stokes_settling/usrStokesDrag.c", fake);
  text = user_error_text([&] { load_drag_udf(fake.string(), "usrStokesDrag"); });
  EXPECT_NE(text.find("cannot load drag UDF library \"" + fake.string() + "\": "),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("invalid ELF header"), std::string::npos) << "dlerror's text: " << text;
  EXPECT_NE(text.find("hint: it must be a shared library for this machine"), std::string::npos)
      << text;
}

// A symbol the library needs and nobody defines: dlopen (RTLD_NOW) refuses it, naming it.
TEST(DragUdfErrors, UnresolvedSymbol) {
  TemporaryFolder folder;
  const std::string library = compile_directly(folder.path(), "unresolved", R"(
#include <quarry/drag_udf.h>
QUARRY_DRAG_UDF_EXPORT_ABI()
double usr_helper_nobody_defines(double);
QUARRY_DRAG_UDF_PROTOTYPE(usrUnresolved);
int usrUnresolved(const quarry_drag_input* in, quarry_drag_output* out, void* user) {
  (void)user;
  out->force[0] = usr_helper_nobody_defines(in->porosity);
  return 0;
}
)");
  const std::string text = user_error_text([&] { load_drag_udf(library, "usrUnresolved"); });
  EXPECT_NE(text.find("undefined symbol: usr_helper_nobody_defines"), std::string::npos) << text;
}

TEST(DragUdfErrors, NoAbiFunction) {
  TemporaryFolder folder;
  const std::string library = compile_directly(folder.path(), "noabi", R"(
#include <quarry/drag_udf.h>
QUARRY_DRAG_UDF_PROTOTYPE(usrNoAbi);
int usrNoAbi(const quarry_drag_input* in, quarry_drag_output* out, void* user) {
  (void)in; (void)out; (void)user;
  return 0;
}
)");
  const std::string text = user_error_text([&] { load_drag_udf(library, "usrNoAbi"); });
  EXPECT_NE(
      text.find("has no function quarry_drag_udf_abi: it was not built against quarry/drag_udf.h"),
      std::string::npos)
      << text;
  EXPECT_NE(text.find("hint: its source must include <quarry/drag_udf.h> and contain "
                      "QUARRY_DRAG_UDF_EXPORT_ABI() once"),
            std::string::npos)
      << text;
}

// A library of ABI 2.3 (as a later drag_udf.h would make it), written without the header.
TEST(DragUdfErrors, OtherAbiMajor) {
  TemporaryFolder folder;
  const std::string library = compile_directly(folder.path(), "future", R"(
#include <stdint.h>
uint32_t quarry_drag_udf_abi(void) { return (2u << 16) | 3u; }
int usrFuture(const void* in, void* out, void* user) { (void)in; (void)out; (void)user; return 0; }
)");
  const std::string text = user_error_text([&] { load_drag_udf(library, "usrFuture"); });
  EXPECT_NE(
      text.find(
          "was built for drag UDF ABI 2.3, this Quarry loads ABI 1.x (its drag_udf.h is 1.0)"),
      std::string::npos)
      << text;
  EXPECT_NE(
      text.find(
          "hint: rebuild it from its source with this Quarry's \"quarry udf build SOURCE.c\""),
      std::string::npos)
      << text;
}

TEST(DragUdfErrors, MissingFunction) {
  TemporaryFolder folder;
  const std::string library = build_stokes_example(folder.path());
  const std::string text = user_error_text([&] { load_drag_udf(library, "usrStokesDarg"); });
  EXPECT_NE(
      text.find("error: drag UDF library \"" + library + "\" has no function \"usrStokesDarg\""),
      std::string::npos)
      << text;
  EXPECT_NE(
      text.find(
          "hint: check the name's spelling and case; a drag function must be exported with C "
          "linkage and not be static: declare it with QUARRY_DRAG_UDF_PROTOTYPE(usrStokesDarg)"),
      std::string::npos)
      << text;
  EXPECT_NE(text.find("\"nm -D --defined-only " + library + "\" lists what the library exports"),
            std::string::npos)
      << text;
  // A function of a library it depends on is not the library's own: libm's exp is refused.
  const std::string libm = user_error_text([&] { load_drag_udf(library, "exp"); });
  EXPECT_NE(libm.find("has no function \"exp\""), std::string::npos) << libm;
  EXPECT_NE(user_error_text([&] {
              load_drag_udf(library, "quarry_drag_udf_abi");
            }).find("is the library's ABI version, not a drag function"),
            std::string::npos);
}

// Functions the library defines but does not export — static, hidden, or with a C++ (mangled)
// name — are not found: the error names the function, the hint says how to export it.
TEST(DragUdfErrors, FunctionNotExported) {
  TemporaryFolder folder;
  const std::string body =
      "(const quarry_drag_input* in, quarry_drag_output* out, void* user) {\n"
      "  (void)in; (void)user; out->force[0] = 1.0; return 0;\n}\n";
  const std::string header = "#include <quarry/drag_udf.h>\nQUARRY_DRAG_UDF_EXPORT_ABI()\n";
  const std::string static_library = build_udf(
      folder.path(), "static_udf",
      header + "static __attribute__((used)) int usrStatic" + body +
          "QUARRY_DRAG_UDF_PROTOTYPE(usrKeep);\n" +
          "int usrKeep(const quarry_drag_input* in, quarry_drag_output* out, void* user) " +
          "{ return usrStatic(in, out, user); }\n");
  const std::string hidden_library =
      build_udf(folder.path(), "hidden_udf",
                header + "__attribute__((visibility(\"hidden\"))) int usrHidden" + body);
  // C++ without extern "C", compiled as C++ by the C compiler's driver.
  const fs::path cxx_source = folder.path() / "cxx_udf.c";
  udf_testing::write_text(
      cxx_source, header + "__attribute__((visibility(\"default\"))) int usrMangled" + body);
  const std::string cxx_library = (folder.path() / "cxx_udf.so").string();
  const udf_testing::Finished built = udf_testing::run({"cc", "-x", "c++", "-shared", "-fPIC", "-I",
                                                        udf_testing::source_dir() + "/include",
                                                        "-o", cxx_library, cxx_source.string()});
  ASSERT_EQ(built.exit_code, 0) << built.output;
  for (const auto& [library, function] :
       {std::pair{static_library, "usrStatic"}, std::pair{hidden_library, "usrHidden"},
        std::pair{cxx_library, "usrMangled"}}) {
    const std::string text = user_error_text([&] { load_drag_udf(library, function); });
    EXPECT_NE(text.find("has no function \"" + std::string(function) + "\""), std::string::npos)
        << text;
    EXPECT_NE(text.find("QUARRY_DRAG_UDF_PROTOTYPE(" + std::string(function) +
                        ") (which also makes it extern \"C\" in C++)"),
              std::string::npos)
        << text;
  }
  // The exported one of the first library loads.
  EXPECT_EQ(load_drag_udf(static_library, "usrKeep").evaluate(failing_input()).force.x, 1.0);
}

TEST(DragUdfErrors, UdfReportsAnError) {
  TemporaryFolder folder;
  const std::string library = build_udf(folder.path(), "refuses", R"(
#include <quarry/drag_udf.h>
QUARRY_DRAG_UDF_EXPORT_ABI()
QUARRY_DRAG_UDF_PROTOTYPE(usrRefuses);
int usrRefuses(const quarry_drag_input* in, quarry_drag_output* out, void* user) {
  (void)user;
  if (in->porosity < 0.5) {
    out->force[0] = 1.0;  /* ignored: the call failed */
    quarry_drag_fail(out, "porosity below 0.5: this law is for dilute flow");
    return 7;
  }
  return 0;
}
)");
  const DragUdf udf = load_drag_udf(library, "usrRefuses");
  const DragUdfError error = udf_error([&] { udf.evaluate(failing_input(), failing_context()); });
  // Typed: what the UDF got and said, for a caller that adds the step.
  EXPECT_EQ(error.udf_message(), "porosity below 0.5: this law is for dilute flow");
  EXPECT_EQ(error.input().particle_id, 42u);
  EXPECT_EQ(error.input().porosity, 0.4);
  EXPECT_NO_THROW(udf.evaluate([] {
    DragInput input = failing_input();
    input.porosity = 1.0;
    return input;
  }()));  // ε = 1: accepted
  const std::string text = error.what();
  EXPECT_NE(text.find("drag UDF \"usrRefuses\" (" + library +
                      ") returned 7 for particle id 42 (type 3)\n"
                      "  its message: porosity below 0.5: this law is for dilute flow\n"),
            std::string::npos)
      << text;
  expect_every_input(text);
  EXPECT_NE(text.find("  hint: "), std::string::npos) << text;
}

TEST(DragUdfErrors, UdfGivesNaNOrABadCoefficient) {
  TemporaryFolder folder;
  const std::string library = build_udf(folder.path(), "nan", R"(
#include <math.h>
#include <quarry/drag_udf.h>
QUARRY_DRAG_UDF_EXPORT_ABI()
QUARRY_DRAG_UDF_PROTOTYPE(usrNaN);
QUARRY_DRAG_UDF_PROTOTYPE(usrNegative);
QUARRY_DRAG_UDF_PROTOTYPE(usrLongMessage);
int usrNaN(const quarry_drag_input* in, quarry_drag_output* out, void* user) {
  (void)user;
  out->force[2] = sqrt(in->fluid_velocity[2] - 1.0);  /* a root of a negative number */
  return 0;
}
int usrNegative(const quarry_drag_input* in, quarry_drag_output* out, void* user) {
  (void)in; (void)user;
  out->drag_coefficient = -1.5e-7;
  out->has_drag_coefficient = 1;
  return 0;
}
int usrLongMessage(const quarry_drag_input* in, quarry_drag_output* out, void* user) {
  (void)in; (void)user;
  for (int i = 0; i < QUARRY_DRAG_UDF_MESSAGE_SIZE; ++i) out->message[i] = 'x';  /* no NUL */
  return -1;
}
)");
  const DragUdf nan_udf = load_drag_udf(library, "usrNaN");
  std::string text =
      physics_error_text([&] { nan_udf.evaluate(failing_input(), failing_context()); });
  EXPECT_NE(
      text.find("drag UDF \"usrNaN\" (" + library + ") gave a force that is not finite, (0, 0, "),
      std::string::npos)
      << text;
  EXPECT_NE(text.find("nan) N for particle id 42 (type 3)"), std::string::npos) << text;
  expect_every_input(text);
  const DragUdf negative = load_drag_udf(library, "usrNegative");
  text = physics_error_text([&] { negative.evaluate(failing_input(), failing_context()); });
  EXPECT_NE(text.find("gave a drag coefficient that is not finite and ≥ 0, -1.5e-07 kg/s"),
            std::string::npos)
      << text;
  // A message without its NUL is cut at the buffer's end.
  const DragUdf long_message = load_drag_udf(library, "usrLongMessage");
  text = physics_error_text([&] { long_message.evaluate(failing_input(), failing_context()); });
  EXPECT_NE(text.find("returned -1 for particle id 42 (type 3)\n  its message: " +
                      std::string(QUARRY_DRAG_UDF_MESSAGE_SIZE - 1, 'x') + "\n"),
            std::string::npos)
      << text;
}

// Bad input from the solver is refused before the UDF is called, as for the built-in laws.
TEST(DragUdfErrors, BadInputIsRefusedLikeTheBuiltInLaws) {
  TemporaryFolder folder;
  const DragUdf udf = load_drag_udf(build_stokes_example(folder.path()), "usrStokesDrag");
  DragInput input = failing_input();
  input.porosity = 0.0;
  EXPECT_THROW(udf.evaluate(input), std::invalid_argument);
}

}  // namespace
}  // namespace quarry::cfd
