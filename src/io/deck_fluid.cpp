// The deck's `fluid:` section (CFD-DEM, issue #18 §5): grid, fluid properties, the boundary of
// each box face, formulation, drag law or user-defined drag, fluid time step, blocked regions.
// Reads into FluidSpec; the UDF library is loaded and the blocked cells are found (their errors
// placed here) when the run is built.
#include <fmt/format.h>

#include <cmath>
#include <stdexcept>
#include <filesystem>
#include <vector>

#include "cfd/drag_laws.h"  // kDragLawNames only (header data: no link dependency on cfd)
#include "io/deck_sections.h"

namespace quarry::deck_detail {

namespace {

const EnumChoices<FluidBoundaryType> kFluidBoundaryTypes{
    "fluid boundary type",
    {{"wall", FluidBoundaryType::wall},
     {"velocity_inlet", FluidBoundaryType::velocity_inlet},
     {"pressure_outlet", FluidBoundaryType::pressure_outlet},
     {"periodic", FluidBoundaryType::periodic}}};

const EnumChoices<FluidModel> kFluidModels{"fluid model", {{"A", FluidModel::a}, {"B", FluidModel::b}}};

const EnumChoices<FluidAdvection> kFluidAdvections{
    "fluid advection scheme", {{"central", FluidAdvection::central}, {"hybrid", FluidAdvection::hybrid}}};

const EnumChoices<FluidMonitorType> kFluidMonitorTypes{
    "fluid monitor type",
    {{"pressure_drop", FluidMonitorType::pressure_drop},
     {"flow_rate", FluidMonitorType::flow_rate},
     {"slip_velocity", FluidMonitorType::slip_velocity}}};

const EnumChoices<int> kAxes{"axis", {{"x", 0}, {"y", 1}, {"z", 2}}};

const EnumChoices<FluidBlockedKind> kFluidBlockedKinds{
    "blocked region type",
    {{"box", FluidBlockedKind::box},
     {"half_space", FluidBlockedKind::half_space},
     {"surface", FluidBlockedKind::surface}}};

const std::array<const char*, 6> kFaceKeys{"x_min", "x_max", "y_min", "y_max", "z_min", "z_max"};

// An incompressible fluid that flows in must leave somewhere: with no pressure_outlet the
// pressure equation ∇·(εa∇φ) = ∇·(εu*) has no solution unless the inlets' volume flows sum to
// zero (a deck fuzzer's packed bed without its outlet stopped a few steps into the run, its
// pressure solve at the iteration limit). Flows in m³/s over whole faces of the grid.
void check_inflow_has_an_outlet(DeckContext& context, const FluidSpec& spec) {
  double net = 0.0, gross = 0.0;  // m³/s into the domain
  const Located<Vec3>* first_inlet = nullptr;
  for (int face = 0; face < 6; ++face) {
    const FluidFaceSpec& f = spec.faces[static_cast<std::size_t>(face)];
    if (f.type.value == FluidBoundaryType::pressure_outlet) return;
    if (f.type.value != FluidBoundaryType::velocity_inlet) continue;
    const int axis = face / 2;
    const double area = spec.cells.value[(axis + 1) % 3] * spec.cells.value[(axis + 2) % 3] *
                        spec.cell_size.value * spec.cell_size.value;  // m²
    const double inward = (face % 2 == 0 ? 1.0 : -1.0) * f.velocity.value[axis];  // m/s
    net += area * inward;
    gross += area * std::abs(inward);
    if (!first_inlet && inward != 0.0) first_inlet = &f.velocity;
  }
  if (!first_inlet || !(std::abs(net) > 1e-9 * gross)) return;
  context.error(first_inlet->where,
                fmt::format("fluid flows {} through the velocity inlets ({:.4g} m³/s net) but no "
                            "face is a pressure_outlet: an incompressible fluid cannot {} a closed "
                            "domain",
                            net > 0.0 ? "in" : "out", std::abs(net), net > 0.0 ? "enter" : "leave"),
                "make a face a pressure_outlet (usually the one opposite the inlet), or give the "
                "inlets velocities whose flows sum to zero");
}

// A boundary velocity the fluid step cannot carry: the explicit advection needs the Courant
// number c = dt Σ_a |u_a| / Δx ≤ 1 (FluidSolver::stable_time_step), and the fluid next to an
// inlet or a moving wall moves at least as fast as the face (an inlet's interstitial speed U/ε
// exceeds its superficial U). Above it the first steps blow up (a fuzzed inlet of 1e308 m/s
// stopped in the momentum solve); refused here with the step and speed that would do.
void check_boundary_courant(DeckContext& context, const FluidSpec& spec) {
  const double dt = spec.time_step.value, h = spec.cell_size.value;  // s, m
  if (!(dt > 0.0) || !(h > 0.0)) return;  // reported where they are read
  for (int face = 0; face < 6; ++face) {
    const FluidFaceSpec& f = spec.faces[static_cast<std::size_t>(face)];
    const FluidBoundaryType type = f.type.value;
    if (type != FluidBoundaryType::velocity_inlet && type != FluidBoundaryType::wall) continue;
    const Vec3& u = f.velocity.value;  // m/s
    const double speed_sum = std::abs(u.x) + std::abs(u.y) + std::abs(u.z);  // m/s
    const double courant = dt * speed_sum / h;
    if (!(courant > 1.0)) continue;
    context.error(f.velocity.where,
                  fmt::format("the fluid at {} moves {:.4g} cells per fluid step (|u_x| + |u_y| "
                              "+ |u_z| = {:.4g} m/s, time_step {:.4g} s, cells of {:.4g} m): the "
                              "explicit advection needs at most 1 (CFL)",
                              kFaceKeys[static_cast<std::size_t>(face)], courant, speed_sum, dt, h),
                  fmt::format("a fluid time_step of at most {:.3g} s (half of it is safer), or a "
                              "boundary speed of at most {:.3g} m/s",
                              h / speed_sum, h / dt));
  }
}

void read_face(MapReader& boundaries, int face, FluidFaceSpec& spec) {
  const std::string key = kFaceKeys[static_cast<std::size_t>(face)];
  MapReader map(boundaries.context(), *boundaries.find(key), *boundaries.find_key(key), key);
  map.reject_unknown_keys({"type", "velocity", "reference_pressure", "reference_point"});
  map.read("type", spec.type, kFluidBoundaryTypes, Presence::required);
  map.read("velocity", spec.velocity);
  map.read("reference_pressure", spec.reference_pressure, any_number(), "Pa");
  map.read("reference_point", spec.reference_point);
  const FluidBoundaryType type = spec.type.value;
  if (map.has("velocity") && type != FluidBoundaryType::wall && type != FluidBoundaryType::velocity_inlet)
    map.context().error(map.where_value("velocity"),
                        fmt::format("\"velocity\" applies to a wall or a velocity_inlet, not to {}", key),
                        "leave it out");
  if ((map.has("reference_pressure") || map.has("reference_point")) &&
      type != FluidBoundaryType::pressure_outlet)
    map.context().error(map.location(),
                        fmt::format("{}: \"reference_pressure\" and \"reference_point\" apply to a "
                                    "pressure_outlet only",
                                    key),
                        "leave them out, or make the face type: pressure_outlet");
}

void read_drag_udf(MapReader& fluid, const DeckParseOptions& options, FluidSpec& spec) {
  MapReader map(fluid.context(), *fluid.find("drag_udf"), *fluid.find_key("drag_udf"), "drag_udf");
  if (!map.is_map()) return;
  map.reject_unknown_keys({"library", "function"});
  FluidDragUdfSpec udf;
  if (map.read("library", udf.library, Presence::required)) {
    std::filesystem::path path(udf.library.value);
    if (path.is_relative() && !options.base_directory.empty())
      udf.library.value = (std::filesystem::path(options.base_directory) / path).string();
  }
  map.read("function", udf.function, Presence::required);
  spec.drag_udf = udf;
}

// One entry of fluid.monitors; the planes must cross the grid (checked here when the grid is
// known, as the run could only report an empty plane).
void read_fluid_monitor(MapReader& map, const FluidSpec& fluid, FluidMonitorSpec& monitor) {
  monitor.where = map.location();
  map.reject_unknown_keys({"name", "type", "axis", "from", "to", "at"});
  map.read("name", monitor.name, Presence::required);
  if (!map.read("type", monitor.type, kFluidMonitorTypes, Presence::required)) return;
  const FluidMonitorType type = monitor.type.value;
  const auto only_for = [&](const char* key, bool applies, const char* types) {
    if (map.has(key) && !applies)
      map.context().error(map.where_value(key),
                          fmt::format("\"{}\" applies to a {} monitor only", key, types), "leave it out");
  };
  only_for("axis", type != FluidMonitorType::slip_velocity, "pressure_drop or flow_rate");
  only_for("from", type == FluidMonitorType::pressure_drop, "pressure_drop");
  only_for("to", type == FluidMonitorType::pressure_drop, "pressure_drop");
  only_for("at", type == FluidMonitorType::flow_rate, "flow_rate");
  if (type == FluidMonitorType::slip_velocity) return;
  map.read("axis", monitor.axis, kAxes, Presence::required);
  std::vector<Located<double>*> planes;
  if (type == FluidMonitorType::pressure_drop) {
    if (map.read("from", monitor.from, any_number(), "m", Presence::required)) planes.push_back(&monitor.from);
    if (map.read("to", monitor.to, any_number(), "m", Presence::required)) planes.push_back(&monitor.to);
  } else if (map.read("at", monitor.at, any_number(), "m", Presence::required)) {
    planes.push_back(&monitor.at);
  }
  const int axis = monitor.axis.value;
  const double low = fluid.origin.value[axis];
  const double high = low + fluid.cells.value[axis] * fluid.cell_size.value;
  for (const Located<double>* plane : planes)
    if (fluid.cell_size.value > 0.0 && !(plane->value >= low && plane->value <= high))
      map.context().error(plane->where,
                          fmt::format("the plane {} = {:.6g} m lies outside the fluid grid ({:.6g} to {:.6g} m)",
                                      "xyz"[axis], plane->value, low, high),
                          "put it between the grid's faces along that axis");
}

// One entry of fluid.blocked: {type: box, min, max}, {type: half_space, point, normal} or
// {type: surface, surface: NAME}. The surface's name, and that it is fixed, are checked with the
// other cross-section names (deck.cpp); that it is closed, when the run is built (its mesh).
void read_blocked_entry(MapReader& map, FluidBlockedSpec& entry) {
  entry.where = map.location();
  const std::vector<std::string> box_keys = {"type", "min", "max"};
  const std::vector<std::string> half_space_keys = {"type", "point", "normal"};
  const std::vector<std::string> surface_keys = {"type", "surface"};
  const std::vector<std::string> all_keys = {"type", "min", "max", "point", "normal", "surface"};
  if (!map.has("type") || !map.read("type", entry.kind, kFluidBlockedKinds)) {
    map.reject_unknown_keys(all_keys);
    map.require("type", "type: is one of " + join_choices(kFluidBlockedKinds));
    return;
  }
  const std::string variant = fmt::format("blocked region type \"{}\"", map.find("type")->Scalar());
  switch (entry.kind.value) {
    case FluidBlockedKind::box: {
      map.reject_unknown_keys(box_keys, all_keys, variant);
      const bool has_min = map.read("min", entry.min, Presence::required);
      const bool has_max = map.read("max", entry.max, Presence::required);
      if (has_min && has_max) check_box_corners(map.context(), "blocked box", entry.min, entry.max);
      break;
    }
    case FluidBlockedKind::half_space:
      map.reject_unknown_keys(half_space_keys, all_keys, variant);
      map.read("point", entry.point, Presence::required);
      if (map.read("normal", entry.normal, Presence::required))
        check_nonzero_direction(map.context(), "normal", entry.normal);
      break;
    case FluidBlockedKind::surface:
      map.reject_unknown_keys(surface_keys, all_keys, variant);
      map.read("surface", entry.surface, Presence::required);
      break;
  }
}

}  // namespace

// Pa·s: below every real fluid (hydrogen gas 8.8e-6 Pa·s at 20 °C, CRC Handbook, "Viscosity of
// gases"); far smaller values make the Reynolds numbers of the drag laws and the advection's
// cell Péclet numbers overflow to infinity, and the fluid step to NaN.
constexpr double kLeastViscosity = 1e-7;

void read_fluid_section(MapReader& root, const DeckParseOptions& options,
                        std::optional<FluidSpec>& fluid) {
  const YAML::Node* value = root.find("fluid");
  if (!value) return;
  MapReader map(root.context(), *value, *root.find_key("fluid"), "fluid");
  if (!map.is_map()) return;
  DeckContext& context = map.context();
  FluidSpec spec;
  spec.where = map.location();
  map.reject_unknown_keys({"density", "viscosity", "time_step", "grid", "boundaries", "model", "advection",
                           "drag_law", "drag_udf", "monitors", "blocked"});
  map.read("density", spec.density, positive(), "kg/m³");
  if (map.read("viscosity", spec.viscosity, positive(), "Pa·s") &&
      spec.viscosity.value < kLeastViscosity)
    context.error(spec.viscosity.where,
                  fmt::format("\"viscosity\" must be at least {}, got {}",
                              with_unit(kLeastViscosity, "Pa·s"),
                              with_unit(spec.viscosity.value, "Pa·s")),
                  "the viscosity is dynamic, in Pa·s: the least viscous gas, hydrogen, has "
                  "8.8e-6 Pa·s at 20 °C (air 1.8e-5, water 0.001)");
  map.read("time_step", spec.time_step, positive(), "s", Presence::required);
  map.read("model", spec.model, kFluidModels);
  map.read("advection", spec.advection, kFluidAdvections);

  if (map.require("grid")) {
    MapReader grid(context, *map.find("grid"), *map.find_key("grid"), "grid");
    grid.reject_unknown_keys({"origin", "cell_size", "cells"});
    grid.read("origin", spec.origin, Presence::required);
    grid.read("cell_size", spec.cell_size, positive(), "m", Presence::required);
    if (grid.read("cells", spec.cells, Presence::required)) {
      for (int axis = 0; axis < 3; ++axis) {
        const double n = spec.cells.value[axis];
        if (!(n >= 1.0 && n == std::floor(n) && n <= 1e6)) {
          context.error(spec.cells.where,
                        fmt::format("\"cells\" must be whole numbers ≥ 1 per axis, got {} along {}", n,
                                    "xyz"[axis]),
                        "write the cell count along x, y and z, e.g. cells: [4, 4, 12]");
          break;
        }
      }
    }
  }

  if (const YAML::Node* boundaries_node = map.find("boundaries")) {
    MapReader boundaries(context, *boundaries_node, *map.find_key("boundaries"), "boundaries");
    boundaries.reject_unknown_keys({kFaceKeys.begin(), kFaceKeys.end()});
    for (int face = 0; face < 6; ++face)
      if (boundaries.has(kFaceKeys[static_cast<std::size_t>(face)]))
        read_face(boundaries, face, spec.faces[static_cast<std::size_t>(face)]);
    for (int axis = 0; axis < 3; ++axis) {
      const bool low = spec.faces[static_cast<std::size_t>(2 * axis)].type.value == FluidBoundaryType::periodic;
      const bool high = spec.faces[static_cast<std::size_t>(2 * axis + 1)].type.value == FluidBoundaryType::periodic;
      if (low != high)
        context.error(boundaries.location(),
                      fmt::format("{} and {} must both be periodic or neither",
                                  kFaceKeys[static_cast<std::size_t>(2 * axis)],
                                  kFaceKeys[static_cast<std::size_t>(2 * axis + 1)]),
                      "a periodic face is paired with the opposite one");
    }
    check_inflow_has_an_outlet(context, spec);
    check_boundary_courant(context, spec);
  }

  std::vector<std::string> law_names;
  for (const cfd::DragLawName& law : cfd::kDragLawNames) law_names.emplace_back(law.name);
  if (map.read("drag_law", spec.drag_law)) {
    if (std::find(law_names.begin(), law_names.end(), spec.drag_law.value) == law_names.end())
      context.error(spec.drag_law.where, fmt::format("unknown drag law \"{}\"", spec.drag_law.value),
                    suggestion_hint(spec.drag_law.value, law_names));
  }
  if (map.has("drag_udf")) {
    if (map.has("drag_law"))
      context.error(map.where_value("drag_udf"), "give either drag_law or drag_udf, not both",
                    "drag_udf replaces the built-in law");
    read_drag_udf(map, options, spec);
  }
  for (MapReader& monitor_map : list_of_maps(map, "monitors", "fluid monitor")) {
    FluidMonitorSpec monitor;
    read_fluid_monitor(monitor_map, spec, monitor);
    spec.monitors.push_back(std::move(monitor));
  }
  if (map.has("blocked")) spec.blocked_where = map.where_value("blocked");
  for (MapReader& entry_map : list_of_maps(map, "blocked", "blocked region")) {
    FluidBlockedSpec entry;
    read_blocked_entry(entry_map, entry);
    spec.blocked.push_back(std::move(entry));
  }
  fluid = spec;
}

namespace {

std::string vector_yaml(const Vec3& v) { return fmt::format("[{}, {}, {}]", v.x, v.y, v.z); }

// A YAML double-quoted string (paths may hold any character).
std::string quoted(const std::string& text) {
  std::string out = "\"";
  for (const char c : text) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

template <class Enum>
const std::string& spelling_of(const EnumChoices<Enum>& choices, Enum value) {
  for (const auto& [spelling, enum_value] : choices.names)
    if (enum_value == value) return spelling;
  throw std::logic_error("a fluid enum value without a spelling");
}

}  // namespace

std::string fluid_section_text(const FluidSpec& spec) {
  std::string out = "fluid:\n";
  out += fmt::format("  density: {}\n  viscosity: {}\n  time_step: {}\n", spec.density.value,
                     spec.viscosity.value, spec.time_step.value);
  out += fmt::format("  grid: {{origin: {}, cell_size: {}, cells: {}}}\n", vector_yaml(spec.origin.value),
                     spec.cell_size.value, vector_yaml(spec.cells.value));
  out += "  boundaries:\n";
  for (std::size_t face = 0; face < 6; ++face) {
    const FluidFaceSpec& f = spec.faces[face];
    out += fmt::format("    {}: {{type: {}", kFaceKeys[face], spelling_of(kFluidBoundaryTypes, f.type.value));
    if (f.type.value == FluidBoundaryType::wall || f.type.value == FluidBoundaryType::velocity_inlet)
      out += ", velocity: " + vector_yaml(f.velocity.value);
    if (f.type.value == FluidBoundaryType::pressure_outlet)
      out += fmt::format(", reference_pressure: {}, reference_point: {}", f.reference_pressure.value,
                         vector_yaml(f.reference_point.value));
    out += "}\n";
  }
  out += "  model: " + spelling_of(kFluidModels, spec.model.value) + "\n";
  out += "  advection: " + spelling_of(kFluidAdvections, spec.advection.value) + "\n";
  if (spec.drag_udf)
    out += fmt::format("  drag_udf: {{library: {}, function: {}}}\n", quoted(spec.drag_udf->library.value),
                       quoted(spec.drag_udf->function.value));
  else
    out += "  drag_law: " + spec.drag_law.value + "\n";
  if (!spec.monitors.empty()) out += "  monitors:\n";
  for (const FluidMonitorSpec& m : spec.monitors) {
    out += fmt::format("    - {{name: {}, type: {}", quoted(m.name.value), spelling_of(kFluidMonitorTypes, m.type.value));
    if (m.type.value != FluidMonitorType::slip_velocity) out += fmt::format(", axis: {}", "xyz"[m.axis.value]);
    if (m.type.value == FluidMonitorType::pressure_drop) out += fmt::format(", from: {}, to: {}", m.from.value, m.to.value);
    if (m.type.value == FluidMonitorType::flow_rate) out += fmt::format(", at: {}", m.at.value);
    out += "}\n";
  }
  if (!spec.blocked.empty()) out += "  blocked:\n";
  for (const FluidBlockedSpec& b : spec.blocked) {
    out += "    - {type: " + spelling_of(kFluidBlockedKinds, b.kind.value);
    switch (b.kind.value) {
      case FluidBlockedKind::box:
        out += fmt::format(", min: {}, max: {}", vector_yaml(b.min.value), vector_yaml(b.max.value));
        break;
      case FluidBlockedKind::half_space:
        out += fmt::format(", point: {}, normal: {}", vector_yaml(b.point.value), vector_yaml(b.normal.value));
        break;
      case FluidBlockedKind::surface:
        out += ", surface: " + quoted(b.surface.value);
        break;
    }
    out += "}\n";
  }
  return out;
}

}  // namespace quarry::deck_detail
