// Deck sections without geometry: simulation settings, output, materials, interactions and
// particle types with their size distributions. Ranges follow the physics: 0 ≤ ν < 0.5 for an
// isotropic solid, 0 < e ≤ 1 for restitution (Hertz-Mindlin damping needs ln e finite).
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>

#include "io/deck_enums.h"
#include "io/deck_sections.h"

namespace quarry::deck_detail {

namespace {

// Bounds of physical magnitudes, far outside any DEM simulation but inside what double arithmetic
// and a 64-bit step count hold: a value beyond them is a typo, and the time step, the Rayleigh
// and Hertz times and the step count computed from it would be meaningless (1e308 Pa gave
// "use a time step <= 0 s"; 1e-320 s a negative step count).
const Range kTimeStepRange = interval(1e-12, true, 10.0, true);       // s
const Range kEndTimeRange = interval(0.0, false, 1e7, true);          // s, 116 days
const Range kDensityRange = interval(0.0, false, 1e5, true);          // kg/m³ (osmium: 22,590)
const Range kYoungsModulusRange = interval(0.0, false, 1e13, true);   // Pa (diamond: 1.2e12)

// Mass fractions of a discrete distribution must sum to one within this tolerance (1).
constexpr double kMassFractionSumTolerance = 1e-6;
// Default clip bounds of normal and log-normal sizes: mean ± this many standard deviations.
constexpr double kDefaultClipStandardDeviations = 3.0;

// Reads `time_step:` either as a fixed step in seconds or as {rayleigh_fraction: f}.
void read_time_step(MapReader& simulation, SimulationSettings& settings) {
  const YAML::Node* value = simulation.find("time_step");
  if (!value) return;
  DeckContext& context = simulation.context();
  if (value->IsMap()) {
    MapReader fraction(context, *value, *simulation.find_key("time_step"), "time_step");
    fraction.reject_unknown_keys({"rayleigh_fraction"});
    fraction.read("rayleigh_fraction", settings.rayleigh_fraction, interval(0.0, false, 1.0, true),
                  "1", Presence::required);
    return;
  }
  Located<double> fixed;
  if (simulation.read("time_step", fixed, kTimeStepRange, "s")) settings.fixed_time_step = fixed;
}

// `periodic: [x, y]`: the periodic axes, each named once.
void read_periodic_axes(MapReader& box, Located<std::array<bool, 3>>& periodic) {
  if (!box.has("periodic")) return;
  DeckContext& context = box.context();
  const std::vector<std::string> axis_names = {"x", "y", "z"};
  std::array<bool, 3> axes{false, false, false};
  bool valid = true;
  for (const YAML::Node& element : read_list(box, "periodic")) {
    const std::optional<std::string> word =
        read_string(context, element, *box.find_key("periodic"), "periodic");
    if (!word) {
      valid = false;
      continue;
    }
    const auto named = std::find(axis_names.begin(), axis_names.end(), *word);
    if (named == axis_names.end()) {
      context.error(context.where(element, *box.find_key("periodic")),
                    fmt::format("unknown axis \"{}\" in periodic", *word),
                    suggestion_hint(*word, axis_names, "periodic lists axes among: "));
      valid = false;
      continue;
    }
    const auto axis = static_cast<std::size_t>(named - axis_names.begin());
    if (axes[axis]) {
      context.error(context.where(element, *box.find_key("periodic")),
                    fmt::format("axis \"{}\" is listed twice in periodic", *word),
                    "name each periodic axis once, e.g. periodic: [x, y]");
      valid = false;
    }
    axes[axis] = true;
  }
  if (valid) periodic = Located<std::array<bool, 3>>(axes, box.where_value("periodic"));
}

void read_domain(MapReader& simulation, Located<Aabb>& domain,
                 Located<std::array<bool, 3>>& periodic) {
  const YAML::Node* value = simulation.find("domain");
  if (!value) {
    simulation.require("domain");
    return;
  }
  MapReader box(simulation.context(), *value, *simulation.find_key("domain"), "domain");
  box.reject_unknown_keys({"min", "max", "periodic"});
  read_periodic_axes(box, periodic);
  Located<Vec3> lower, upper;
  const bool has_lower = box.read("min", lower, Presence::required);
  const bool has_upper = box.read("max", upper, Presence::required);
  if (!has_lower || !has_upper || !check_box_corners(box.context(), "domain", lower, upper)) return;
  Aabb bounds;
  bounds.lo = lower.value;
  bounds.hi = upper.value;
  domain = Located<Aabb>(bounds, box.location());
}

void read_size_distribution(MapReader& particle_type, SizeDistributionSpec& size) {
  const YAML::Node* value = particle_type.find("size");
  if (!value) {
    particle_type.require("size");
    return;
  }
  DeckContext& context = particle_type.context();
  MapReader map(context, *value, *particle_type.find_key("size"), "size");
  if (!map.is_map()) return;
  const std::vector<std::string> all_keys = {
      "distribution", "radius",        "min_radius", "max_radius", "mean_radius",
      "std_radius",   "median_radius", "log_std",    "radii",      "mass_fractions"};
  // Without a valid kind only the union of all kinds' keys can be checked; checking before
  // `require` lets a misspelled "distribution" be reported once, as a misspelling.
  if (!map.has("distribution") || !map.read("distribution", size.kind, kSizeDistributions)) {
    map.reject_unknown_keys(all_keys);
    map.require("distribution", "distribution: is one of " + join_choices(kSizeDistributions));
    return;
  }
  const std::string variant =
      fmt::format("size distribution \"{}\"", map.find("distribution")->Scalar());
  switch (size.kind.value) {
    case SizeDistributionKind::fixed:
      map.reject_unknown_keys({"distribution", "radius"}, all_keys, variant);
      map.read("radius", size.radius, positive(), "m", Presence::required);
      break;
    case SizeDistributionKind::uniform: {
      map.reject_unknown_keys({"distribution", "min_radius", "max_radius"}, all_keys, variant);
      const bool has_min =
          map.read("min_radius", size.min_radius, positive(), "m", Presence::required);
      const bool has_max =
          map.read("max_radius", size.max_radius, positive(), "m", Presence::required);
      if (has_min && has_max)
        check_range(context, size.max_radius.where, "max_radius", size.max_radius,
                    at_least(size.min_radius), "m");
      break;
    }
    case SizeDistributionKind::normal:
    case SizeDistributionKind::log_normal: {
      const bool is_normal = size.kind.value == SizeDistributionKind::normal;
      const char* centre_key = is_normal ? "mean_radius" : "median_radius";
      const char* spread_key = is_normal ? "std_radius" : "log_std";
      map.reject_unknown_keys({"distribution", centre_key, spread_key, "min_radius", "max_radius"},
                              all_keys, variant);
      Located<double> centre, spread;
      const bool has_centre = map.read(centre_key, centre, positive(), "m", Presence::required);
      const bool has_spread =
          map.read(spread_key, spread, positive(), is_normal ? "m" : "1", Presence::required);
      const bool explicit_min = map.has("min_radius");
      const bool explicit_max = map.has("max_radius");
      bool bounds_valid = map.read("min_radius", size.min_radius, positive(), "m") || !explicit_min;
      bounds_valid = (map.read("max_radius", size.max_radius, positive(), "m") || !explicit_max) &&
                     bounds_valid;
      if (!has_centre || !has_spread) break;
      const SourceLocation spread_where = spread.where;
      if (is_normal) {
        size.mean_radius = centre;
        size.std_radius = spread;
      } else {
        // log_mean = ln(median / 1 m): the median of a log-normal is exp(μ) (e.g. Crow &
        // Shimizu, "Lognormal Distributions", 1988, ch. 1).
        size.log_mean = Located<double>(std::log(centre.value), centre.where);
        size.log_std = spread;
      }
      const double spread_radius = kDefaultClipStandardDeviations * spread.value;
      if (!explicit_min) {
        const double default_min =
            is_normal ? centre.value - spread_radius : centre.value * std::exp(-spread_radius);
        size.min_radius = Located<double>(default_min, map.location());
        if (default_min <= 0.0) {
          context.error(
              spread_where,
              fmt::format("the default min_radius = mean_radius − 3 std_radius = {:.6g} m "
                          "is not > 0 m",
                          default_min),
              "give min_radius > 0 explicitly");
          bounds_valid = false;
        }
      }
      if (!explicit_max) {
        const double default_max =
            is_normal ? centre.value + spread_radius : centre.value * std::exp(spread_radius);
        size.max_radius = Located<double>(default_max, map.location());
      }
      if (bounds_valid && size.max_radius.value <= size.min_radius.value)
        context.error(size.max_radius.where,
                      fmt::format("max_radius must be > min_radius = {} m, got {} m",
                                  size.min_radius.value, size.max_radius.value));
      break;
    }
    case SizeDistributionKind::discrete: {
      map.reject_unknown_keys({"distribution", "radii", "mass_fractions"}, all_keys, variant);
      const bool has_radii = map.require("radii");
      const bool has_fractions = map.require("mass_fractions");
      if (!has_radii || !has_fractions) break;
      const auto read_positive_list = [&](const std::string& key, const std::string& unit,
                                          std::vector<Located<double>>& out) {
        const YAML::Node& list = *map.find(key);
        if (!list.IsSequence() || list.size() == 0) {
          context.error(map.where_value(key),
                        fmt::format("expected a non-empty list of numbers for \"{}\", got {}", key,
                                    describe_node(list)));
          return false;
        }
        bool valid = true;
        for (std::size_t index = 0; index < list.size(); ++index) {
          const std::string element_name = fmt::format("{}[{}]", key, index);
          const std::optional<double> number =
              read_number(context, list[index], list, element_name);
          if (!number) {
            valid = false;
            continue;
          }
          const SourceLocation at = context.where(list[index], list);
          valid = check_range(context, at, element_name, *number, positive(), unit) && valid;
          out.emplace_back(*number, at);
        }
        return valid;
      };
      const bool radii_valid = read_positive_list("radii", "m", size.discrete_radii);
      const bool fractions_valid =
          read_positive_list("mass_fractions", "1", size.discrete_mass_fractions);
      if (!radii_valid || !fractions_valid) break;
      if (size.discrete_radii.size() != size.discrete_mass_fractions.size()) {
        context.error(map.where_value("mass_fractions"),
                      fmt::format("mass_fractions has {} entries but radii has {}",
                                  size.discrete_mass_fractions.size(), size.discrete_radii.size()),
                      "give one mass fraction per radius");
        break;
      }
      double sum = 0.0;
      for (const auto& fraction : size.discrete_mass_fractions) sum += fraction.value;
      if (std::abs(sum - 1.0) > kMassFractionSumTolerance)
        context.error(map.where_value("mass_fractions"),
                      fmt::format("mass_fractions must sum to 1, got {:.10g}", sum),
                      "fractions are shares of the total mass, e.g. [0.25, 0.75]");
      break;
    }
  }
}

CalculixSpec read_calculix(MapReader& map) {
  CalculixSpec calculix;
  map.reject_unknown_keys({"thickness", "youngs_modulus", "poisson_ratio", "density", "analysis",
                           "time", "supports"});
  map.read("thickness", calculix.thickness, positive(), "m", Presence::required);
  map.read("youngs_modulus", calculix.youngs_modulus, positive(), "Pa", Presence::required);
  map.read("poisson_ratio", calculix.poisson_ratio, interval(0.0, true, 0.5, false), "1");
  map.read("analysis", calculix.analysis, kCalculixAnalyses);
  const bool dynamic = calculix.analysis.value == CalculixAnalysis::dynamic;
  // The dynamic analysis needs the mass of the structure; a static one ignores it.
  map.read("density", calculix.density, positive(), "kg/m³",
           dynamic ? Presence::required : Presence::optional);
  Located<double> time;
  if (map.read("time", time, non_negative(), "s")) {
    if (dynamic)
      map.context().error(time.where, "time applies only to analysis: static",
                          "the dynamic analysis uses the whole load history");
    else
      calculix.static_time = time;
  }
  for (MapReader& support_map : list_of_maps(map, "supports", "support"))
    calculix.supports.push_back(read_support(support_map, false));
  return calculix;
}

}  // namespace

SupportSpec read_support(MapReader& map, bool groups) {
  SupportSpec support;
  if (groups)
    map.reject_unknown_keys({"name", "box", "group", "fix"});
  else
    map.reject_unknown_keys({"name", "box", "fix"});
  map.read("name", support.name, Presence::required);
  map.read("fix", support.fix, kSupportFixities);
  if (groups && map.read("group", support.group)) {
    if (const YAML::Node* box = map.find_key("box"))
      map.context().error(map.context().where(*box), "a support takes a box or a group, not both",
                          "keep the group (the mesh's physical group of points or curves)");
    return support;
  }
  if (!map.require("box", groups ? "box: {min: [x, y, z], max: [x, y, z]} selects the nodes "
                                   "inside, or group: a physical group of points or curves"
                                 : "box: {min: [x, y, z], max: [x, y, z]} selects the nodes inside"))
    return support;
  MapReader box(map.context(), *map.find("box"), *map.find_key("box"), "box");
  if (!box.is_map()) return support;
  box.reject_unknown_keys({"min", "max"});
  const bool has_lower = box.read("min", support.min, Presence::required);
  const bool has_upper = box.read("max", support.max, Presence::required);
  // A flat box is allowed (nodes on a plane edge): only min > max in some component is wrong.
  if (has_lower && has_upper)
    for (int axis = 0; axis < 3; ++axis)
      if (support.max.value[axis] < support.min.value[axis]) {
        map.context().error(support.max.where,
                            fmt::format("support box max must be ≥ min in every component, got "
                                        "max[{}] = {} m < min[{}] = {} m",
                                        axis, support.max.value[axis], axis,
                                        support.min.value[axis]),
                            "swap the corners");
        break;
      }
  return support;
}

void read_export_section(MapReader& root, ExportSpec& fem_export) {
  const YAML::Node* value = root.find("export");
  if (!value) return;
  MapReader map(root.context(), *value, *root.find_key("export"), "export");
  fem_export.enabled = true;
  fem_export.where = map.location();
  map.reject_unknown_keys({"interval", "directory", "formats", "calculix"});
  map.read("interval", fem_export.interval, positive(), "s", Presence::required);
  map.read("directory", fem_export.directory);
  DeckContext& context = map.context();
  if (const YAML::Node* formats = map.find("formats")) {
    if (!formats->IsSequence() || formats->size() == 0) {
      context.error(map.where_value("formats"),
                    fmt::format("expected a non-empty list of formats for \"formats\", got {}",
                                describe_node(*formats)),
                    "write it as formats: [" + join_choices(kExportFormats) + "]");
    } else {
      for (std::size_t index = 0; index < formats->size(); ++index) {
        const std::string key = fmt::format("formats[{}]", index);
        if (const auto format = read_enum(context, (*formats)[index], *formats, key, kExportFormats))
          fem_export.formats.emplace_back(*format, context.where((*formats)[index], *formats));
      }
    }
  }
  const bool wants_calculix =
      fem_export.formats.empty() ||
      std::any_of(fem_export.formats.begin(), fem_export.formats.end(),
                  [](const Located<ExportFormat>& f) { return f.value == ExportFormat::calculix; });
  if (map.has("calculix")) {
    MapReader calculix(context, *map.find("calculix"), *map.find_key("calculix"), "calculix");
    if (calculix.is_map()) fem_export.calculix = read_calculix(calculix);
  } else if (wants_calculix && map.is_map()) {
    map.require("calculix",
                "the CalculiX deck needs calculix: {thickness, youngs_modulus, poisson_ratio, "
                "supports}; or leave calculix out of formats:");
  }
}

std::vector<MapReader> list_of_maps(MapReader& parent, const std::string& key,
                                    const std::string& what) {
  std::vector<MapReader> maps;
  for (const YAML::Node& element : read_list(parent, key))
    maps.emplace_back(parent.context(), element, *parent.find_key(key), what);
  return maps;
}

void read_simulation_section(MapReader& root, SimulationSettings& settings) {
  const YAML::Node* value = root.find("simulation");
  if (!value) {
    root.require("simulation");
    return;
  }
  MapReader map(root.context(), *value, *root.find_key("simulation"), "simulation");
  map.reject_unknown_keys({"end_time", "time_step", "impact_speed", "gravity", "domain",
                           "integrator", "threads", "skin", "sort_interval", "max_overlap_fraction",
                           "seed"});
  map.read("end_time", settings.end_time, kEndTimeRange, "s", Presence::required);
  read_time_step(map, settings);
  Located<double> impact_speed;
  if (map.read("impact_speed", impact_speed, positive(), "m/s"))
    settings.impact_speed = impact_speed;
  map.read("gravity", settings.gravity);
  read_domain(map, settings.domain, settings.periodic);
  map.read("integrator", settings.integrator, kIntegrators);
  map.read("threads", settings.threads, non_negative());
  // `skin: auto`: chosen at every list build from the fastest particle (sim/world_update.cpp);
  // a word that is neither a number nor `auto` says that both exist.
  const YAML::Node* skin = map.find("skin");
  double skin_number = 0.0;  // m
  if (skin && skin->IsScalar() && skin->Scalar() == "auto")
    settings.skin = Located<double>{-1.0, map.where_value("skin")};
  else if (skin && skin->IsScalar() && !YAML::convert<double>::decode(*skin, skin_number))
    map.context().error(map.where_value("skin"),
                        fmt::format("expected a number (m) or auto for \"skin\", got \"{}\"", skin->Scalar()),
                        suggestion_hint(skin->Scalar(), {"auto"}, "a fixed skin in m, or "));
  else
    map.read("skin", settings.skin, non_negative(), "m");
  map.read("sort_interval", settings.sort_interval, non_negative());
  map.read("max_overlap_fraction", settings.max_overlap_fraction, interval(0.0, false, 1.0, true),
           "1");
  Located<std::int64_t> seed;
  if (map.read("seed", seed, non_negative()))
    settings.seed = static_cast<std::uint64_t>(seed.value);
}

void read_output_section(MapReader& root, OutputSpec& output) {
  const YAML::Node* value = root.find("output");
  if (!value) return;
  MapReader map(root.context(), *value, *root.find_key("output"), "output");
  map.reject_unknown_keys({"directory", "interval", "monitor_interval", "checkpoint_interval",
                           "plots", "progress_interval", "contacts"});
  map.read("directory", output.directory);
  map.read("interval", output.interval, non_negative(), "s");
  map.read("monitor_interval", output.monitor_interval, non_negative(), "s");
  map.read("checkpoint_interval", output.checkpoint_interval, non_negative(), "s");
  map.read("plots", output.plots);
  map.read("progress_interval", output.progress_interval, non_negative(), "s");
  map.read("contacts", output.contacts);
}

void read_materials_section(MapReader& root, std::vector<MaterialSpec>& materials) {
  if (!root.require("materials")) return;
  std::vector<MapReader> maps = list_of_maps(root, "materials", "material");
  const YAML::Node& listed = *root.find("materials");
  if (maps.empty() && (listed.IsNull() || (listed.IsSequence() && listed.size() == 0)))
    root.context().error(root.context().where(*root.find_key("materials")),
                         "materials must list at least one material",
                         "add e.g. - {name: ore, density: 2500, youngs_modulus: 5.0e7, "
                         "poisson_ratio: 0.25}");
  for (MapReader& map : maps) {
    MaterialSpec material;
    map.read("rigid", material.rigid);
    if (material.rigid.value)  // infinitely stiff: no elastic constants to give
      map.reject_unknown_keys({"name", "density", "rigid"}, {"youngs_modulus", "poisson_ratio"},
                              "a rigid material (rigid: true)");
    else
      map.reject_unknown_keys({"name", "density", "youngs_modulus", "poisson_ratio", "rigid"});
    map.read("name", material.name, Presence::required);
    map.read("density", material.density, kDensityRange, "kg/m³", Presence::required);
    if (!material.rigid.value) {
      map.read("youngs_modulus", material.youngs_modulus, kYoungsModulusRange, "Pa", Presence::required);
      // Isotropic elasticity requires −1 < ν < 0.5; granular solids have ν ≥ 0.
      map.read("poisson_ratio", material.poisson_ratio, interval(0.0, true, 0.5, false), "1",
               Presence::required);
    }
    materials.push_back(std::move(material));
  }
}

void read_interactions_section(MapReader& root, std::vector<InteractionSpec>& interactions) {
  for (MapReader& map : list_of_maps(root, "interactions", "interaction")) {
    DeckContext& context = map.context();
    InteractionSpec interaction;
    const std::vector<std::string> common_keys = {
        "materials",     "restitution",    "static_friction", "rolling_friction",
        "rolling_model", "cohesion_model", "model",           "clip_attraction"};
    const std::vector<std::string> linear_keys = {"stiffness", "tangential_stiffness_ratio"};
    const std::vector<std::string> sjkr_keys = {"cohesion"}, jkr_keys = {"surface_energy"};
    const bool known_model = map.read("model", interaction.normal_model, kContactModels);
    const bool is_linear = interaction.normal_model.value == NormalModel::linear;
    const bool known_cohesion =
        map.read("cohesion_model", interaction.cohesion_model, kCohesionModels);
    const bool is_jkr = interaction.cohesion_model.value == CohesionModel::jkr;
    // Keys of the variants this interaction is (all of them while a variant is misspelt, which
    // is reported already), and those of the others.
    std::vector<std::string> allowed = common_keys, others;
    const auto take = [&](const std::vector<std::string>& keys, bool applies) {
      (applies ? allowed : others).insert((applies ? allowed : others).end(), keys.begin(), keys.end());
    };
    take(linear_keys, is_linear || (map.has("model") && !known_model));
    const bool any_cohesion = map.has("cohesion_model") && !known_cohesion;
    take(sjkr_keys, !is_jkr || any_cohesion);
    take(jkr_keys, is_jkr || any_cohesion);
    map.reject_unknown_keys(allowed, others,
                            fmt::format("contact model \"{}\" with cohesion_model \"{}\"",
                                        is_linear ? "linear" : "hertz_mindlin",
                                        is_jkr ? "jkr" : "sjkr"));

    if (const YAML::Node* names = map.find("materials")) {
      if (!names->IsSequence() || names->size() != 2) {
        context.error(map.where_value("materials"),
                      fmt::format("expected a list of 2 material names for \"materials\", got {}",
                                  describe_node(*names)),
                      "write it as materials: [ore, steel]");
      } else {
        if (const auto first = read_string(context, (*names)[0], *names, "materials[0]"))
          interaction.material_a = Located<std::string>(*first, context.where((*names)[0]));
        if (const auto second = read_string(context, (*names)[1], *names, "materials[1]"))
          interaction.material_b = Located<std::string>(*second, context.where((*names)[1]));
      }
    } else {
      map.require("materials");
    }
    map.read("restitution", interaction.restitution, interval(0.0, false, 1.0, true), "1");
    map.read("static_friction", interaction.static_friction, non_negative(), "1");
    map.read("rolling_friction", interaction.rolling_friction, non_negative(), "1");
    map.read("rolling_model", interaction.rolling_model, kRollingModels);
    map.read("cohesion", interaction.cohesion_energy_density, non_negative(), "J/m³");
    if (is_jkr && map.is_map() && !map.has("surface_energy"))
      context.error(map.where_value("cohesion_model"),
                    "missing required key \"surface_energy\" in interaction",
                    "cohesion_model: jkr needs JKR's surface energy in J/m², e.g. "
                    "surface_energy: 0.05");
    map.read("surface_energy", interaction.surface_energy, positive(), "J/m²");
    map.read("clip_attraction", interaction.clip_attraction);
    if (is_linear) {
      if (!map.has("stiffness") && map.is_map())
        context.error(
            map.location(), "missing required key \"stiffness\" in interaction",
            "model: linear needs the normal spring stiffness in N/m, e.g. stiffness: 1.0e4");
      map.read("stiffness", interaction.linear_stiffness, positive(), "N/m");
      map.read("tangential_stiffness_ratio", interaction.linear_tangential_ratio, positive(), "1");
    }
    interactions.push_back(std::move(interaction));
  }
}

void read_particle_types_section(MapReader& root, std::vector<ParticleTypeSpec>& particle_types) {
  for (MapReader& map : list_of_maps(root, "particle_types", "particle type")) {
    ParticleTypeSpec particle_type;
    map.reject_unknown_keys({"name", "material", "size", "fixed"});
    map.read("name", particle_type.name, Presence::required);
    map.read("material", particle_type.material, Presence::required);
    map.read("fixed", particle_type.fixed);
    read_size_distribution(map, particle_type.size);
    particle_types.push_back(std::move(particle_type));
  }
}

}  // namespace quarry::deck_detail
