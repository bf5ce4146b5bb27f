// StructureModel → fem::ShellModel and the coupling surface's DEM mesh (structure_adapter.h).
#include "fsi/structure_adapter.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include <fmt/format.h>

#include "core/structure_model.h"
#include "io/bulk_data.h"
#include "io/gmsh_reader.h"

namespace quarry::fsi {

namespace {

// The solver's material for MAT1 (+ MATS1): one material per section, so PSHELL's MID1, MID2
// and MID3 must name the same card (the bending and shear materials are the membrane's).
fem::ShellMaterial shell_material(const IsotropicMaterial& m) {
  fem::ShellMaterial out;
  out.youngs_modulus = m.youngs_modulus;
  out.poisson_ratio = m.poisson_ratio;
  out.density = m.density;
  if (m.plasticity) {
    out.yield_stress = m.plasticity->initial_yield_stress;
    out.hardening_modulus = m.plasticity->hardening_modulus;
  }
  return out;
}

// A degenerate or non-convex element, reported at its card (the solver's own check,
// fem::element_shape, would otherwise stop the run with the element's index alone).
void report_shape(const StructureModel& structure, const ShellElement& card,
                  const fem::ShellModel& model, const fem::ShellElement& element,
                  Diagnostics& errors) {
  std::array<Vec3, 4> x{};
  for (std::size_t k = 0; k < static_cast<std::size_t>(element.node_count); ++k)
    x[k] = model.nodes[static_cast<std::size_t>(element.nodes[k])];
  const fem::ElementShape shape = fem::element_shape(x, element.node_count);
  const char* kind = card.shape == ShellShape::quad4 ? "quadrilateral" : "triangle";
  if (shape.kind == fem::ElementShape::degenerate)
    errors.error(structure.where(card.where),
                 fmt::format("shell element {} ({}) is degenerate: area {:.3g} m² for a longest "
                             "edge of {:.3g} m",
                             card.id, kind, shape.area, shape.longest_edge),
                 "its grid points coincide or lie on one line: check their coordinates and the "
                 "element's list of grid points");
  else if (shape.kind == fem::ElementShape::not_convex)
    errors.error(structure.where(card.where),
                 fmt::format("shell element {} ({}) is not convex at grid {} (a bow-tie or a "
                             "re-entrant corner)",
                             card.id, kind, card.nodes[static_cast<std::size_t>(shape.corner)]),
                 "list the grid points in order around the element, and check their "
                 "coordinates");
}

}  // namespace

AdaptedStructure adapt_structure(const StructureModel& structure, const AdapterOptions& options) {
  Diagnostics errors;
  AdaptedStructure out;
  fem::ShellModel& model = out.model;

  // Nodes in ascending GRID id (the map's order): deterministic, independent of card order.
  std::map<int, std::int32_t> node_of_grid;
  for (const auto& [id, grid] : structure.nodes) {
    node_of_grid[id] = static_cast<std::int32_t>(model.nodes.size());
    model.nodes.push_back(grid.position);
    out.grid_id.push_back(id);
  }

  // One section per PSHELL used, one material per MAT1 used, in first-use order.
  std::map<int, int> section_of_property, material_of_card;
  for (const ShellElement& e : structure.shells) {
    if (e.property_id == 0) {
      errors.error(structure.where(e.where),
                   fmt::format("shell element {} has no property (thickness and material)", e.id),
                   "give it a PSHELL, or the deck's structures: thickness and material");
      continue;
    }
    auto found = section_of_property.find(e.property_id);
    if (found == section_of_property.end()) {
      const ShellProperty& p = structure.properties.at(e.property_id);
      const SourceLocation at = structure.where(p.where);
      if (!p.bending_material_id)
        errors.error(at, fmt::format("PSHELL {} has no MID2: a membrane, which the shell solver does not model", p.id),
                     "set MID2 to the membrane material");
      else if (*p.bending_material_id != p.membrane_material_id ||
               (p.shear_material_id && *p.shear_material_id != p.membrane_material_id))
        errors.error(at, fmt::format("PSHELL {} names different materials for membrane, bending and shear", p.id),
                     "the shell solver takes one isotropic material per section: use MID1 for all three");
      if (std::abs(p.bending_inertia_ratio - 1.0) > 1e-9)
        errors.error(at, fmt::format("PSHELL {} has 12I/T³ = {} (only 1, a solid section, is modelled)", p.id,
                                     p.bending_inertia_ratio));
      if (p.nonstructural_mass != 0.0)
        errors.error(at, fmt::format("PSHELL {} has a non-structural mass NSM = {} kg/m², which the solver does not add",
                                     p.id, p.nonstructural_mass),
                     "raise the material's density by NSM / T instead");
      auto material = material_of_card.find(p.membrane_material_id);
      if (material == material_of_card.end()) {
        const IsotropicMaterial& m = structure.materials.at(p.membrane_material_id);
        if (!(m.density > 0.0))
          errors.error(structure.where(m.where), fmt::format("MAT1 {} has no density (RHO): explicit dynamics needs mass", m.id));
        material = material_of_card.emplace(m.id, static_cast<int>(model.materials.size())).first;
        model.materials.push_back(shell_material(m));
      }
      fem::ShellSection section;
      section.thickness = p.thickness;
      section.integration_points = options.integration_points;
      section.material = material->second;
      found = section_of_property.emplace(p.id, static_cast<int>(model.sections.size())).first;
      model.sections.push_back(section);
    }
    fem::ShellElement element;
    element.node_count = e.node_count();
    for (int k = 0; k < element.node_count; ++k) element.nodes[static_cast<std::size_t>(k)] = node_of_grid.at(e.nodes[static_cast<std::size_t>(k)]);
    element.section = found->second;
    report_shape(structure, e, model, element, errors);
    model.elements.push_back(element);
    out.element_id.push_back(e.id);
  }

  // Constraints: the permanent ones of the GRIDs, then the selected SPC set. Nastran numbers
  // DOFs 1–6 as bits 0–5, the solver's dof:: bits are the same (ux … rz).
  for (const auto& [id, grid] : structure.nodes) {
    if (grid.permanent_constraints.empty()) continue;
    fem::BoundaryCondition bc;
    bc.nodes = {node_of_grid.at(id)};
    bc.dofs = grid.permanent_constraints.mask;
    model.boundary_conditions.push_back(bc);
  }
  std::set<int> set_ids;
  for (const SinglePointConstraint& c : structure.constraints) set_ids.insert(c.set_id);
  std::optional<int> chosen = options.constraint_set;
  if (!chosen && set_ids.size() == 1) chosen = *set_ids.begin();
  if (!chosen && set_ids.size() > 1)
    errors.error(structure.where(structure.constraints.front().where),
                 fmt::format("the model has {} SPC sets; which one applies is not said", set_ids.size()),
                 "name it in the deck's structures: constraint_set");
  if (chosen && !set_ids.empty() && !set_ids.contains(*chosen))
    errors.error({}, fmt::format("constraint set {} is not in the model (its SPC/SPC1 sets: {})", *chosen,
                                 fmt::join(set_ids, ", ")));
  for (const SinglePointConstraint& c : structure.constraints) {
    if (!chosen || c.set_id != *chosen) continue;
    fem::BoundaryCondition bc;
    for (int grid : c.nodes) bc.nodes.push_back(node_of_grid.at(grid));
    bc.dofs = c.dofs.mask;
    model.boundary_conditions.push_back(bc);
  }

  if (errors.has_errors()) throw UserError(std::move(errors));
  return out;
}

CouplingMesh coupling_mesh(const StructureModel& structure, const AdaptedStructure& adapted,
                           const std::vector<int>& surface_ids) {
  std::map<int, std::size_t> element_of_id;
  for (std::size_t e = 0; e < adapted.element_id.size(); ++e) element_of_id[adapted.element_id[e]] = e;

  // Vertices: the surfaces' nodes in ascending solver index.
  std::vector<std::size_t> elements;
  std::set<std::size_t> taken;
  std::set<std::int32_t> nodes;
  for (int surface_id : surface_ids) {
    const auto surface = structure.surfaces.find(surface_id);
    if (surface == structure.surfaces.end())
      throw UserError({}, fmt::format("coupling surface SURF {} is not in the model", surface_id));
    for (int id : surface->second.elements) {
      const std::size_t e = element_of_id.at(id);
      if (!taken.insert(e).second) continue;  // in an earlier SURF too: one shell, one contact face
      elements.push_back(e);
      const fem::ShellElement& element = adapted.model.elements[e];
      for (int k = 0; k < element.node_count; ++k) nodes.insert(element.nodes[static_cast<std::size_t>(k)]);
    }
  }
  CouplingMesh mesh;
  std::map<std::int32_t, std::uint32_t> vertex_of_node;
  for (std::int32_t n : nodes) {
    vertex_of_node[n] = static_cast<std::uint32_t>(mesh.node_of_vertex.size());
    mesh.node_of_vertex.push_back(n);
    mesh.vertices.push_back(adapted.model.nodes[static_cast<std::size_t>(n)]);
  }
  for (std::size_t e : elements) {
    const fem::ShellElement& element = adapted.model.elements[e];
    if (element.node_count == 3)
      mesh.triangles.push_back({vertex_of_node.at(element.nodes[0]), vertex_of_node.at(element.nodes[1]),
                                vertex_of_node.at(element.nodes[2])});
    else
      mesh.quads.push_back({vertex_of_node.at(element.nodes[0]), vertex_of_node.at(element.nodes[1]),
                            vertex_of_node.at(element.nodes[2]), vertex_of_node.at(element.nodes[3])});
  }
  return mesh;
}

SurfaceSpec coupling_surface_spec(const CouplingMesh& mesh, const std::string& name,
                                  const std::string& material) {
  SurfaceSpec s;
  s.name = name;
  s.kind = SurfaceKind::mesh;
  s.mesh_vertices = mesh.vertices;
  s.mesh_triangles = mesh.triangles;
  s.mesh_quads = mesh.quads;
  s.material = material;
  s.coupled = true;
  return s;
}

CoupledStructure prepare_coupling(const StructureModel& structure, const AdapterOptions& options,
                                  std::optional<int> surface_id) {
  if (structure.couplings.empty() || structure.couplings.front().surfaces.empty())
    throw UserError({structure.source_files.empty() ? std::string() : structure.source_files.front(), 0, 0},
                    "the model has no EDEM card with a COUPLING surface",
                    "add `EDEM,<id>,CONTROL,<PERIOD>,<FILTER>,COUPLING,SURF,<surf id>,<label>`");
  const EdemCoupling& edem = structure.couplings.front();
  CoupledStructure out;
  for (const CouplingSurfaceRef& ref : edem.surfaces) {
    if (surface_id && ref.surface_id != *surface_id) continue;
    out.surface_ids.push_back(ref.surface_id);
    out.labels.push_back(ref.label ? *ref.label : default_coupling_label(edem.id, ref.surface_id));
  }
  if (surface_id && out.surface_ids.empty()) {  // a SURF of the model the card does not name
    out.surface_ids.push_back(*surface_id);
    out.labels.push_back(default_coupling_label(edem.id, *surface_id));
  }
  out.adapted = adapt_structure(structure, options);
  out.mesh = coupling_mesh(structure, out.adapted, out.surface_ids);
  out.period = edem.period;
  out.filter = edem.filter;
  return out;
}

StructureModel mesh_structure(const std::string& path, const MeshStructureSpec& spec) {
  GmshReadOptions read;
  read.units = spec.units.value == MeshLengthUnit::millimetre ? UnitSystem::mm_tonne_second
                                                               : UnitSystem::si;
  StructureModel model = read_gmsh(path, read);

  constexpr int kId = 1;  // of the one section, material and constraint set
  ShellProperty section;
  section.id = kId;
  section.thickness = spec.thickness.value;
  section.membrane_material_id = kId;
  section.bending_material_id = kId;
  section.shear_material_id = kId;
  section.fiber_bottom = -0.5 * section.thickness;
  section.fiber_top = 0.5 * section.thickness;
  model.properties[kId] = section;
  IsotropicMaterial material;
  material.id = kId;
  material.youngs_modulus = spec.youngs_modulus.value;
  material.poisson_ratio = spec.poisson_ratio.value;
  material.shear_modulus = material.youngs_modulus / (2.0 * (1.0 + material.poisson_ratio));
  material.density = spec.density.value;
  if (spec.yield_stress.value > 0.0)
    material.plasticity = J2Plasticity{spec.yield_stress.value, spec.hardening_modulus.value, {}};
  model.materials[kId] = material;
  for (ShellElement& element : model.shells) element.property_id = kId;

  const IdSet* group = nullptr;
  std::vector<std::string> names;
  for (const auto& [id, set] : model.sets) {
    if (set.kind != SetKind::element) continue;
    names.push_back(fmt::format("\"{}\"", set.name));
    if (set.name == spec.coupling_group.value) group = &set;
  }
  if (!group)
    throw UserError(spec.coupling_group.where,
                    fmt::format("the mesh \"{}\" has no physical surface group \"{}\"", path,
                                spec.coupling_group.value),
                    names.empty() ? "give the coupled surfaces a physical group in Gmsh "
                                    "(Physical Surface(\"name\") = {...})"
                                  : fmt::format("its surface groups: {}", fmt::join(names, ", ")));
  model.surfaces[group->id] = Surface{group->id, group->members, group->where};
  EdemCoupling coupling;
  coupling.surfaces.push_back({group->id, group->name, group->where});
  model.couplings.push_back(coupling);

  for (const SupportSpec& support : spec.supports) {
    SinglePointConstraint constraint;
    constraint.set_id = kId;
    constraint.dofs = support.fix.value == SupportFixity::clamped ? DofSet::all() : DofSet{0x07};
    if (!support.group.value.empty()) {
      const auto named = std::find_if(model.node_groups.begin(), model.node_groups.end(),
                                      [&](const IdSet& g) { return g.name == support.group.value; });
      if (named == model.node_groups.end()) {
        std::vector<std::string> groups;
        for (const IdSet& g : model.node_groups) groups.push_back(fmt::format("\"{}\"", g.name));
        throw UserError(support.group.where,
                        fmt::format("the mesh \"{}\" has no physical group of points or curves "
                                    "named \"{}\"",
                                    path, support.group.value),
                        groups.empty() ? std::string("give the supported edges or points a "
                                                     "physical group in Gmsh, or use a box")
                                       : fmt::format("its groups of points and curves: {}",
                                                     fmt::join(groups, ", ")));
      }
      constraint.nodes = named->members;
    } else {
      const Aabb box{support.min.value, support.max.value};  // m, inclusive
      for (const auto& [id, grid] : model.nodes)
        if (box.contains(grid.position)) constraint.nodes.push_back(id);
    }
    if (constraint.nodes.empty())
      throw UserError(support.name.where,
                      fmt::format("support \"{}\" holds no node of the mesh \"{}\"",
                                  support.name.value, path),
                      support.group.value.empty()
                          ? "its box is in m, inclusive, and the mesh's coordinates are converted "
                            "from its `units` first: widen the box to take the supported nodes"
                          : "its physical group has no elements of points or curves in the mesh");
    model.constraints.push_back(std::move(constraint));
  }
  return model;
}

CoupledStructure read_coupled_mesh(const std::string& path, const MeshStructureSpec& spec,
                                   const AdapterOptions& options) {
  return prepare_coupling(mesh_structure(path, spec), options);
}

CoupledStructure read_coupled_structure(const std::string& path, const AdapterOptions& options,
                                        std::optional<int> surface_id) {
  return prepare_coupling(read_bulk_data(path), options, surface_id);
}

CoupledStructure coupled_structure_from_text(const std::string& text, const std::string& display_name,
                                             const AdapterOptions& options) {
  return prepare_coupling(read_bulk_data_string(text, display_name), options);
}

}  // namespace quarry::fsi
