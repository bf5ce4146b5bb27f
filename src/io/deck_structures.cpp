// The deck's `structures:` section (issue #17 §5): shell models coupled two-way to the
// particles, each naming its bulk-data file and what the file does not say. Reference:
// docs/fem.md, "Coupling"; the model itself is read when the run starts (fsi).
#include <filesystem>
#include <set>

#include <fmt/format.h>

#include "io/deck_enums.h"
#include "io/deck_sections.h"

namespace quarry::deck_detail {

namespace {

// Keys of every entry; those that pick among bulk data's cards; what a Gmsh mesh's entry gives
// in place of the bulk data's cards (MeshStructureSpec).
const std::vector<std::string> kCommonKeys = {"name",   "model",   "material",
                                              "period", "filter",  "mass_scaling_time_step",
                                              "damping", "drilling", "export"};
const std::vector<std::string> kBulkDataKeys = {"constraint_set", "surface"};
const std::vector<std::string> kMeshKeys = {"units",         "thickness", "youngs_modulus",
                                            "poisson_ratio", "density",   "yield_stress",
                                            "hardening_modulus", "coupling_group", "supports"};

std::vector<std::string> structure_keys() {
  std::vector<std::string> keys = kCommonKeys;
  keys.insert(keys.end(), kBulkDataKeys.begin(), kBulkDataKeys.end());
  keys.insert(keys.end(), kMeshKeys.begin(), kMeshKeys.end());
  return keys;
}

bool is_gmsh_path(const std::string& path) {
  return std::filesystem::path(path).extension() == ".msh";
}

// A Gmsh mesh's section, material, supports and coupling group (MeshStructureSpec), in SI.
MeshStructureSpec read_mesh_structure(MapReader& map) {
  MeshStructureSpec mesh;
  map.read("units", mesh.units, kMeshLengthUnits, Presence::required);
  map.read("thickness", mesh.thickness, positive(), "m", Presence::required);
  map.read("youngs_modulus", mesh.youngs_modulus, positive(), "Pa", Presence::required);
  map.read("poisson_ratio", mesh.poisson_ratio, interval(0.0, true, 0.5, false), "1");
  map.read("density", mesh.density, positive(), "kg/m³", Presence::required);
  map.read("yield_stress", mesh.yield_stress, non_negative(), "Pa");
  map.read("hardening_modulus", mesh.hardening_modulus, non_negative(), "Pa");
  map.read("coupling_group", mesh.coupling_group, Presence::required);
  for (MapReader& support_map : list_of_maps(map, "supports", "support"))
    mesh.supports.push_back(read_support(support_map, true));
  return mesh;
}

// The model path against the deck's folder, stored absolute; it must exist when files are
// required (as STL files are).
void read_model_path(MapReader& map, const DeckParseOptions& options, Located<std::string>& model) {
  if (!map.read("model", model, Presence::required)) return;
  namespace fs = std::filesystem;
  fs::path path(model.value);
  if (path.is_relative()) path = fs::path(options.base_directory) / path;
  std::error_code ignored;
  const fs::path resolved = fs::absolute(path, ignored).lexically_normal();
  if (options.require_files && !fs::is_regular_file(resolved, ignored)) {
    map.context().error(model.where, fmt::format("structure model \"{}\" not found", model.value),
                        fmt::format("looked for \"{}\"; relative paths start at the deck's folder",
                                    resolved.string()));
    return;
  }
  model.value = resolved.string();
}

}  // namespace

void read_structures_section(MapReader& root, const DeckParseOptions& options, const SimulationSpec& spec,
                             std::vector<StructureSpec>& structures) {
  if (!root.has("structures")) return;
  std::vector<std::string> materials;
  for (const MaterialSpec& m : spec.materials) materials.push_back(m.name.value);
  std::set<std::string> taken, coupled_meshes;  // surface and structure names
  for (const SurfaceSpec& s : spec.surfaces) {
    taken.insert(s.name.value);
    if (s.coupled.value && s.kind.value == SurfaceKind::mesh) coupled_meshes.insert(s.name.value);
  }

  for (MapReader& map : list_of_maps(root, "structures", "structure")) {
    if (!map.is_map()) continue;
    map.reject_unknown_keys(structure_keys());
    StructureSpec structure;
    structure.where = map.location();
    DeckContext& context = map.context();
    // A coupled mesh surface of the structure's name is its coupling surface as a checkpoint's
    // deck lists it (added when the run started): fsi::CoupledStructures takes it on a restored
    // world and refuses it in a new run.
    if (map.read("name", structure.name, Presence::required) && coupled_meshes.contains(structure.name.value))
      coupled_meshes.erase(structure.name.value);
    else if (!structure.name.value.empty() && !taken.insert(structure.name.value).second)
      context.error(structure.name.where,
                    fmt::format("the name \"{}\" is taken by another surface or structure", structure.name.value),
                    "the structure's coupling surface is a surface of the world: give it a name of its own");
    read_model_path(map, options, structure.model);
    // A Gmsh mesh needs its section, material, supports and coupling group from here; bulk
    // data has cards for them, and the keys that pick among its cards mean nothing for a mesh.
    const bool gmsh = is_gmsh_path(structure.model.value);
    for (const std::string& key : gmsh ? kBulkDataKeys : kMeshKeys)
      if (const YAML::Node* key_node = map.find_key(key))
        context.error(context.where(*key_node),
                      fmt::format("`{}` applies to a {} model; \"{}\" is {}", key,
                                  gmsh ? "bulk data" : "Gmsh (.msh)",
                                  std::filesystem::path(structure.model.value).filename().string(),
                                  gmsh ? "a Gmsh mesh" : "bulk data"),
                      gmsh ? "a Gmsh mesh names its coupling surface by `coupling_group` and its "
                             "supports by `supports` (physical groups or boxes)"
                           : "the bulk data's cards give it (PSHELL, MAT1, MATS1, SPC, the EDEM "
                             "card's COUPLING surface)");
    if (gmsh) structure.mesh = read_mesh_structure(map);
    if (map.read("material", structure.material, Presence::required) &&
        std::find(materials.begin(), materials.end(), structure.material.value) == materials.end())
      context.error(structure.material.where, fmt::format("unknown material \"{}\"", structure.material.value),
                    suggestion_hint(structure.material.value, materials));
    Located<int> integer;
    if (map.read("constraint_set", integer, positive())) structure.constraint_set = integer;
    if (map.read("surface", integer, positive())) structure.surface = integer;
    Located<double> time;
    if (map.read("period", time, positive(), "s")) {
      structure.period = time;
      const double end = spec.simulation.end_time.value;
      if (end > 0.0 && !(time.value < end))
        context.error(time.where, fmt::format("period {} s is not below the end time {} s", time.value, end),
                      "the EDEM card's PERIOD is the time between synchronisations, 0 < PERIOD < TTERM");
    }
    if (map.read("filter", time, positive(), "s")) {
      structure.filter = time;
      if (structure.period && !(time.value > structure.period->value))
        context.error(time.where,
                      fmt::format("filter {} s must exceed period {} s", time.value, structure.period->value),
                      "FILTER > PERIOD (seed 000); leave it out to filter over one period");
    }
    map.read("mass_scaling_time_step", structure.mass_scaling_time_step, non_negative(), "s");
    map.read("damping", structure.damping, non_negative(), "1/s");
    // Above 1 the drilling mode of a lone square element can outrun the stable step (docs/fem.md).
    Located<double> alpha;
    if (map.read("drilling", alpha, interval(0.0, true, 1.0, true), "1")) structure.drilling = alpha;
    map.read("export", structure.export_loads);
    structures.push_back(std::move(structure));
  }
}

}  // namespace quarry::deck_detail
