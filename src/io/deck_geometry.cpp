// Deck sections with geometry: surfaces (STL, primitives or inline meshes, prescribed motion),
// factories with their insertion regions, and monitors. STL paths are resolved against the
// deck's folder here so that the world builder never depends on the current directory.
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <filesystem>

#include "io/deck_enums.h"
#include "io/deck_sections.h"

namespace quarry::deck_detail {

namespace {

// A cylinder wall of fewer segments than this is not a cylinder (a triangle prism at best).
constexpr int kMinimumCylinderResolution = 3;

std::vector<std::string> joined(std::vector<std::string> first,
                                const std::vector<std::string>& second) {
  first.insert(first.end(), second.begin(), second.end());
  return first;
}

// The keys of every variant, for "does not apply to" messages.
std::vector<std::string> union_of(const std::vector<std::vector<std::string>>& variants) {
  std::vector<std::string> all;
  for (const auto& keys : variants) all = joined(std::move(all), keys);
  return all;
}

// start_time ≥ 0 and stop_time > start_time (s).
void read_time_window(MapReader& map, Located<double>& start_time, Located<double>& stop_time) {
  map.read("start_time", start_time, non_negative(), "s");
  if (!map.read("stop_time", stop_time, non_negative(), "s")) return;
  if (stop_time.value <= start_time.value)
    map.context().error(stop_time.where,
                        fmt::format("stop_time must be > start_time = {} s, got {} s",
                                    start_time.value, stop_time.value));
}

void read_box_corners(MapReader& map, const std::string& what, Located<Vec3>& lower,
                      Located<Vec3>& upper) {
  const bool has_lower = map.read("min", lower, Presence::required);
  const bool has_upper = map.read("max", upper, Presence::required);
  if (has_lower && has_upper) check_box_corners(map.context(), what, lower, upper);
}

// Region of space for factories and monitors: {type: box, min, max} or
// {type: cylinder, base, axis, radius, length}.
RegionSpec read_region(MapReader& parent, const std::string& key) {
  RegionSpec region;
  MapReader map(parent.context(), *parent.find(key), *parent.find_key(key), "region");
  if (!map.is_map()) return region;
  const std::vector<std::string> box_keys = {"type", "min", "max"};
  const std::vector<std::string> cylinder_keys = {"type", "base", "axis", "radius", "length"};
  const std::vector<std::string> point_keys = {"type", "position"};
  const std::vector<std::string> all_keys = union_of({box_keys, cylinder_keys, point_keys});
  if (!map.has("type") || !map.read("type", region.kind, kRegionKinds)) {
    map.reject_unknown_keys(all_keys);
    map.require("type", "type: is one of " + join_choices(kRegionKinds));
    return region;
  }
  const std::string variant = fmt::format("region type \"{}\"", map.find("type")->Scalar());
  if (region.kind.value == RegionKind::box) {
    map.reject_unknown_keys(box_keys, all_keys, variant);
    read_box_corners(map, "region", region.min, region.max);
  } else if (region.kind.value == RegionKind::point) {
    map.reject_unknown_keys(point_keys, all_keys, variant);
    map.read("position", region.position, Presence::required);
  } else {
    map.reject_unknown_keys(cylinder_keys, all_keys, variant);
    map.read("base", region.base, Presence::required);
    if (map.read("axis", region.axis, Presence::required))
      check_nonzero_direction(map.context(), "axis", region.axis);
    map.read("radius", region.radius, positive(), "m", Presence::required);
    map.read("length", region.length, positive(), "m", Presence::required);
  }
  return region;
}

void read_motion(MapReader& surface, MotionSpec& motion) {
  if (!surface.has("motion")) return;
  MapReader map(surface.context(), *surface.find("motion"), *surface.find_key("motion"), "motion");
  if (!map.is_map()) return;
  const std::vector<std::string> common_keys = {"type", "start_time", "stop_time"};
  const std::vector<std::string> rotation_keys = {"axis_point", "axis_direction",
                                                  "angular_velocity"};
  const std::vector<std::string> translation_keys = {"velocity"};
  const std::vector<std::string> vibration_keys = {"amplitude", "frequency"};
  const std::vector<std::string> all_keys =
      union_of({common_keys, rotation_keys, translation_keys, vibration_keys});
  if (!map.has("type") || !map.read("type", motion.kind, kMotionKinds)) {
    map.reject_unknown_keys(all_keys);
    map.require("type", "type: is one of " + join_choices(kMotionKinds));
    return;
  }
  const std::string variant = fmt::format("motion type \"{}\"", map.find("type")->Scalar());
  switch (motion.kind.value) {
    case MotionKind::rotation:
      map.reject_unknown_keys(joined(common_keys, rotation_keys), all_keys, variant);
      map.read("axis_point", motion.axis_point, Presence::required);
      if (map.read("axis_direction", motion.axis_direction, Presence::required))
        check_nonzero_direction(map.context(), "axis_direction", motion.axis_direction);
      map.read("angular_velocity", motion.angular_velocity, any_number(), "rad/s",
               Presence::required);
      break;
    case MotionKind::translation:
      map.reject_unknown_keys(joined(common_keys, translation_keys), all_keys, variant);
      map.read("velocity", motion.velocity, Presence::required);
      break;
    case MotionKind::vibration:
      map.reject_unknown_keys(joined(common_keys, vibration_keys), all_keys, variant);
      map.read("amplitude", motion.amplitude, Presence::required);
      map.read("frequency", motion.frequency, positive(), "Hz", Presence::required);
      break;
    case MotionKind::none:
      break;  // not spellable in a deck: no motion key means none
  }
  read_time_window(map, motion.start_time, motion.stop_time);
}

// Resolves an STL path against the deck's folder, stores it absolute, and checks it exists
// unless the caller supplies the meshes itself (options.require_files false).
void read_stl_file(MapReader& map, const DeckParseOptions& options, Located<std::string>& file) {
  if (!map.read("file", file, Presence::required)) return;
  namespace fs = std::filesystem;
  fs::path path(file.value);
  if (path.is_relative()) path = fs::path(options.base_directory) / path;
  std::error_code ignored;
  const fs::path resolved = fs::absolute(path, ignored).lexically_normal();
  if (options.require_files && !fs::is_regular_file(resolved, ignored)) {
    const bool folder = fs::is_directory(resolved, ignored);
    map.context().error(file.where,
                        folder ? fmt::format("STL file \"{}\" is a folder, not a file", file.value)
                               : fmt::format("STL file \"{}\" not found", file.value),
                        fmt::format("looked for \"{}\"; relative paths start at the deck's folder",
                                    resolved.string()));
    return;
  }
  file.value = resolved.string();
}

// The points of an inline mesh, `vertices: [[x, y, z], …]` (m), into surface.mesh_vertices.
// Returns how many the deck lists (bad entries included, so that indices are checked against
// what the user wrote); 0 when the list is absent or not a list.
std::size_t read_mesh_vertices(MapReader& map, SurfaceSpec& surface) {
  if (!map.require("vertices", "vertices: [[x, y, z], …] lists the mesh's points in m")) return 0;
  DeckContext& context = map.context();
  const YAML::Node& list = *map.find("vertices");
  surface.mesh_where = map.where_value("vertices");
  if (!list.IsSequence() || list.size() == 0) {
    context.error(surface.mesh_where,
                  fmt::format("expected a non-empty list of points for \"vertices\", got {}",
                              describe_node(list)),
                  "write it as vertices: [[x, y, z], …] in m");
    return 0;
  }
  std::size_t index = 0;
  for (const YAML::Node& element : list) {
    const std::string name = fmt::format("vertices[{}]", index++);
    if (!element.IsSequence() || element.size() != 3) {
      context.error(context.where(element, list),
                    fmt::format("expected a list of 3 numbers for \"{}\", got {}", name,
                                describe_node(element)),
                    "write each vertex as [x, y, z] in m");
      continue;
    }
    Vec3 point;
    bool valid = true;
    for (int component = 0; component < 3; ++component) {
      const std::optional<double> number =
          read_number(context, element[component], element, fmt::format("{}[{}]", name, component));
      if (number)
        point[component] = *number;
      else
        valid = false;
    }
    if (valid) surface.mesh_vertices.push_back(point);
  }
  return list.size();
}

// The elements of an inline mesh under `key` (triangles: [[a, b, c], …], quads:
// [[a, b, c, d], …]): 0-based indices below vertex_count, no vertex twice in one element.
// Returns how many elements the deck lists (0 when the key is absent or empty), or -1 when
// the value is not a list (reported).
template <std::size_t Corners>
long read_mesh_elements(MapReader& map, const std::string& key, const std::string& noun,
                        std::size_t vertex_count,
                        std::vector<std::array<std::uint32_t, Corners>>& elements) {
  const YAML::Node* list = map.find(key);
  if (!list || list->IsNull()) return 0;
  DeckContext& context = map.context();
  const std::string shape = Corners == 3 ? "[a, b, c]" : "[a, b, c, d]";
  if (!list->IsSequence()) {
    context.error(
        map.where_value(key),
        fmt::format("expected a list of {}s for \"{}\", got {}", noun, key, describe_node(*list)),
        fmt::format("write it as {}: [{}, …], 0-based indices into vertices", key, shape));
    return -1;
  }
  // Indices are stored as 32-bit; a deck cannot list more vertices than that in practice.
  const std::uint64_t addressable = std::min<std::uint64_t>(vertex_count, std::uint64_t{1} << 32);
  std::size_t index = 0;
  for (const YAML::Node& element : *list) {
    const std::string name = fmt::format("{}[{}]", key, index++);
    if (!element.IsSequence() || element.size() != Corners) {
      context.error(context.where(element, *list),
                    fmt::format("expected a list of {} vertex indices for \"{}\", got {}", Corners,
                                name, describe_node(element)),
                    fmt::format("write each {} as {}, 0-based indices into vertices", noun, shape));
      continue;
    }
    std::array<std::uint32_t, Corners> corners{};
    bool valid = true;
    for (std::size_t corner = 0; corner < Corners; ++corner) {
      const YAML::Node value = element[corner];
      const std::string corner_name = fmt::format("{}[{}]", name, corner);
      const std::optional<std::int64_t> vertex = read_integer(context, value, element, corner_name);
      if (!vertex) {
        valid = false;
        continue;
      }
      if (*vertex < 0 || static_cast<std::uint64_t>(*vertex) >= addressable) {
        // Without a vertex list (reported there) there is no range to check against.
        if (addressable > 0)
          context.error(context.where(value, element),
                        fmt::format("{} = {} is out of range: the mesh has {} vertices",
                                    corner_name, *vertex, vertex_count),
                        fmt::format("indices are 0-based, from 0 to {}", addressable - 1));
        valid = false;
        continue;
      }
      corners[corner] = static_cast<std::uint32_t>(*vertex);
    }
    if (!valid) continue;
    // A repeated vertex leaves a triangle without area, or a quad that is a triangle at best.
    bool degenerate = false;
    for (std::size_t first = 0; first < Corners && !degenerate; ++first)
      for (std::size_t second = first + 1; second < Corners && !degenerate; ++second)
        if (corners[first] == corners[second]) {
          context.error(context.where(element, *list),
                        fmt::format("degenerate {} \"{}\": vertex {} appears twice", noun, name,
                                    corners[first]),
                        fmt::format("the corners of a {} must be distinct vertices; correct the "
                                    "index or remove the {}",
                                    noun, noun));
          degenerate = true;
        }
    if (!degenerate) elements.push_back(corners);
  }
  return static_cast<long>(list->size());
}

// An inline mesh surface: vertices plus at least one triangle or quad.
void read_mesh(MapReader& map, SurfaceSpec& surface) {
  const std::size_t vertex_count = read_mesh_vertices(map, surface);
  const long triangles =
      read_mesh_elements<3>(map, "triangles", "triangle", vertex_count, surface.mesh_triangles);
  const long quads = read_mesh_elements<4>(map, "quads", "quad", vertex_count, surface.mesh_quads);
  if (triangles != 0 || quads != 0) return;
  const std::string hint =
      "a mesh needs triangles: [[a, b, c], …] or quads: [[a, b, c, d], …] (0-based indices "
      "into vertices)";
  if (!map.has("triangles") && !map.has("quads")) {
    map.require("triangles", hint);
    return;
  }
  map.context().error(map.where_value(map.has("triangles") ? "triangles" : "quads"),
                      "a mesh surface needs at least one triangle or quad", hint);
}

}  // namespace

void read_surfaces_section(MapReader& root, const DeckParseOptions& options,
                           std::vector<SurfaceSpec>& surfaces) {
  const std::vector<std::string> common_keys = {
      "name", "type", "material", "motion", "conveyor_velocity", "export", "coupled"};
  const std::vector<std::string> stl_keys = {"file", "scale", "offset"};
  const std::vector<std::string> plane_keys = {"point", "normal", "size"};
  const std::vector<std::string> box_keys = {"min", "max"};
  const std::vector<std::string> cylinder_keys = {"base",   "axis",   "radius",
                                                  "length", "capped", "resolution"};
  const std::vector<std::string> mesh_keys = {"vertices", "triangles", "quads"};
  const std::vector<std::string> all_keys =
      union_of({common_keys, stl_keys, plane_keys, box_keys, cylinder_keys, mesh_keys});
  for (MapReader& map : list_of_maps(root, "surfaces", "surface")) {
    DeckContext& context = map.context();
    SurfaceSpec surface;
    const bool known_kind = map.has("type") && map.read("type", surface.kind, kSurfaceKinds);
    if (!known_kind) {
      map.reject_unknown_keys(all_keys);
      map.require("type", "type: is one of " + join_choices(kSurfaceKinds));
    }
    const std::string variant =
        known_kind ? fmt::format("surface type \"{}\"", map.find("type")->Scalar()) : "";
    if (known_kind) {
      switch (surface.kind.value) {
        case SurfaceKind::stl:
          map.reject_unknown_keys(joined(common_keys, stl_keys), all_keys, variant);
          read_stl_file(map, options, surface.file);
          map.read("scale", surface.scale, positive(), "1");
          map.read("offset", surface.offset);
          break;
        case SurfaceKind::plane:
          map.reject_unknown_keys(joined(common_keys, plane_keys), all_keys, variant);
          map.read("point", surface.point, Presence::required);
          if (map.read("normal", surface.normal, Presence::required))
            check_nonzero_direction(context, "normal", surface.normal);
          map.read("size", surface.size, positive(), "m");
          break;
        case SurfaceKind::box:
          map.reject_unknown_keys(joined(common_keys, box_keys), all_keys, variant);
          read_box_corners(map, "box", surface.min, surface.max);
          break;
        case SurfaceKind::cylinder:
          map.reject_unknown_keys(joined(common_keys, cylinder_keys), all_keys, variant);
          map.read("base", surface.base, Presence::required);
          if (map.read("axis", surface.axis, Presence::required))
            check_nonzero_direction(context, "axis", surface.axis);
          map.read("radius", surface.radius, positive(), "m", Presence::required);
          map.read("length", surface.length, positive(), "m", Presence::required);
          map.read("capped", surface.capped);
          map.read("resolution", surface.resolution, at_least(kMinimumCylinderResolution));
          break;
        case SurfaceKind::mesh:
          map.reject_unknown_keys(joined(common_keys, mesh_keys), all_keys, variant);
          read_mesh(map, surface);
          break;
      }
    }
    if (map.read("name", surface.name, Presence::required) && !usable_in_file_names(surface.name.value))
      context.error(surface.name.where,
                    fmt::format("surface name \"{}\" cannot be part of a file name", surface.name.value),
                    "a surface's name names its output files (NAME_000001.vtu, NAME.pvd): no '/', '\\' or "
                    "control characters, and no '.' first");
    map.read("material", surface.material, Presence::required);
    read_motion(map, surface.motion);
    map.read("conveyor_velocity", surface.conveyor_velocity);
    map.read("export", surface.export_loads);
    // One driver per surface: fixed, a prescribed motion, or the coupling partner.
    if (map.read("coupled", surface.coupled) && surface.coupled.value && map.has("motion"))
      context.error(context.where(*map.find_key("coupled")),
                    "a coupled surface cannot also have a motion",
                    "a surface has one driver (fixed, a prescribed motion or a coupling "
                    "partner); remove motion: or coupled: true");
    surfaces.push_back(std::move(surface));
  }
}

void read_factories_section(MapReader& root, std::vector<FactorySpec>& factories) {
  for (MapReader& map : list_of_maps(root, "factories", "factory")) {
    DeckContext& context = map.context();
    FactorySpec factory;
    map.reject_unknown_keys({"name", "particle_type", "region", "count", "mass", "mass_rate",
                             "start_time", "stop_time", "velocity", "angular_velocity", "max_attempts"});
    map.read("name", factory.name, Presence::required);
    map.read("particle_type", factory.particle_type, Presence::required);
    if (map.require("region")) factory.region = read_region(map, "region");
    // Exactly one of count / mass says when the factory is done.
    if (map.has("count") && map.has("mass")) {
      context.error(context.where(*map.find_key("mass")),
                    "give either count or mass in a factory, not both",
                    "count is a number of particles, mass a total in kg");
    } else if (!map.has("count") && !map.has("mass") && map.is_map()) {
      context.error(map.location(), "missing required key \"count\" or \"mass\" in factory");
    }
    Located<std::int64_t> count;
    if (map.read("count", count, at_least(1.0))) factory.target_count = count;
    Located<double> mass;
    if (map.read("mass", mass, positive(), "kg")) factory.target_mass = mass;
    Located<double> mass_rate;
    if (map.read("mass_rate", mass_rate, positive(), "kg/s")) factory.mass_rate = mass_rate;
    read_time_window(map, factory.start_time, factory.stop_time);
    map.read("velocity", factory.initial_velocity);
    map.read("angular_velocity", factory.initial_angular_velocity);
    map.read("max_attempts", factory.max_attempts, at_least(1.0));
    factories.push_back(std::move(factory));
  }
}

// A box region where a monitor needs one (stress, velocity profile): required, and a box.
void read_monitor_box(MapReader& map, MonitorSpec& monitor, const std::string& variant) {
  if (!map.require("region", "give the region as {type: box, min: [x, y, z], max: [x, y, z]}")) return;
  monitor.region = read_region(map, "region");
  if (monitor.region->kind.value != RegionKind::box)
    map.context().error(monitor.region->kind.where, fmt::format("a {} needs a box region", variant),
                        "give region: {type: box, min: [x, y, z], max: [x, y, z]}");
}

void read_monitors_section(MapReader& root, std::vector<MonitorSpec>& monitors) {
  const std::vector<std::string> common_keys = {"name", "type"};
  const std::vector<std::string> mass_keys = {"region"};
  const std::vector<std::string> particle_keys = {"id"};
  const std::vector<std::string> flow_keys = {"point", "normal", "region"};
  const std::vector<std::string> stress_keys = {"region"};
  const std::vector<std::string> profile_keys = {"region", "axis", "bins"};
  const std::vector<std::string> all_keys =
      union_of({common_keys, mass_keys, particle_keys, flow_keys, profile_keys});
  for (MapReader& map : list_of_maps(root, "monitors", "monitor")) {
    MonitorSpec monitor;
    map.read("name", monitor.name, Presence::required);
    if (map.has("type") && !map.read("type", monitor.kind, kMonitorKinds)) {
      map.reject_unknown_keys(all_keys);
      monitors.push_back(std::move(monitor));
      continue;
    }
    const std::string variant = fmt::format("monitor type \"{}\"", spelling(kMonitorKinds, monitor.kind.value));
    switch (monitor.kind.value) {
      case MonitorKind::mass:
        map.reject_unknown_keys(joined(common_keys, mass_keys), all_keys, variant);
        if (map.has("region")) {
          monitor.region = read_region(map, "region");
          if (monitor.region->kind.value == RegionKind::point)
            map.context().error(monitor.region->kind.where, "a monitor's region cannot be a point: it holds no mass",
                                "use a box or a cylinder around the place to watch");
        }
        break;
      case MonitorKind::particle:
        map.reject_unknown_keys(joined(common_keys, particle_keys), all_keys, variant);
        map.read("id", monitor.particle_id, at_least(1.0), Presence::required);
        break;
      case MonitorKind::mass_flow:
        map.reject_unknown_keys(joined(common_keys, flow_keys), all_keys, variant);
        map.read("point", monitor.point, Presence::required);
        if (map.read("normal", monitor.normal, Presence::required))
          check_nonzero_direction(map.context(), "normal", monitor.normal);
        if (map.has("region")) {  // the window of the plane that counts
          monitor.region = read_region(map, "region");
          if (monitor.region->kind.value == RegionKind::point)
            map.context().error(monitor.region->kind.where, "a mass-flow window cannot be a point: nothing crosses it",
                                "use a box or a cylinder around the opening, across the plane");
        }
        break;
      case MonitorKind::stress:
        map.reject_unknown_keys(joined(common_keys, stress_keys), all_keys, variant);
        read_monitor_box(map, monitor, variant);
        break;
      case MonitorKind::velocity_profile:
        map.reject_unknown_keys(joined(common_keys, profile_keys), all_keys, variant);
        read_monitor_box(map, monitor, variant);
        map.read("axis", monitor.axis, kAxes, Presence::required);
        map.read("bins", monitor.bins, interval(1.0, true, 10000.0, true));
        break;
    }
    monitors.push_back(std::move(monitor));
  }
}

}  // namespace quarry::deck_detail
