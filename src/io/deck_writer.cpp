// Deck writer: one line per key in the order of docs/deck.md, vectors and small maps in flow
// style. Numbers use fmt's shortest round-trip form and names are quoted only where plain YAML
// would read them differently, so the text reads back into the same spec.
#include "io/deck_writer.h"

#include <fmt/format.h>

#include <array>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string_view>
#include <utility>
#include <vector>

#include "io/deck_enums.h"
#include "io/deck_sections.h"

namespace quarry {

namespace {

// A stop time at or beyond this is the "never" default of MotionSpec and FactorySpec (s).
constexpr double kNever = 1e300;
// How far from exp(log_mean) the median of a log-normal size is looked for, in ulps each way;
// exp and log are each within an ulp or so, and |ln R| below ~700 stretches that to a few
// hundred ulps of R at most.
constexpr int kMedianSearchUlps = 4096;

// Shortest text that reads back as the same double.
std::string number(double value) {
  return fmt::format("{}", value);
}

std::string vector_text(const Vec3& value) {
  return fmt::format("[{}, {}, {}]", number(value.x), number(value.y), number(value.z));
}

// True when a plain YAML scalar spelled `text` reads back as the same string and looks like
// one to a reader: a letter, `_` or `/` first (no number, no indicator such as -, ?, [, &, *,
// ", #), then only letters, digits and `_./-+`, and not a word YAML reads as null or a boolean.
bool is_plain_safe(std::string_view text) {
  if (text.empty()) return false;
  std::string lower(text);
  for (char& c : lower)
    if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
  for (const char* word : {"null", "true", "false", "yes", "no", "on", "off", "y", "n"})
    if (lower == word) return false;
  const auto is_letter = [](char c) { return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z'); };
  const char first = text.front();
  if (!is_letter(first) && first != '_' && first != '/') return false;
  for (const char c : text)
    if (!is_letter(c) && !(c >= '0' && c <= '9') && c != '_' && c != '.' && c != '/' && c != '-' &&
        c != '+')
      return false;
  return true;
}

// A name or path: plain where that is safe, else double-quoted with YAML escapes.
std::string text(const std::string& value) {
  if (is_plain_safe(value)) return value;
  std::string quoted = "\"";
  for (const char c : value) {
    const auto byte = static_cast<unsigned char>(c);
    if (c == '"' || c == '\\') {
      quoted += '\\';
      quoted += c;
    } else if (byte < 0x20 || byte == 0x7f) {
      quoted += fmt::format("\\x{:02x}", byte);
    } else {
      quoted += c;  // UTF-8 passes through
    }
  }
  return quoted + "\"";
}

const char* boolean(bool value) {
  return value ? "true" : "false";
}

// Spellings of the enumerated keys: the parser's own tables (deck_enums.h).
const std::string& spelling(Integrator v) { return deck_detail::spelling(deck_detail::kIntegrators, v); }
const std::string& spelling(NormalModel v) { return deck_detail::spelling(deck_detail::kContactModels, v); }
const std::string& spelling(CohesionModel v) { return deck_detail::spelling(deck_detail::kCohesionModels, v); }
const std::string& spelling(RollingModel v) { return deck_detail::spelling(deck_detail::kRollingModels, v); }
const std::string& spelling(SizeDistributionKind v) { return deck_detail::spelling(deck_detail::kSizeDistributions, v); }
const std::string& spelling(SurfaceKind v) { return deck_detail::spelling(deck_detail::kSurfaceKinds, v); }
const std::string& spelling(MotionKind v) { return deck_detail::spelling(deck_detail::kMotionKinds, v); }
const std::string& spelling(RegionKind v) { return deck_detail::spelling(deck_detail::kRegionKinds, v); }
const std::string& spelling(ExportFormat v) { return deck_detail::spelling(deck_detail::kExportFormats, v); }
const std::string& spelling(CalculixAnalysis v) { return deck_detail::spelling(deck_detail::kCalculixAnalyses, v); }
const std::string& spelling(SupportFixity v) { return deck_detail::spelling(deck_detail::kSupportFixities, v); }
const std::string& spelling(MeshLengthUnit v) { return deck_detail::spelling(deck_detail::kMeshLengthUnits, v); }
const std::string& spelling(MonitorKind v) { return deck_detail::spelling(deck_detail::kMonitorKinds, v); }
const std::string& spelling(Axis v) { return deck_detail::spelling(deck_detail::kAxes, v); }

// The median radius (m) to write for a log-normal size. The parser stores log_mean =
// ln(median), so the median written must be a double whose logarithm is log_mean exactly; of
// those, the one with the fewest significant digits, which is the user's own median when the
// spec came from a deck. Falls back to exp(log_mean) when no double maps onto log_mean
// (possible only for a log_mean set in code, and then the round trip is off by an ulp).
double median_radius_of(double log_mean) {
  const double estimate = std::exp(log_mean);
  const auto matches = [log_mean](double median) { return std::log(median) == log_mean; };
  double found = estimate;
  double above = estimate, below = estimate;
  for (int step = 0; step < kMedianSearchUlps && !matches(found); ++step) {
    above = std::nextafter(above, std::numeric_limits<double>::infinity());
    below = std::nextafter(below, 0.0);
    found = matches(above) ? above : below;
  }
  if (!matches(found)) return estimate;
  // 17 significant digits give `found` back exactly, so the loop ends with a match.
  for (int digits = 1; digits <= 17; ++digits) {
    const std::string rounded = fmt::format("{:.{}e}", found, digits - 1);
    double candidate = 0.0;
    std::from_chars(rounded.data(), rounded.data() + rounded.size(), candidate);
    if (matches(candidate)) return candidate;
  }
  return found;
}

std::string region_text(const RegionSpec& region) {
  switch (region.kind.value) {
    case RegionKind::box:
      return fmt::format("{{type: {}, min: {}, max: {}}}", spelling(region.kind),
                         vector_text(region.min), vector_text(region.max));
    case RegionKind::cylinder:
      return fmt::format("{{type: {}, base: {}, axis: {}, radius: {}, length: {}}}",
                         spelling(region.kind), vector_text(region.base), vector_text(region.axis),
                         number(region.radius), number(region.length));
    case RegionKind::point:
      return fmt::format("{{type: {}, position: {}}}", spelling(region.kind), vector_text(region.position));
  }
  return "{}";
}

std::string number_list(const std::vector<Located<double>>& values) {
  std::string list;
  for (const Located<double>& value : values) list += (list.empty() ? "" : ", ") + number(value);
  return "[" + list + "]";
}

// The whole deck is appended to one string, a line at a time.
class DeckText {
 public:
  // `indent` spaces, then the line.
  template <class... Args>
  void line(int indent, fmt::format_string<Args...> format, Args&&... args) {
    out_.append(static_cast<std::size_t>(indent), ' ');
    out_ += fmt::format(format, std::forward<Args>(args)...);
    out_ += '\n';
  }
  std::string take() { return std::move(out_); }

 private:
  std::string out_;
};

// The key of a top-level list, with [] when the list is empty (plainer than a bare key).
void list_key(DeckText& deck, const char* key, bool empty) {
  deck.line(0, "{}:{}", key, empty ? " []" : "");
}

void write_simulation(DeckText& deck, const SimulationSettings& settings) {
  deck.line(0, "simulation:");
  deck.line(2, "end_time: {}", number(settings.end_time));
  if (settings.fixed_time_step)
    deck.line(2, "time_step: {}", number(*settings.fixed_time_step));
  else
    deck.line(2, "time_step: {{rayleigh_fraction: {}}}", number(settings.rayleigh_fraction));
  if (settings.impact_speed) deck.line(2, "impact_speed: {}", number(*settings.impact_speed));
  deck.line(2, "gravity: {}", vector_text(settings.gravity));
  std::string periodic;  // ", periodic: [x, y]" when some axis is periodic
  for (int a = 0; a < 3; ++a)
    if (settings.periodic.value[a])
      periodic += std::string(periodic.empty() ? "" : ", ") + "xyz"[a];
  if (!periodic.empty()) periodic = ", periodic: [" + periodic + "]";
  deck.line(2, "domain: {{min: {}, max: {}{}}}", vector_text(settings.domain.value.lo),
            vector_text(settings.domain.value.hi), periodic);
  deck.line(2, "integrator: {}", spelling(settings.integrator));
  deck.line(2, "threads: {}", settings.threads.value);
  if (settings.skin.value < 0.0)
    deck.line(2, "skin: auto");
  else
    deck.line(2, "skin: {}", number(settings.skin));
  deck.line(2, "sort_interval: {}", settings.sort_interval.value);
  deck.line(2, "max_overlap_fraction: {}", number(settings.max_overlap_fraction));
  deck.line(2, "seed: {}", settings.seed);
}

void write_materials(DeckText& deck, const std::vector<MaterialSpec>& materials) {
  list_key(deck, "materials", materials.empty());
  for (const MaterialSpec& material : materials) {
    deck.line(2, "- name: {}", text(material.name));
    deck.line(4, "density: {}", number(material.density));
    if (material.rigid.value) {
      deck.line(4, "rigid: true");
      continue;
    }
    deck.line(4, "youngs_modulus: {}", number(material.youngs_modulus));
    deck.line(4, "poisson_ratio: {}", number(material.poisson_ratio));
  }
}

void write_interactions(DeckText& deck, const std::vector<InteractionSpec>& interactions) {
  list_key(deck, "interactions", interactions.empty());
  for (const InteractionSpec& interaction : interactions) {
    deck.line(2, "- materials: [{}, {}]", text(interaction.material_a),
              text(interaction.material_b));
    deck.line(4, "model: {}", spelling(interaction.normal_model));
    deck.line(4, "restitution: {}", number(interaction.restitution));
    deck.line(4, "static_friction: {}", number(interaction.static_friction));
    deck.line(4, "rolling_friction: {}", number(interaction.rolling_friction));
    deck.line(4, "rolling_model: {}", spelling(interaction.rolling_model));
    deck.line(4, "cohesion_model: {}", spelling(interaction.cohesion_model));
    // Each cohesion model's key belongs to it only; the parser rejects it otherwise.
    if (interaction.cohesion_model.value == CohesionModel::jkr)
      deck.line(4, "surface_energy: {}", number(interaction.surface_energy));
    else
      deck.line(4, "cohesion: {}", number(interaction.cohesion_energy_density));
    deck.line(4, "clip_attraction: {}", boolean(interaction.clip_attraction));
    // The spring keys belong to model: linear only; the parser rejects them otherwise.
    if (interaction.normal_model.value == NormalModel::linear) {
      deck.line(4, "stiffness: {}", number(interaction.linear_stiffness));
      deck.line(4, "tangential_stiffness_ratio: {}", number(interaction.linear_tangential_ratio));
    }
  }
}

std::string size_text(const SizeDistributionSpec& size) {
  const std::string& kind = spelling(size.kind);
  switch (size.kind.value) {
    case SizeDistributionKind::fixed:
      return fmt::format("{{distribution: {}, radius: {}}}", kind, number(size.radius));
    case SizeDistributionKind::uniform:
      return fmt::format("{{distribution: {}, min_radius: {}, max_radius: {}}}", kind,
                         number(size.min_radius), number(size.max_radius));
    // The clip bounds are written even when the deck left them to their defaults (mean ± 3
    // std): the values the run uses.
    case SizeDistributionKind::normal:
      return fmt::format(
          "{{distribution: {}, mean_radius: {}, std_radius: {}, min_radius: {}, max_radius: {}}}",
          kind, number(size.mean_radius), number(size.std_radius), number(size.min_radius),
          number(size.max_radius));
    case SizeDistributionKind::log_normal:
      return fmt::format(
          "{{distribution: {}, median_radius: {}, log_std: {}, min_radius: {}, max_radius: {}}}",
          kind, number(median_radius_of(size.log_mean)), number(size.log_std),
          number(size.min_radius), number(size.max_radius));
    case SizeDistributionKind::discrete:
      return fmt::format("{{distribution: {}, radii: {}, mass_fractions: {}}}", kind,
                         number_list(size.discrete_radii),
                         number_list(size.discrete_mass_fractions));
  }
  return "{}";
}

void write_particle_types(DeckText& deck, const std::vector<ParticleTypeSpec>& particle_types) {
  list_key(deck, "particle_types", particle_types.empty());
  for (const ParticleTypeSpec& particle_type : particle_types) {
    deck.line(2, "- name: {}", text(particle_type.name));
    deck.line(4, "material: {}", text(particle_type.material));
    deck.line(4, "size: {}", size_text(particle_type.size));
    deck.line(4, "fixed: {}", boolean(particle_type.fixed));
  }
}

std::string motion_text(const MotionSpec& motion) {
  std::string keys;
  switch (motion.kind.value) {
    case MotionKind::rotation:
      keys = fmt::format(", axis_point: {}, axis_direction: {}, angular_velocity: {}",
                         vector_text(motion.axis_point), vector_text(motion.axis_direction),
                         number(motion.angular_velocity));
      break;
    case MotionKind::translation:
      keys = fmt::format(", velocity: {}", vector_text(motion.velocity));
      break;
    case MotionKind::vibration:
      keys = fmt::format(", amplitude: {}, frequency: {}", vector_text(motion.amplitude),
                         number(motion.frequency));
      break;
    case MotionKind::none:
      break;  // not written: no motion key means none
  }
  keys += fmt::format(", start_time: {}", number(motion.start_time));
  if (motion.stop_time.value < kNever)
    keys += fmt::format(", stop_time: {}", number(motion.stop_time));
  return fmt::format("{{type: {}{}}}", spelling(motion.kind), keys);
}

// One vertex or element a line: a mesh of a few hundred entries stays readable and diffable.
template <class Element, class Format>
void write_list(DeckText& deck, const std::string& key, const std::vector<Element>& elements,
                Format&& format_element) {
  if (elements.empty()) {
    deck.line(4, "{}: []", key);
    return;
  }
  deck.line(4, "{}:", key);
  for (const Element& element : elements) deck.line(6, "- {}", format_element(element));
}

void write_surfaces(DeckText& deck, const std::vector<SurfaceSpec>& surfaces) {
  list_key(deck, "surfaces", surfaces.empty());
  for (const SurfaceSpec& surface : surfaces) {
    deck.line(2, "- name: {}", text(surface.name));
    deck.line(4, "type: {}", spelling(surface.kind));
    switch (surface.kind.value) {
      case SurfaceKind::stl:
        deck.line(4, "file: {}", text(surface.file));
        deck.line(4, "scale: {}", number(surface.scale));
        deck.line(4, "offset: {}", vector_text(surface.offset));
        break;
      case SurfaceKind::plane:
        deck.line(4, "point: {}", vector_text(surface.point));
        deck.line(4, "normal: {}", vector_text(surface.normal));
        deck.line(4, "size: {}", number(surface.size));
        break;
      case SurfaceKind::box:
        deck.line(4, "min: {}", vector_text(surface.min));
        deck.line(4, "max: {}", vector_text(surface.max));
        break;
      case SurfaceKind::cylinder:
        deck.line(4, "base: {}", vector_text(surface.base));
        deck.line(4, "axis: {}", vector_text(surface.axis));
        deck.line(4, "radius: {}", number(surface.radius));
        deck.line(4, "length: {}", number(surface.length));
        deck.line(4, "capped: {}", boolean(surface.capped));
        deck.line(4, "resolution: {}", surface.resolution.value);
        break;
      case SurfaceKind::mesh:
        write_list(deck, "vertices", surface.mesh_vertices, vector_text);
        // An empty element list is left out; the other one carries the mesh.
        if (!surface.mesh_triangles.empty() || surface.mesh_quads.empty())
          write_list(deck, "triangles", surface.mesh_triangles,
                     [](const std::array<std::uint32_t, 3>& corners) {
                       return fmt::format("[{}, {}, {}]", corners[0], corners[1], corners[2]);
                     });
        if (!surface.mesh_quads.empty())
          write_list(deck, "quads", surface.mesh_quads,
                     [](const std::array<std::uint32_t, 4>& corners) {
                       return fmt::format("[{}, {}, {}, {}]", corners[0], corners[1], corners[2],
                                          corners[3]);
                     });
        break;
    }
    deck.line(4, "material: {}", text(surface.material));
    if (surface.motion.kind.value != MotionKind::none)
      deck.line(4, "motion: {}", motion_text(surface.motion));
    deck.line(4, "conveyor_velocity: {}", vector_text(surface.conveyor_velocity));
    deck.line(4, "export: {}", boolean(surface.export_loads));
    deck.line(4, "coupled: {}", boolean(surface.coupled));
  }
}

void write_factories(DeckText& deck, const std::vector<FactorySpec>& factories) {
  list_key(deck, "factories", factories.empty());
  for (const FactorySpec& factory : factories) {
    deck.line(2, "- name: {}", text(factory.name));
    deck.line(4, "particle_type: {}", text(factory.particle_type));
    deck.line(4, "region: {}", region_text(factory.region));
    if (factory.target_count) deck.line(4, "count: {}", factory.target_count->value);
    if (factory.target_mass) deck.line(4, "mass: {}", number(*factory.target_mass));
    if (factory.mass_rate) deck.line(4, "mass_rate: {}", number(*factory.mass_rate));
    deck.line(4, "start_time: {}", number(factory.start_time));
    if (factory.stop_time.value < kNever) deck.line(4, "stop_time: {}", number(factory.stop_time));
    deck.line(4, "velocity: {}", vector_text(factory.initial_velocity));
    deck.line(4, "angular_velocity: {}", vector_text(factory.initial_angular_velocity));
    deck.line(4, "max_attempts: {}", factory.max_attempts.value);
  }
}

void write_monitors(DeckText& deck, const std::vector<MonitorSpec>& monitors) {
  list_key(deck, "monitors", monitors.empty());
  for (const MonitorSpec& monitor : monitors) {
    deck.line(2, "- name: {}", text(monitor.name));
    deck.line(4, "type: {}", spelling(monitor.kind.value));
    switch (monitor.kind.value) {
      case MonitorKind::particle:
        deck.line(4, "id: {}", monitor.particle_id.value);
        break;
      case MonitorKind::mass_flow:
        deck.line(4, "point: {}", vector_text(monitor.point));
        deck.line(4, "normal: {}", vector_text(monitor.normal));
        break;
      case MonitorKind::velocity_profile:
        deck.line(4, "axis: {}", spelling(monitor.axis.value));
        deck.line(4, "bins: {}", monitor.bins.value);
        break;
      case MonitorKind::mass:
      case MonitorKind::stress:
        break;
    }
    if (monitor.region) deck.line(4, "region: {}", region_text(*monitor.region));
  }
}

void write_output(DeckText& deck, const OutputSpec& output) {
  deck.line(0, "output:");
  deck.line(2, "directory: {}", text(output.directory));
  deck.line(2, "interval: {}", number(output.interval));
  deck.line(2, "monitor_interval: {}", number(output.monitor_interval));
  deck.line(2, "checkpoint_interval: {}", number(output.checkpoint_interval));
  deck.line(2, "plots: {}", boolean(output.plots));
  deck.line(2, "progress_interval: {}", number(output.progress_interval));
  deck.line(2, "contacts: {}", boolean(output.contacts));
}

// `supports:` at `indent`: the CalculiX model's, a Gmsh structure's.
void write_supports(DeckText& deck, int indent, const std::vector<SupportSpec>& supports) {
  if (supports.empty()) {
    deck.line(indent, "supports: []");
    return;
  }
  deck.line(indent, "supports:");
  for (const SupportSpec& support : supports)
    if (!support.group.value.empty())
      deck.line(indent + 2, "- {{name: {}, group: {}, fix: {}}}", text(support.name),
                text(support.group), spelling(support.fix));
    else
      deck.line(indent + 2, "- {{name: {}, box: {{min: {}, max: {}}}, fix: {}}}",
                text(support.name), vector_text(support.min), vector_text(support.max),
                spelling(support.fix));
}

void write_calculix(DeckText& deck, const CalculixSpec& calculix) {
  deck.line(2, "calculix:");
  deck.line(4, "thickness: {}", number(calculix.thickness));
  deck.line(4, "youngs_modulus: {}", number(calculix.youngs_modulus));
  deck.line(4, "poisson_ratio: {}", number(calculix.poisson_ratio));
  // 0 is "not given" (a static analysis does without the mass); the key accepts only > 0.
  if (calculix.density.value > 0.0) deck.line(4, "density: {}", number(calculix.density));
  deck.line(4, "analysis: {}", spelling(calculix.analysis));
  if (calculix.static_time) deck.line(4, "time: {}", number(*calculix.static_time));
  write_supports(deck, 4, calculix.supports);
}

void write_export(DeckText& deck, const ExportSpec& fem_export) {
  if (!fem_export.enabled) return;
  deck.line(0, "export:");
  deck.line(2, "interval: {}", number(fem_export.interval));
  deck.line(2, "directory: {}", text(fem_export.directory));
  // No formats key means all formats; an empty list would be an error.
  if (!fem_export.formats.empty()) {
    std::string formats;
    for (const Located<ExportFormat>& format : fem_export.formats)
      formats += (formats.empty() ? "" : ", ") + spelling(format);
    deck.line(2, "formats: [{}]", formats);
  }
  if (fem_export.calculix) write_calculix(deck, *fem_export.calculix);
}

// The structures: entries (deck_structures.cpp). Their coupled surfaces are in `surfaces:` as
// well (added when the run started): a restart takes them as the structures' coupling surfaces
// (fsi::CoupledStructures), their state from the checkpoint's "structures" section.
void write_structures(DeckText& deck, const std::vector<StructureSpec>& structures) {
  if (structures.empty()) return;
  deck.line(0, "structures:");
  for (const StructureSpec& s : structures) {
    deck.line(2, "- name: {}", text(s.name));
    deck.line(4, "model: {}", text(s.model));
    deck.line(4, "material: {}", text(s.material));
    if (s.constraint_set) deck.line(4, "constraint_set: {}", s.constraint_set->value);
    if (s.surface) deck.line(4, "surface: {}", s.surface->value);
    if (s.period) deck.line(4, "period: {}", number(*s.period));
    if (s.filter) deck.line(4, "filter: {}", number(*s.filter));
    deck.line(4, "mass_scaling_time_step: {}", number(s.mass_scaling_time_step));
    deck.line(4, "damping: {}", number(s.damping));
    if (s.drilling) deck.line(4, "drilling: {}", number(*s.drilling));
    if (s.export_loads.value) deck.line(4, "export: true");
    if (!s.mesh) continue;
    const MeshStructureSpec& m = *s.mesh;
    deck.line(4, "units: {}", spelling(m.units));
    deck.line(4, "thickness: {}", number(m.thickness));
    deck.line(4, "youngs_modulus: {}", number(m.youngs_modulus));
    deck.line(4, "poisson_ratio: {}", number(m.poisson_ratio));
    deck.line(4, "density: {}", number(m.density));
    deck.line(4, "yield_stress: {}", number(m.yield_stress));
    deck.line(4, "hardening_modulus: {}", number(m.hardening_modulus));
    deck.line(4, "coupling_group: {}", text(m.coupling_group));
    write_supports(deck, 4, m.supports);
  }
}

// The `particles:` sources (files by their stored absolute path); left out when there are none.
// The particles read from the files are not written: a restart takes them from its checkpoint.
void write_particle_sources(DeckText& deck, const std::vector<ParticleSourceSpec>& sources) {
  if (sources.empty()) return;
  list_key(deck, "particles", false);
  for (const ParticleSourceSpec& source : sources) {
    if (!source.file.value.empty()) {
      deck.line(2, "- file: {}", text(source.file));
    } else {
      deck.line(2, "- type: {}", text(source.type));
      deck.line(4, "position: {}", vector_text(source.position));
      if (source.radius) deck.line(4, "radius: {}", number(*source.radius));
      deck.line(4, "velocity: {}", vector_text(source.velocity));
      deck.line(4, "angular_velocity: {}", vector_text(source.angular_velocity));
    }
    deck.line(4, "allow_overlap: {}", boolean(source.allow_overlap));
  }
}

}  // namespace

std::string write_deck(const SimulationSpec& spec) {
  DeckText deck;
  deck.line(0,
            "# Quarry deck (docs/deck.md) written from a SimulationSpec: the values a run uses,");
  deck.line(0, "# defaults included.");
  write_simulation(deck, spec.simulation);
  write_materials(deck, spec.materials);
  write_interactions(deck, spec.interactions);
  write_particle_types(deck, spec.particle_types);
  write_surfaces(deck, spec.surfaces);
  write_factories(deck, spec.factories);
  write_particle_sources(deck, spec.particle_sources);
  write_monitors(deck, spec.monitors);
  write_output(deck, spec.output);
  write_export(deck, spec.fem_export);
  write_structures(deck, spec.structures);
  std::string text = deck.take();
  if (spec.fluid) text += deck_detail::fluid_section_text(*spec.fluid);
  return text;
}

}  // namespace quarry
