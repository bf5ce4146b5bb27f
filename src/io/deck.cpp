// Deck parser entry points: YAML text → SimulationSpec. Reads every section (deck_settings,
// deck_geometry), then checks what spans sections — names that refer to other entries and
// the material interactions every possible contact needs — and reports all errors at once.
#include "io/deck.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <set>
#include <sstream>

#include "core/periodic_box.h"
#include "insert/size_distribution.h"
#include "io/deck_sections.h"

namespace quarry {

namespace {

using deck_detail::DeckContext;
using deck_detail::MapReader;

const std::vector<std::string> kTopLevelKeys = {"simulation",     "materials", "interactions",
                                                "particle_types", "surfaces",  "factories",
                                                "monitors",       "output",         "particles",
                                                "export",         "structures",     "fluid"};

// Reports a second entry of the same name in one section; empty names were reported already.
void check_unique_names(DeckContext& context, const std::string& noun,
                        const std::vector<const Located<std::string>*>& names) {
  std::map<std::string, const Located<std::string>*> first_of;
  for (const Located<std::string>* name : names) {
    if (name->value.empty()) continue;
    const auto [entry, inserted] = first_of.emplace(name->value, name);
    if (!inserted)
      context.error(name->where, fmt::format("duplicate {} name \"{}\"", noun, name->value),
                    fmt::format("first defined on line {}", entry->second->where.line));
  }
}

template <class Spec>
std::vector<const Located<std::string>*> names_of(const std::vector<Spec>& entries) {
  std::vector<const Located<std::string>*> names;
  for (const Spec& entry : entries) names.push_back(&entry.name);
  return names;
}

template <class Spec>
std::vector<std::string> spellings_of(const std::vector<Spec>& entries) {
  std::vector<std::string> names;
  for (const Spec& entry : entries)
    if (!entry.name.value.empty()) names.push_back(entry.name.value);
  return names;
}

// Reports a reference to a name that no entry of the section defines. An empty reference
// was reported already (missing or malformed key).
bool check_reference(DeckContext& context, const std::string& noun,
                     const Located<std::string>& reference,
                     const std::vector<std::string>& defined) {
  if (reference.value.empty()) return false;
  if (std::find(defined.begin(), defined.end(), reference.value) != defined.end()) return true;
  context.error(reference.where, fmt::format("unknown {} \"{}\"", noun, reference.value),
                defined.empty() ? fmt::format("no {} is defined", noun)
                                : deck_detail::suggestion_hint(reference.value, defined));
  return false;
}

// Unordered pair of material names, so that [ore, steel] and [steel, ore] are one interaction.
std::pair<std::string, std::string> material_pair(const std::string& a, const std::string& b) {
  return a < b ? std::make_pair(a, b) : std::make_pair(b, a);
}

// Every pair of materials that can meet needs an interaction: particle–particle for all
// particle-type materials (each with itself and with the others), particle–surface for every
// particle material with every surface material.
void check_interactions(DeckContext& context, const SimulationSpec& spec,
                        const std::vector<std::string>& material_names) {
  std::map<std::pair<std::string, std::string>, const InteractionSpec*> defined;
  for (const InteractionSpec& interaction : spec.interactions) {
    const bool known_a =
        check_reference(context, "material", interaction.material_a, material_names);
    const bool known_b =
        check_reference(context, "material", interaction.material_b, material_names);
    if (!known_a || !known_b) continue;
    const auto [entry, inserted] = defined.emplace(
        material_pair(interaction.material_a.value, interaction.material_b.value), &interaction);
    if (!inserted)
      context.error(interaction.material_a.where,
                    fmt::format("duplicate interaction for materials \"{}\" and \"{}\"",
                                interaction.material_a.value, interaction.material_b.value),
                    fmt::format("first defined on line {}", entry->second->material_a.where.line));
  }

  std::set<std::pair<std::string, std::string>> reported;
  const auto require_pair = [&](const std::string& a, const std::string& b,
                                const SourceLocation& where, const std::string& why) {
    const auto pair = material_pair(a, b);
    if (defined.count(pair) || !reported.insert(pair).second) return;
    context.error(
        where,
        fmt::format("no interaction defined for materials \"{}\" and \"{}\" ({})", a, b, why),
        fmt::format("add to interactions: - {{materials: [{}, {}], restitution: 0.5, "
                    "static_friction: 0.5, rolling_friction: 0.05}}",
                    pair.first, pair.second));
  };
  // Only references that resolved: an unknown material was reported on its own.
  const auto known = [&](const Located<std::string>& material) {
    return std::find(material_names.begin(), material_names.end(), material.value) !=
           material_names.end();
  };
  for (std::size_t i = 0; i < spec.particle_types.size(); ++i) {
    const ParticleTypeSpec& later = spec.particle_types[i];
    if (!known(later.material)) continue;
    for (std::size_t j = 0; j <= i; ++j) {
      const ParticleTypeSpec& earlier = spec.particle_types[j];
      if (!known(earlier.material)) continue;
      require_pair(earlier.material.value, later.material.value, later.material.where,
                   i == j
                       ? fmt::format("particles of type \"{}\" touch each other", later.name.value)
                       : fmt::format("particle types \"{}\" and \"{}\" touch", earlier.name.value,
                                     later.name.value));
    }
  }
  for (const SurfaceSpec& surface : spec.surfaces) {
    if (!known(surface.material)) continue;
    for (const ParticleTypeSpec& particle_type : spec.particle_types) {
      if (!known(particle_type.material)) continue;
      require_pair(particle_type.material.value, surface.material.value, surface.material.where,
                   fmt::format("particles of type \"{}\" touch surface \"{}\"",
                               particle_type.name.value, surface.name.value));
    }
  }
}

// Periodic axes (issue #20) against what else the deck holds: a period long enough for the
// neighbour search (check_periodic_domain, which the C ABI's settings get too), a fluid grid periodic with the same
// period along it, and mass-flow planes either along a periodic axis or
// perpendicular to it (a tilted plane would meet its own periodic images).
void check_periodic_axes(DeckContext& context, const SimulationSpec& spec) {
  const auto& periodic = spec.simulation.periodic;
  if (!(periodic.value[0] || periodic.value[1] || periodic.value[2])) return;
  const char* const axis_names[3] = {"x", "y", "z"};
  // An empty domain is a missing or malformed one, reported already where it is read.
  if (!spec.simulation.domain.value.empty())
    check_periodic_domain(spec.simulation, spec.particle_types, context.diagnostics);
  // With a fluid grid, each periodic axis of the particles must be a periodic axis of the
  // fluid with the same period: the particle-to-cell kernel (cfdem/cell_kernel.h) wraps a
  // particle on the grid's period, which must be the one its position wraps on.
  if (spec.fluid && !spec.simulation.domain.value.empty()) {
    const FluidSpec& fluid = *spec.fluid;
    const Aabb& domain = spec.simulation.domain.value;
    for (int a = 0; a < 3; ++a) {
      if (!periodic.value[a]) continue;
      const auto face = static_cast<std::size_t>(2 * a);
      if (fluid.faces[face].type.value != FluidBoundaryType::periodic) {
        context.error(periodic.where,
                      fmt::format("the particles are periodic along {} but the fluid is not", axis_names[a]),
                      fmt::format("make the fluid's {0}_min and {0}_max boundaries periodic, or leave {0} "
                                  "out of periodic",
                                  axis_names[a]));
        continue;
      }
      const double period = domain.hi[a] - domain.lo[a];  // m
      const double lo = fluid.origin.value[a];              // m
      const double hi = lo + fluid.cells.value[a] * fluid.cell_size.value;
      const double tolerance = 1e-9 * period;
      if (std::abs(lo - domain.lo[a]) > tolerance || std::abs(hi - domain.hi[a]) > tolerance)
        context.error(fluid.cell_size.where,
                      fmt::format("the fluid grid spans {:.6g} to {:.6g} m along {}, the periodic domain "
                                  "{:.6g} to {:.6g} m",
                                  lo, hi, axis_names[a], domain.lo[a], domain.hi[a]),
                      fmt::format("a periodic axis needs one period for both: grid origin {:.6g} and cells x "
                                  "cell_size = {:.6g} m along {}",
                                  domain.lo[a], period, axis_names[a]));
    }
  }
  for (const MonitorSpec& monitor : spec.monitors) {
    if (monitor.kind.value != MonitorKind::mass_flow) continue;
    const Vec3 normal = monitor.normal.value;
    for (int a = 0; a < 3; ++a) {
      const bool along_axis = normal[(a + 1) % 3] == 0.0 && normal[(a + 2) % 3] == 0.0;
      if (!periodic.value[a] || normal[a] == 0.0 || along_axis) continue;
      context.error(
          monitor.normal.where,
          fmt::format("the plane of mass-flow monitor \"{}\" is tilted across the periodic axis {}",
                      monitor.name.value, axis_names[a]),
          fmt::format("a plane across a periodic axis must be perpendicular to it (normal: [{}]) "
                      "or contain it (a normal with no {} component)",
                      a == 0   ? "1, 0, 0"
                      : a == 1 ? "0, 1, 0"
                               : "0, 0, 1",
                      axis_names[a]));
    }
  }
}

// fluid.blocked surfaces: a name of surfaces:, and a fixed one (blocked cells never move).
void check_blocked_surfaces(DeckContext& context, const SimulationSpec& spec) {
  const std::vector<std::string> surface_names = spellings_of(spec.surfaces);
  for (const FluidBlockedSpec& entry : spec.fluid->blocked) {
    if (entry.kind.value != FluidBlockedKind::surface) continue;
    if (!check_reference(context, "surface", entry.surface, surface_names)) continue;
    for (const SurfaceSpec& surface : spec.surfaces) {
      if (surface.name.value != entry.surface.value) continue;
      if (surface.motion.kind.value == MotionKind::none && !surface.coupled.value) break;
      context.error(entry.surface.where,
                    fmt::format("surface \"{}\" {}, but blocked fluid cells are fixed", surface.name.value,
                                surface.coupled.value ? "is coupled (moved by a partner)" : "has a motion"),
                    fmt::format("block a fixed surface; to keep \"{}\" moving, leave it out of fluid.blocked "
                                "(particles still touch it)",
                                surface.name.value));
      break;
    }
  }
}

// A mass-flow window must reach across its plane, or nothing is ever counted: the plane
// n·(x − p) = 0 meets a convex region iff the region's extent along n spans 0 (for a cylinder,
// its axis segment's ends ± radius × the part of n across the axis).
void check_flow_windows(DeckContext& context, const SimulationSpec& spec) {
  for (const MonitorSpec& monitor : spec.monitors) {
    if (monitor.kind.value != MonitorKind::mass_flow || !monitor.region) continue;
    const double length = norm(monitor.normal.value);
    if (!(length > 0.0)) continue;  // reported where the normal is read
    const Vec3 n = monitor.normal.value / length, p = monitor.point.value;
    const RegionSpec& r = *monitor.region;
    double lo = 0.0, hi = 0.0;  // m, the region's extent along n from the plane
    if (r.kind.value == RegionKind::box) {
      lo = std::numeric_limits<double>::infinity(), hi = -lo;
      for (int corner = 0; corner < 8; ++corner) {
        const Vec3 x{(corner & 1 ? r.max : r.min).value.x, (corner & 2 ? r.max : r.min).value.y,
                     (corner & 4 ? r.max : r.min).value.z};
        lo = std::min(lo, dot(x - p, n));
        hi = std::max(hi, dot(x - p, n));
      }
    } else if (r.kind.value == RegionKind::cylinder && norm(r.axis.value) > 0.0) {
      const Vec3 axis = r.axis.value / norm(r.axis.value);
      const double ends[2] = {dot(r.base.value - p, n), dot(r.base.value + axis * r.length.value - p, n)};
      const double across = r.radius.value * norm(n - axis * dot(n, axis));
      lo = std::min(ends[0], ends[1]) - across;
      hi = std::max(ends[0], ends[1]) + across;
    } else {
      continue;  // a point window is reported where the region is read
    }
    if (lo > 0.0 || hi < 0.0)
      context.error(r.kind.where,
                    fmt::format("the window of mass-flow monitor \"{}\" does not reach its plane (it lies {:.6g} to "
                                "{:.6g} m from it along the normal)",
                                monitor.name.value, lo, hi),
                    "the region is the part of the plane that counts: make it reach across the plane, around the "
                    "opening");
  }
}

void check_cross_references(DeckContext& context, const SimulationSpec& spec) {
  check_unique_names(context, "material", names_of(spec.materials));
  check_unique_names(context, "particle type", names_of(spec.particle_types));
  check_unique_names(context, "surface", names_of(spec.surfaces));
  check_unique_names(context, "factory", names_of(spec.factories));
  check_unique_names(context, "monitor", names_of(spec.monitors));
  if (spec.fluid) check_unique_names(context, "fluid monitor", names_of(spec.fluid->monitors));

  const std::vector<std::string> material_names = spellings_of(spec.materials);
  for (const ParticleTypeSpec& particle_type : spec.particle_types)
    if (check_reference(context, "material", particle_type.material, material_names))
      for (const MaterialSpec& material : spec.materials)
        if (material.name.value == particle_type.material.value && material.rigid.value)
          context.error(particle_type.material.where,
                        fmt::format("particle type \"{}\" has the rigid material \"{}\"", particle_type.name.value,
                                    material.name.value),
                        "rigid: true is for surface materials (an infinitely stiff wall); particles need "
                        "youngs_modulus and poisson_ratio");
  for (const SurfaceSpec& surface : spec.surfaces)
    check_reference(context, "material", surface.material, material_names);
  const std::vector<std::string> particle_type_names = spellings_of(spec.particle_types);
  for (const FactorySpec& factory : spec.factories)
    check_reference(context, "particle type", factory.particle_type, particle_type_names);
  check_interactions(context, spec, material_names);
  if (spec.fluid) check_blocked_surfaces(context, spec);
  // An export: section with no surface to export is a mistake, not a silent no-op.
  if (spec.fem_export.enabled &&
      std::none_of(spec.surfaces.begin(), spec.surfaces.end(),
                   [](const SurfaceSpec& surface) { return surface.export_loads.value; }) &&
      std::none_of(spec.structures.begin(), spec.structures.end(),
                   [](const StructureSpec& structure) { return structure.export_loads.value; }))
    context.error(spec.fem_export.where, "the export: section applies to no surface",
                  "flag the surfaces (or structures) to export with export: true");
}

// Errors in the order of the file (the first line of the output is the first mistake in the
// deck); errors without a line go last, and errors in other files the deck reads (particle
// tables) after the deck's own, each file's in the order found.
Diagnostics in_file_order(const Diagnostics& diagnostics, const std::string& deck_name) {
  std::vector<Diagnostic> items = diagnostics.all();
  const auto line_key = [](const Diagnostic& item) {
    return item.where.line > 0 ? item.where.line : std::numeric_limits<int>::max();
  };
  std::stable_sort(items.begin(), items.end(), [&](const Diagnostic& a, const Diagnostic& b) {
    const bool a_other = a.where.file != deck_name, b_other = b.where.file != deck_name;
    if (a_other || b_other) return !a_other && b_other;
    return std::make_pair(line_key(a), a.where.column) <
           std::make_pair(line_key(b), b.where.column);
  });
  Diagnostics sorted;
  for (Diagnostic& item : items) {
    if (item.severity == Severity::error)
      sorted.error(std::move(item.where), std::move(item.message), std::move(item.hint));
    else
      sorted.warning(std::move(item.where), std::move(item.message), std::move(item.hint));
  }
  return sorted;
}

// The line (1-based) of the `---` that starts the deck's second document: the first `---` line
// after a line with content (a `---` before any content only opens the first document).
int second_document_line(const std::string& text) {
  std::istringstream lines(text);
  std::string line;
  bool content = false;
  for (int number = 1; std::getline(lines, line); ++number) {
    const bool marker = line.rfind("---", 0) == 0 && (line.size() == 3 || line[3] == ' ' || line[3] == '\t' || line[3] == '\r');
    if (marker && content) return number;
    const auto first = line.find_first_not_of(" \t\r");
    if (!marker && first != std::string::npos && line[first] != '#') content = true;
  }
  return 0;
}

SimulationSpec parse_yaml(const std::string& yaml_text, const std::string& display_name,
                          const DeckParseOptions& options) {
  YAML::Node root;
  try {
    const std::vector<YAML::Node> documents = YAML::LoadAll(yaml_text);
    if (documents.size() > 1) {
      // A second `---` starts a second document, which a plain load would drop without a word.
      const int line = second_document_line(yaml_text);
      throw UserError({display_name, line, 1},
                      "a second YAML document starts here: a deck is one document, and "
                      "everything from this line on would be ignored",
                      "remove this '---' line, or the text after it that belongs to another deck");
    }
    if (!documents.empty()) root = documents.front();
  } catch (const YAML::Exception& error) {
    // A syntax error stops the YAML reader; nothing after it can be trusted.
    const SourceLocation where =
        error.mark.is_null()
            ? SourceLocation{display_name, 0, 0}
            : SourceLocation{display_name, error.mark.line + 1, error.mark.column + 1};
    throw UserError(where, "YAML syntax error: " + error.msg,
                    "check the indentation and the brackets on this line and the line above");
  }
  if (root.IsNull())
    throw UserError({display_name, 0, 0}, "the deck is empty",
                    "a deck needs at least the simulation: and materials: sections (docs/deck.md)");

  DeckContext context{display_name, {}};
  SimulationSpec spec;
  spec.deck_path = display_name;
  MapReader top(context, root, root, "the deck");
  if (top.is_map()) {
    top.reject_unknown_keys(kTopLevelKeys);
    deck_detail::read_simulation_section(top, spec.simulation);
    deck_detail::read_materials_section(top, spec.materials);
    deck_detail::read_interactions_section(top, spec.interactions);
    deck_detail::read_particle_types_section(top, spec.particle_types);
    deck_detail::read_surfaces_section(top, options, spec.surfaces);
    deck_detail::read_factories_section(top, spec.factories);
    deck_detail::read_particles_section(top, options, spec);
    deck_detail::read_monitors_section(top, spec.monitors);
    deck_detail::read_output_section(top, spec.output);
    deck_detail::read_export_section(top, spec.fem_export);
    deck_detail::read_structures_section(top, options, spec, spec.structures);
    deck_detail::read_fluid_section(top, options, spec.fluid);
    check_cross_references(context, spec);
    check_periodic_axes(context, spec);
    check_flow_windows(context, spec);
  }
  if (context.diagnostics.has_errors()) throw UserError(in_file_order(context.diagnostics, display_name));
  return spec;
}

}  // namespace

void check_periodic_domain(const SimulationSettings& settings, const std::vector<ParticleTypeSpec>& types,
                           Diagnostics& problems) {
  const auto& periodic = settings.periodic;
  const char* const axis_names[3] = {"x", "y", "z"};
  const Aabb& domain = settings.domain.value;
  // Largest and smallest radius any particle can have (m), as build_world sizes the grid and
  // the default skin; a size distribution with errors of its own is reported already.
  double max_radius = 0.0, min_radius = std::numeric_limits<double>::infinity();
  try {
    for (const ParticleTypeSpec& type : types) {
      const SizeSampler sampler(type.size);
      max_radius = std::max(max_radius, sampler.max_radius());
      min_radius = std::min(min_radius, sampler.min_radius());
    }
  } catch (const UserError&) {
    max_radius = 0.0;
  }
  const double skin = settings.skin.value >= 0.0 ? settings.skin.value : 0.2 * min_radius;  // m
  const double shortest = shortest_period(max_radius, skin);                                // m
  for (int a = 0; a < 3; ++a) {
    if (!periodic.value[a]) continue;
    const double period = domain.hi[a] - domain.lo[a];  // m
    if (!(period > 0.0) || !std::isfinite(period)) {  // NaN and infinite bounds included
      problems.error(periodic.where,
                     fmt::format("{0} is periodic but the domain has no finite extent along {0} "
                                 "(min {1} m, max {2} m): a periodic axis takes its period from "
                                 "the domain",
                                 axis_names[a], domain.lo[a], domain.hi[a]),
                     fmt::format("give the domain max > min along {0}, or leave {0} out of periodic",
                                 axis_names[a]));
      continue;
    }
    if (max_radius <= 0.0 || period >= shortest) continue;
    problems.error(
        periodic.where,
        fmt::format("the period along {} ({:.4g} m) is shorter than the neighbour search needs: "
                    "3 × (2 R_max + skin) = 3 × (2 × {:.4g} + {:.4g}) = {:.4g} m",
                    axis_names[a], period, max_radius, skin, shortest),
        fmt::format("make the domain at least {:.4g} m long along {}, or leave {} out of periodic",
                    shortest, axis_names[a], axis_names[a]));
  }
}

bool usable_in_file_names(const std::string& name) {
  if (name.empty() || name.front() == '.') return false;
  return std::none_of(name.begin(), name.end(), [](char c) {
    const auto byte = static_cast<unsigned char>(c);
    return c == '/' || c == '\\' || byte < 0x20 || byte == 0x7f;
  });
}

SimulationSpec parse_deck(const std::string& path) {
  std::error_code error;
  if (std::filesystem::is_directory(path, error))
    throw UserError({path, 0, 0}, "this is a folder, not a deck file", "give the path of the YAML deck itself");
  if (std::filesystem::exists(path, error) && !std::filesystem::is_regular_file(path, error))
    throw UserError({path, 0, 0}, "this is not a regular file (a device or a pipe), not a deck file",
                    "give the path of the YAML deck itself");
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw UserError({path, 0, 0}, "cannot open the deck file",
                    "check the path; it is relative to the current directory");
  std::ostringstream text;
  text << in.rdbuf();
  DeckParseOptions options;
  options.base_directory = std::filesystem::path(path).parent_path().string();
  return parse_yaml(text.str(), path, options);
}

SimulationSpec parse_deck_string(const std::string& yaml_text, const std::string& display_name) {
  return parse_yaml(yaml_text, display_name, DeckParseOptions{});
}

SimulationSpec parse_deck_string(const std::string& yaml_text, const std::string& display_name,
                                 const DeckParseOptions& options) {
  return parse_yaml(yaml_text, display_name, options);
}

}  // namespace quarry
