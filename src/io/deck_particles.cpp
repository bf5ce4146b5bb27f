// The deck's `particles:` section (issue #20): the particles a run starts from, read from CSV
// tables and earlier frames (io/particle_file_reader.h) or given one by one. The checks that
// need the built world (radius within the type's sizes, inside the domain, overlaps) are made
// when the particles are placed (sim/initial_particles.cpp).
#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <filesystem>

#include "io/deck_sections.h"
#include "io/particle_file_reader.h"

namespace quarry::deck_detail {

namespace {

const std::vector<std::string> kFileKeys = {"file", "allow_overlap"};
const std::vector<std::string> kInlineKeys = {"type",     "position",         "radius",
                                              "velocity", "angular_velocity", "allow_overlap"};

std::string lower_extension(const std::string& path) {
  std::string extension = std::filesystem::path(path).extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return extension;
}

// Resolves `file` against the deck's folder (stored absolute) and reads its particles.
void read_particle_file(MapReader& map, const DeckParseOptions& options,
                        const std::vector<std::string>& type_names, std::uint32_t source,
                        ParticleSourceSpec& entry, std::vector<InitialParticle>& particles) {
  if (!map.read("file", entry.file, Presence::required)) return;
  namespace fs = std::filesystem;
  DeckContext& context = map.context();
  const std::string extension = lower_extension(entry.file.value);
  if (extension != ".csv" && extension != ".vtu") {
    context.error(
        entry.file.where,
        fmt::format("particle file \"{}\" is neither .csv nor .vtu", entry.file.value),
        "a CSV table (x,y,z,radius,type,…) or a particles_NNNNNN.vtu frame of an earlier run");
    return;
  }
  fs::path path(entry.file.value);
  if (path.is_relative()) path = fs::path(options.base_directory) / path;
  std::error_code ignored;
  const fs::path resolved = fs::absolute(path, ignored).lexically_normal();
  entry.file.value = resolved.string();
  // A restart reads the particles from its checkpoint, not from the file.
  if (!options.require_files) return;
  if (!fs::is_regular_file(resolved, ignored)) {
    context.error(
        entry.file.where,
        fmt::format("particle file \"{}\" {}", path.filename().string(),
                    fs::is_directory(resolved, ignored) ? "is a folder, not a file" : "not found"),
        fmt::format("looked for \"{}\"; relative paths start at the deck's folder",
                    resolved.string()));
    return;
  }
  std::vector<InitialParticle> read =
      extension == ".csv"
          ? read_particle_csv(entry.file.value, type_names, source, context.diagnostics)
          : read_particle_vtu(entry.file.value, type_names, source, context.diagnostics);
  particles.insert(particles.end(), read.begin(), read.end());
}

void read_inline_particle(MapReader& map, const std::vector<std::string>& type_names,
                          std::uint32_t source, ParticleSourceSpec& entry,
                          std::vector<InitialParticle>& particles) {
  DeckContext& context = map.context();
  InitialParticle particle;
  particle.source = source;
  bool valid = map.read("type", entry.type, Presence::required);
  if (valid) {
    const auto found = std::find(type_names.begin(), type_names.end(), entry.type.value);
    if (found == type_names.end()) {
      context.error(entry.type.where, fmt::format("unknown particle type \"{}\"", entry.type.value),
                    type_names.empty() ? std::string("no particle type is defined")
                                       : suggestion_hint(entry.type.value, type_names));
      valid = false;
    } else {
      particle.type = static_cast<std::uint16_t>(found - type_names.begin());
    }
  }
  valid &= map.read("position", entry.position, Presence::required);
  Located<double> radius;
  if (map.has("radius")) {
    if (map.read("radius", radius, positive(), "m"))
      entry.radius = radius;
    else
      valid = false;
  }
  map.read("velocity", entry.velocity);
  map.read("angular_velocity", entry.angular_velocity);
  if (!valid) return;
  particle.position = entry.position.value;
  particle.velocity = entry.velocity.value;
  particle.angular_velocity = entry.angular_velocity.value;
  particle.radius = entry.radius ? entry.radius->value : 0.0;
  particles.push_back(particle);
}

}  // namespace

void read_particles_section(MapReader& root, const DeckParseOptions& options,
                            SimulationSpec& spec) {
  std::vector<std::string> type_names;
  for (const ParticleTypeSpec& type : spec.particle_types) type_names.push_back(type.name.value);
  for (MapReader& map : list_of_maps(root, "particles", "particles entry")) {
    ParticleSourceSpec entry;
    entry.where = map.location();
    const auto source = static_cast<std::uint32_t>(spec.particle_sources.size());
    const bool from_file = map.has("file");
    if (from_file) {
      map.reject_unknown_keys(kFileKeys, kInlineKeys, "a particles entry with file:");
      // An entry that mixes both kinds is reported above; its file is not read.
      const bool mixed = std::any_of(
          kInlineKeys.begin(), kInlineKeys.end(),
          [&](const std::string& key) { return key != "allow_overlap" && map.has(key); });
      if (!mixed)
        read_particle_file(map, options, type_names, source, entry, spec.initial_particles);
    } else {
      map.reject_unknown_keys(kInlineKeys);
      if (map.is_map() && !map.has("type") && !map.has("position"))
        map.context().error(
            map.location(), "a particles entry needs file: or type: and position:",
            "- {file: settled.csv} (or a .vtu frame), or - {type: NAME, position: [x, y, z]}");
      else
        read_inline_particle(map, type_names, source, entry, spec.initial_particles);
    }
    map.read("allow_overlap", entry.allow_overlap);
    spec.particle_sources.push_back(std::move(entry));
  }
}

}  // namespace quarry::deck_detail
