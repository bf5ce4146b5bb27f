// Loading a drag UDF: dlopen, the ABI version, the function, each failure a user error with a
// hint; evaluating it: DragInput into quarry_drag_input, the output checked before the solver
// sees it.
#include "cfd/drag_udf.h"

#include <dlfcn.h>
#include <fmt/format.h>
#include <link.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <system_error>

namespace quarry::cfd {
namespace {

constexpr const char* kAbiSymbol = "quarry_drag_udf_abi";

constexpr const char* kBuildHint =
    "build the library from its C source with \"quarry udf build SOURCE.c\" (it writes SOURCE.so "
    "beside the source)";

std::string abi_text(std::uint32_t version) {
  return fmt::format("{}.{}", version >> 16, version & 0xffffu);
}

std::string show(const double (&v)[3]) {
  return fmt::format("({}, {}, {})", v[0], v[1], v[2]);
}

bool finite(const Vec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

// dlerror's text, or a stand-in if it has none.
std::string last_dl_error() {
  const char* text = ::dlerror();
  return text ? text : "no reason given";
}

// The address of `name` if the library of `handle` defines it itself. dlsym on a handle also
// searches the libraries it depends on: without this check a function named "exp" would be
// libm's, and an ABI function could come from another UDF library it links.
void* own_symbol(void* handle, const std::string& name) {
  void* address = ::dlsym(handle, name.c_str());
  if (address == nullptr) return nullptr;
  link_map* map = nullptr;
  Dl_info info{};
  if (::dlinfo(handle, RTLD_DI_LINKMAP, &map) != 0 || map == nullptr) return nullptr;
  if (::dladdr(address, &info) == 0 || info.dli_fname == nullptr) return nullptr;
  return std::strcmp(info.dli_fname, map->l_name) == 0 ? address : nullptr;
}

}  // namespace

DragUdfLibrary open_drag_udf_library(const std::string& library_path, std::uint32_t& abi_version,
                                     const SourceLocation& where) {
  namespace fs = std::filesystem;
  std::error_code error;
  const fs::file_status status = fs::status(library_path, error);
  if (!fs::exists(status))
    throw UserError(where, fmt::format("drag UDF library \"{}\" does not exist", library_path),
                    std::string(kBuildHint) + ", and check the path");
  if (fs::is_directory(status))
    throw UserError(
        where,
        fmt::format("drag UDF library \"{}\" is a folder, not a shared library", library_path),
        kBuildHint);

  // A name without a slash would be searched for in the system's library folders.
  const std::string open_path =
      library_path.find('/') == std::string::npos ? "./" + library_path : library_path;
  ::dlerror();
  // The library is closed when its last user goes: a DragUdf holds it while its function
  // pointer may be called.
  DragUdfLibrary library(::dlopen(open_path.c_str(), RTLD_NOW | RTLD_LOCAL), [](void* handle) {
    if (handle != nullptr) ::dlclose(handle);
  });
  if (!library)
    throw UserError(
        where,
        fmt::format("cannot load drag UDF library \"{}\": {}", library_path, last_dl_error()),
        "it must be a shared library for this machine whose every symbol resolves; " +
            std::string(kBuildHint) + " (--cflags \"-lNAME\" links a library it needs)");

  void* abi_symbol = own_symbol(library.get(), kAbiSymbol);
  if (abi_symbol == nullptr)
    throw UserError(where,
                    fmt::format("drag UDF library \"{}\" has no function {}: it was not built "
                                "against quarry/drag_udf.h",
                                library_path, kAbiSymbol),
                    "its source must include <quarry/drag_udf.h> and contain "
                    "QUARRY_DRAG_UDF_EXPORT_ABI() once; then build it with \"quarry udf build\"");
  abi_version = reinterpret_cast<std::uint32_t (*)()>(abi_symbol)();
  if ((abi_version >> 16) != QUARRY_DRAG_UDF_ABI_MAJOR)
    throw UserError(
        where,
        fmt::format("drag UDF library \"{}\" was built for drag UDF ABI {}, this Quarry "
                    "loads ABI {}.x (its drag_udf.h is {})",
                    library_path, abi_text(abi_version), QUARRY_DRAG_UDF_ABI_MAJOR,
                    abi_text(QUARRY_DRAG_UDF_ABI_VERSION)),
        "rebuild it from its source with this Quarry's \"quarry udf build SOURCE.c\", "
        "which compiles it against this version's drag_udf.h");
  return library;
}

DragUdf load_drag_udf(const std::string& library_path, const std::string& function_name,
                      const SourceLocation& library_where, const SourceLocation& function_where) {
  const SourceLocation& function_place =
      function_where.file.empty() ? library_where : function_where;
  if (function_name.empty())
    throw UserError(function_place, "the drag UDF's function name is empty",
                    "give the name of the C function in the library, e.g. usrStokesDrag");
  if (function_name == kAbiSymbol)
    throw UserError(function_place,
                    fmt::format("{} is the library's ABI version, not a drag function", kAbiSymbol),
                    "give the name of the drag function, the one declared with "
                    "QUARRY_DRAG_UDF_PROTOTYPE");

  DragUdf udf;
  udf.library_ = open_drag_udf_library(library_path, udf.abi_version_, library_where);
  udf.library_path_ = library_path;
  udf.function_name_ = function_name;
  void* function_symbol = own_symbol(udf.library_.get(), function_name);
  if (function_symbol == nullptr)
    throw UserError(
        function_place,
        fmt::format("drag UDF library \"{}\" has no function \"{}\"", library_path, function_name),
        fmt::format("check the name's spelling and case; a drag function must be exported "
                    "with C linkage and not be static: declare it with "
                    "QUARRY_DRAG_UDF_PROTOTYPE({}) (which also makes it extern \"C\" in "
                    "C++); \"nm -D --defined-only {}\" lists what the library exports",
                    function_name, library_path));
  udf.function_ = reinterpret_cast<quarry_drag_fn>(function_symbol);
  return udf;
}

DragResult DragUdf::evaluate(const DragInput& input, const DragUdfContext& context) const {
  check_drag_input(input);
  quarry_drag_input in{};
  in.struct_size = sizeof in;
  in.particle_type = context.particle_type;
  in.particle_id = context.particle_id;
  in.time = context.time;
  in.particle_volume =
      context.particle_volume > 0.0 ? context.particle_volume : particle_volume(input);
  in.particle_diameter = input.diameter;
  for (int i = 0; i < 3; ++i) {
    in.particle_velocity[i] = input.particle_velocity[i];
    in.fluid_velocity[i] = input.fluid_velocity[i];
    in.pressure_gradient[i] = context.pressure_gradient[i];
  }
  in.porosity = input.porosity;
  in.fluid_viscosity = input.fluid_viscosity;
  in.fluid_density = input.fluid_density;
  in.reynolds_number = superficial_reynolds_number(input);

  quarry_drag_output out{};  // zeroed, as AcuSolve's outVec arrives
  out.struct_size = sizeof out;
  const int returned = function_(&in, &out, nullptr);
  out.message[sizeof out.message - 1] = '\0';  // a UDF that filled the buffer to the end
  const Vec3 force{out.force[0], out.force[1], out.force[2]};

  std::string failure;
  if (returned != 0)
    failure = fmt::format("returned {}", returned);
  else if (!finite(force))
    failure = fmt::format("gave a force that is not finite, {} N", show(out.force));
  else if (out.has_drag_coefficient != 0 &&
           !(std::isfinite(out.drag_coefficient) && out.drag_coefficient >= 0.0))
    failure = fmt::format("gave a drag coefficient that is not finite and ≥ 0, {} kg/s",
                          out.drag_coefficient);
  if (!failure.empty()) {
    const std::string message =
        out.message[0] != '\0' ? fmt::format("\n  its message: {}", out.message) : std::string();
    throw DragUdfError(
        fmt::format(
            "t = {} s: drag UDF \"{}\" ({}) {} for particle id {} (type {}){}\n"
            "  its input: particle_volume {} m³, particle_diameter {} m, particle_velocity {} m/s, "
            "fluid_velocity {} m/s, porosity {}, fluid_viscosity {} Pa·s, fluid_density {} kg/m³, "
            "pressure_gradient {} Pa/m, reynolds_number {}\n"
            "  hint: the function refused this input or its formula breaks down for it (a division "
            "by zero, a root or power of a negative number); call it on these values alone to see "
            "which",
            in.time, function_name_, library_path_, failure, in.particle_id, in.particle_type,
            message, in.particle_volume, in.particle_diameter, show(in.particle_velocity),
            show(in.fluid_velocity), in.porosity, in.fluid_viscosity, in.fluid_density,
            show(in.pressure_gradient), in.reynolds_number),
        in, out.message);
  }

  double coefficient = 0.0;
  if (out.has_drag_coefficient != 0) {
    coefficient = out.drag_coefficient;
  } else {
    const Vec3 slip = slip_velocity(input);
    const double slip2 = norm2(slip);
    if (slip2 > 0.0) coefficient = dot(force, slip) / slip2;
  }
  return DragResult{force, coefficient};
}

}  // namespace quarry::cfd
