// User-defined drag (include/quarry/drag_udf.h, issue #18 §4): a drag function in a shared
// library, loaded with dlopen and checked (file, ABI version, symbol) when the run is built, then
// evaluated per particle wherever a built-in law would be (drag_laws.h).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <utility>

#include "cfd/drag_laws.h"
#include "core/diagnostics.h"
#include "core/vec3.h"
#include "quarry/drag_udf.h"

namespace quarry::cfd {

// What a UDF reads beyond DragInput (quarry_drag_input's other fields).
struct DragUdfContext {
  Vec3 pressure_gradient;           // ∇p of the fluid (Pa/m)
  std::uint64_t particle_id = 0;    // persistent id, for the UDF's and our messages
  std::uint32_t particle_type = 0;  // type index
  double time = 0.0;                // s
  double particle_volume = 0.0;     // V_p (m³); 0: a sphere's, π d³/6 of the input's diameter
};

// A UDF call that failed: it returned non-zero, or its force or coefficient is not finite (or
// the coefficient is negative). what() names the function and library, the particle, the time,
// every input value and the UDF's message; the run loop stops with exit code 3 (a PhysicsError).
class DragUdfError : public PhysicsError {
 public:
  DragUdfError(std::string what, quarry_drag_input input, std::string udf_message)
      : PhysicsError(std::move(what)), input_(input), udf_message_(std::move(udf_message)) {}
  // The input the UDF was given.
  const quarry_drag_input& input() const { return input_; }
  // Its out->message, "" if it wrote none.
  const std::string& udf_message() const { return udf_message_; }

 private:
  quarry_drag_input input_;
  std::string udf_message_;
};

// An open drag UDF library. Closes it (dlclose) when the last owner goes; a DragUdf shares it,
// so its function pointer stays valid as long as the DragUdf lives.
using DragUdfLibrary = std::shared_ptr<void>;

// A loaded drag function. Copies share the library. evaluate is const and keeps no state, so
// several threads may call it at once for different particles, as the ABI promises the UDF.
class DragUdf {
 public:
  // Calls the function for one particle and returns its force, and as coefficient the UDF's
  // drag_coefficient if it set one, else force·(u − v)/|u − v|² (0 at zero slip).
  // Pre: check_drag_input holds (std::invalid_argument otherwise, as for the built-in laws).
  // Throws DragUdfError if the function returns non-zero, gives a force that is not finite, or
  // a drag coefficient that is not finite or is negative.
  // Cost: one call of the UDF plus filling two small structs.
  DragResult evaluate(const DragInput& input, const DragUdfContext& context = {}) const;

  const std::string& library_path() const { return library_path_; }
  const std::string& function_name() const { return function_name_; }
  // The library's quarry_drag_udf_abi(), (major << 16) | minor.
  std::uint32_t abi_version() const { return abi_version_; }

 private:
  friend DragUdf load_drag_udf(const std::string&, const std::string&, const SourceLocation&,
                               const SourceLocation&);
  DragUdf() = default;

  DragUdfLibrary library_;
  quarry_drag_fn function_ = nullptr;
  std::string library_path_;
  std::string function_name_;
  std::uint32_t abi_version_ = 0;
};

// Opens the shared library at `library_path` (dlopen with RTLD_NOW | RTLD_LOCAL: every symbol
// it needs resolved now, none of its own visible to anything else) and checks its ABI version.
// Throws UserError placed at `where` (`file:line:col: error:` when the deck gave it, `quarry:
// error:` otherwise), with a hint, when:
//   the file does not exist or is a folder;
//   dlopen refuses it (not a shared library, another architecture, a symbol it needs is missing:
//     dlerror's text);
//   it has no quarry_drag_udf_abi of its own (not built against drag_udf.h);
//   its ABI major is not QUARRY_DRAG_UDF_ABI_MAJOR (both versions named).
// Any minor is accepted: the structs' struct_size tells the library what Quarry gives.
// `abi_version` receives the library's version. Runs the library's constructors, if it has any.
// Cost: one dlopen.
DragUdfLibrary open_drag_udf_library(const std::string& library_path, std::uint32_t& abi_version,
                                     const SourceLocation& where = {});

// open_drag_udf_library, then the function `function_name` of that library. Errors of the
// library are placed at library_where, a function the library does not define (or a name that
// is the ABI function) at function_where (library_where if that has no file).
DragUdf load_drag_udf(const std::string& library_path, const std::string& function_name,
                      const SourceLocation& library_where = {},
                      const SourceLocation& function_where = {});

}  // namespace quarry::cfd
