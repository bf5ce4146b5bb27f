// MED writer and reader for exported surface loads (med_file.h), after the MED-fichier 4 API
// reference (Salome, "MED fichier" user guide): mesh = MEDmeshCr + node coordinates + nodal
// connectivity; each field = MEDfieldCr once + MEDfieldValueWr per computing step.
#include "export/med_file.h"

#include <hdf5.h>
#include <med.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <map>
#include <stdexcept>

namespace quarry::fem_export {

namespace {

[[noreturn]] void fail(const std::string& path, const std::string& what) {
  throw std::runtime_error("MED file " + path + ": " + what);
}

void check(med_err status, const std::string& path, const std::string& what) {
  if (status < 0) fail(path, what + " failed");
}

// MED short names (components, units) are blank-padded fields of MED_SNAME_SIZE characters.
std::string short_names(std::initializer_list<const char*> names) {
  std::string packed;
  for (const char* name : names) {
    std::string field(name);
    field.resize(MED_SNAME_SIZE, ' ');
    packed += field;
  }
  return packed;
}

std::string trimmed(const char* text, std::size_t length) {
  std::string s(text, strnlen(text, length));
  while (!s.empty() && s.back() == ' ') s.pop_back();
  return s;
}

struct FieldLayout {
  const char* name;
  med_entity_type entity;
  med_geometry_type geometry;
  int components;
  const char* unit;
};

// Component names are code_aster's (NOM_CMP_IDEM='OUI' in LIRE_CHAMP maps them one to one):
// PRES of the PRES_R quantity for the pressure, FX FY FZ of FORC_R for forces and tractions.
constexpr FieldLayout kFields[] = {
    {kMedPressureField, MED_CELL, MED_TRIA3, 1, "Pa"},
    {kMedShearField, MED_CELL, MED_TRIA3, 3, "Pa"},
    {kMedForceField, MED_CELL, MED_TRIA3, 3, "N"},
    {kMedNodalForceField, MED_NODE, MED_NONE, 3, "N"},
};

// A moving surface's displacement, m: code_aster's DX DY DZ.
constexpr FieldLayout kDisplacementLayout = {kMedDisplacementField, MED_NODE, MED_NONE, 3, "m"};

// Blank-separated MED component names of `field`.
std::string component_names(const FieldLayout& field) {
  if (field.components == 1) return short_names({kMedPressureComponent});
  const char* const* names =
      std::strcmp(field.name, kMedDisplacementField) == 0 ? kMedDisplacementComponents : kMedForceComponents;
  return short_names({names[0], names[1], names[2]});
}

void create_field(med_idt file, const std::string& path, const std::string& mesh_name, const FieldLayout& field) {
  const std::string names = component_names(field);
  const std::string units =
      field.components == 1 ? short_names({field.unit}) : short_names({field.unit, field.unit, field.unit});
  check(MEDfieldCr(file, field.name, MED_FLOAT64, field.components, names.c_str(), units.c_str(), "s",
                   mesh_name.c_str()),
        path, std::string("MEDfieldCr ") + field.name);
}

std::vector<double> flatten(std::span<const Vec3> values) {
  std::vector<double> flat(3 * values.size());
  for (std::size_t i = 0; i < values.size(); ++i) {
    flat[3 * i] = values[i].x;
    flat[3 * i + 1] = values[i].y;
    flat[3 * i + 2] = values[i].z;
  }
  return flat;
}

std::vector<Vec3> unflatten(const std::vector<double>& flat) {
  std::vector<Vec3> values(flat.size() / 3);
  for (std::size_t i = 0; i < values.size(); ++i)
    values[i] = {flat[3 * i], flat[3 * i + 1], flat[3 * i + 2]};
  return values;
}

// Node groups as MED families: family 0 ("FAMILLE_ZERO", required) holds nodes in no group;
// each distinct set of groups a node belongs to gets its own positive family number (MED
// numbers node families > 0 and element families < 0), named after its groups.
void write_node_groups(med_idt file, const std::string& path, const std::string& mesh_name,
                       std::size_t node_count, std::span<const MedNodeGroup> groups) {
  check(MEDfamilyCr(file, mesh_name.c_str(), "FAMILLE_ZERO", 0, 0, ""), path, "MEDfamilyCr 0");
  if (groups.empty()) return;
  std::vector<std::vector<std::size_t>> membership(node_count);  // group indices per node
  for (std::size_t g = 0; g < groups.size(); ++g)
    for (std::uint32_t v : groups[g].nodes)
      if (v < node_count) membership[v].push_back(g);
  std::map<std::vector<std::size_t>, med_int> family_of;  // deterministic: ordered by group set
  for (const auto& m : membership)
    if (!m.empty()) family_of.emplace(m, 0);
  med_int next = 1;
  for (auto& [members, number] : family_of) {
    number = next++;
    std::string names(members.size() * MED_LNAME_SIZE, '\0');
    std::string family_name = "F";
    for (std::size_t k = 0; k < members.size(); ++k) {
      const std::string& group = groups[members[k]].name;
      std::copy_n(group.begin(), std::min<std::size_t>(group.size(), MED_LNAME_SIZE),
                  names.begin() + k * MED_LNAME_SIZE);
      family_name += "_" + group;
    }
    family_name.resize(std::min<std::size_t>(family_name.size(), MED_NAME_SIZE));
    check(MEDfamilyCr(file, mesh_name.c_str(), family_name.c_str(), number,
                      static_cast<med_int>(members.size()), names.c_str()),
          path, "MEDfamilyCr " + family_name);
  }
  std::vector<med_int> numbers(node_count, 0);
  for (std::size_t v = 0; v < node_count; ++v)
    if (!membership[v].empty()) numbers[v] = family_of.at(membership[v]);
  check(MEDmeshEntityFamilyNumberWr(file, mesh_name.c_str(), MED_NO_DT, MED_NO_IT, MED_NODE,
                                    MED_NONE, static_cast<med_int>(node_count), numbers.data()),
        path, "MEDmeshEntityFamilyNumberWr");
}

}  // namespace

MedLoadWriter::MedLoadWriter(const std::string& path, const std::string& mesh_name,
                             std::span<const Vec3> nodes,
                             std::span<const std::array<std::uint32_t, 3>> triangles, bool resume,
                             std::span<const MedNodeGroup> groups, bool displacement)
    : path_(path), mesh_name_(mesh_name.substr(0, MED_NAME_SIZE)),
      node_count_(nodes.size()), element_count_(triangles.size()), displacement_(displacement) {
  std::error_code ignored;
  if (resume && std::filesystem::exists(path, ignored)) return;
  const med_idt file = MEDfileOpen(path.c_str(), MED_ACC_CREAT);
  if (file < 0) fail(path, "cannot create");
  struct Closer {
    med_idt id;
    ~Closer() { MEDfileClose(id); }
  } closer{file};
  check(MEDfileCommentWr(file, "Quarry DEM surface loads (time means per export interval)"),
        path, "MEDfileCommentWr");
  const std::string axes = short_names({"X", "Y", "Z"});
  const std::string axis_units = short_names({"m", "m", "m"});
  // Space dimension 3, mesh dimension 2: a surface in space, as code_aster's shell models expect.
  check(MEDmeshCr(file, mesh_name_.c_str(), 3, 2, MED_UNSTRUCTURED_MESH,
                  "DEM surface, element id = input order", "s", MED_SORT_DTIT, MED_CARTESIAN,
                  axes.c_str(), axis_units.c_str()),
        path, "MEDmeshCr");
  const std::vector<double> coordinates = flatten(nodes);
  check(MEDmeshNodeCoordinateWr(file, mesh_name_.c_str(), MED_NO_DT, MED_NO_IT, 0.0,
                                MED_FULL_INTERLACE, static_cast<med_int>(nodes.size()),
                                coordinates.data()),
        path, "MEDmeshNodeCoordinateWr");
  std::vector<med_int> connectivity(3 * triangles.size());
  for (std::size_t t = 0; t < triangles.size(); ++t)
    for (int k = 0; k < 3; ++k) connectivity[3 * t + k] = static_cast<med_int>(triangles[t][k] + 1);
  check(MEDmeshElementConnectivityWr(file, mesh_name_.c_str(), MED_NO_DT, MED_NO_IT, 0.0,
                                     MED_CELL, MED_TRIA3, MED_NODAL, MED_FULL_INTERLACE,
                                     static_cast<med_int>(triangles.size()), connectivity.data()),
        path, "MEDmeshElementConnectivityWr");
  write_node_groups(file, path, mesh_name_, nodes.size(), groups);
  for (const FieldLayout& field : kFields) create_field(file, path, mesh_name_, field);
  if (displacement_) create_field(file, path, mesh_name_, kDisplacementLayout);
}

MedLoadWriter::~MedLoadWriter() { close(); }

void MedLoadWriter::close() {
  if (file_ < 0) return;
  MEDfileClose(file_);
  file_ = -1;
  // HDF5 keeps caches and free lists that grow with the number of objects a file holds (about
  // 3.5 kB per stored step, measured); closing the library after each record (it reopens itself
  // on the next call) keeps the run's memory flat however many records the file collects.
  H5garbage_collect();
  H5close();
}

void MedLoadWriter::write(int step_number, const LoadFrame& frame, std::span<const Vec3> displacement) {
  if (frame.pressure.size() != element_count_ || frame.nodal_force.size() != node_count_ ||
      displacement.size() != (displacement_ ? node_count_ : 0))
    fail(path_, "frame sizes do not match the mesh");
  // Open, write, close: the file on disk is complete after every record (MED has no flush), so
  // a crash loses at most the record being written.
  if (file_ < 0) {
    file_ = MEDfileOpen(path_.c_str(), MED_ACC_RDWR);
    if (file_ < 0) fail(path_, "cannot open for writing");
  }
  const med_idt file = file_;
  struct CloseAfterWrite {
    MedLoadWriter& writer;
    ~CloseAfterWrite() { writer.close(); }
  } close_after_write{*this};
  const auto write_field = [&](const FieldLayout& field, const std::vector<double>& values) {
    const med_int count = static_cast<med_int>(field.entity == MED_NODE ? node_count_ : element_count_);
    check(MEDfieldValueWr(file, field.name, step_number, MED_NO_IT, frame.time, field.entity,
                          field.geometry, MED_FULL_INTERLACE, MED_ALL_CONSTITUENT, count,
                          reinterpret_cast<const unsigned char*>(values.data())),
          path_, std::string("MEDfieldValueWr ") + field.name);
  };
  write_field(kFields[0], frame.pressure);
  write_field(kFields[1], flatten(frame.shear_stress));
  write_field(kFields[2], flatten(frame.force));
  write_field(kFields[3], flatten(frame.nodal_force));
  if (displacement_) write_field(kDisplacementLayout, flatten(displacement));
}

MedLoadFile read_med_loads(const std::string& path) {
  const med_idt file = MEDfileOpen(path.c_str(), MED_ACC_RDONLY);
  if (file < 0) fail(path, "cannot open for reading");
  struct Closer {
    med_idt id;
    ~Closer() { MEDfileClose(id); }
  } closer{file};
  MedLoadFile result;
  char mesh_name[MED_NAME_SIZE + 1] = {};
  char description[MED_COMMENT_SIZE + 1] = {};
  char dt_unit[MED_SNAME_SIZE + 1] = {};
  char axis_names[3 * MED_SNAME_SIZE + 1] = {};
  char axis_units[3 * MED_SNAME_SIZE + 1] = {};
  med_int space_dimension = 0, mesh_dimension = 0, steps = 0;
  med_mesh_type mesh_type;
  med_sorting_type sorting;
  med_axis_type axis_type;
  check(MEDmeshInfo(file, 1, mesh_name, &space_dimension, &mesh_dimension, &mesh_type, description,
                    dt_unit, &sorting, &steps, &axis_type, axis_names, axis_units),
        path, "MEDmeshInfo");
  result.mesh_name = trimmed(mesh_name, MED_NAME_SIZE);
  result.space_dimension = space_dimension;
  result.mesh_dimension = mesh_dimension;
  med_bool changed, transformed;
  const med_int node_count = MEDmeshnEntity(file, mesh_name, MED_NO_DT, MED_NO_IT, MED_NODE,
                                            MED_NONE, MED_COORDINATE, MED_NO_CMODE, &changed,
                                            &transformed);
  const med_int cell_count = MEDmeshnEntity(file, mesh_name, MED_NO_DT, MED_NO_IT, MED_CELL,
                                            MED_TRIA3, MED_CONNECTIVITY, MED_NODAL, &changed,
                                            &transformed);
  if (node_count < 0 || cell_count < 0) fail(path, "cannot count nodes or triangles");
  std::vector<double> coordinates(3 * static_cast<std::size_t>(node_count));
  check(MEDmeshNodeCoordinateRd(file, mesh_name, MED_NO_DT, MED_NO_IT, MED_FULL_INTERLACE,
                                coordinates.data()),
        path, "MEDmeshNodeCoordinateRd");
  result.nodes = unflatten(coordinates);
  std::vector<med_int> connectivity(3 * static_cast<std::size_t>(cell_count));
  check(MEDmeshElementConnectivityRd(file, mesh_name, MED_NO_DT, MED_NO_IT, MED_CELL, MED_TRIA3,
                                     MED_NODAL, MED_FULL_INTERLACE, connectivity.data()),
        path, "MEDmeshElementConnectivityRd");
  result.triangles.resize(static_cast<std::size_t>(cell_count));
  for (std::size_t t = 0; t < result.triangles.size(); ++t)
    for (int k = 0; k < 3; ++k)
      result.triangles[t][k] = static_cast<std::uint32_t>(connectivity[3 * t + k] - 1);

  // Node groups: families → groups, then each node's family number.
  std::map<med_int, std::vector<std::string>> groups_of_family;
  const med_int family_count = MEDnFamily(file, mesh_name);
  for (int f = 1; f <= family_count; ++f) {
    const med_int group_count = MEDnFamilyGroup(file, mesh_name, f);
    if (group_count < 0) fail(path, "MEDnFamilyGroup failed");
    char family_name[MED_NAME_SIZE + 1] = {};
    med_int number = 0;
    std::string names(static_cast<std::size_t>(group_count) * MED_LNAME_SIZE + 1, '\0');
    check(MEDfamilyInfo(file, mesh_name, f, family_name, &number, names.data()), path,
          "MEDfamilyInfo");
    for (med_int g = 0; g < group_count; ++g) {
      std::string name = names.substr(static_cast<std::size_t>(g) * MED_LNAME_SIZE, MED_LNAME_SIZE);
      name.resize(std::strlen(name.c_str()));
      groups_of_family[number].push_back(name);
    }
  }
  if (!groups_of_family.empty() && node_count > 0) {
    std::vector<med_int> numbers(static_cast<std::size_t>(node_count), 0);
    med_bool has_numbers = MED_FALSE, unused = MED_FALSE;
    if (MEDmeshnEntity(file, mesh_name, MED_NO_DT, MED_NO_IT, MED_NODE, MED_NONE, MED_FAMILY_NUMBER,
                       MED_NODAL, &unused, &has_numbers) > 0)
      check(MEDmeshEntityFamilyNumberRd(file, mesh_name, MED_NO_DT, MED_NO_IT, MED_NODE, MED_NONE,
                                        numbers.data()),
            path, "MEDmeshEntityFamilyNumberRd");
    std::map<std::string, std::vector<std::uint32_t>> nodes_of_group;
    for (std::size_t v = 0; v < numbers.size(); ++v) {
      const auto it = groups_of_family.find(numbers[v]);
      if (it == groups_of_family.end()) continue;
      for (const std::string& g : it->second) nodes_of_group[g].push_back(static_cast<std::uint32_t>(v));
    }
    for (auto& [name, nodes] : nodes_of_group) result.node_groups.push_back({name, std::move(nodes)});
  }

  const med_int field_count = MEDnField(file);
  for (int f = 1; f <= field_count; ++f) {
    const med_int components = MEDfieldnComponent(file, f);
    if (components < 0) fail(path, "MEDfieldnComponent failed");
    char field_name[MED_NAME_SIZE + 1] = {};
    char field_mesh[MED_NAME_SIZE + 1] = {};
    std::vector<char> names(static_cast<std::size_t>(components) * MED_SNAME_SIZE + 1);
    std::vector<char> units(static_cast<std::size_t>(components) * MED_SNAME_SIZE + 1);
    char field_dt_unit[MED_SNAME_SIZE + 1] = {};
    med_bool local;
    med_field_type type;
    med_int step_count = 0;
    check(MEDfieldInfo(file, f, field_name, field_mesh, &local, &type, names.data(), units.data(),
                       field_dt_unit, &step_count),
          path, "MEDfieldInfo");
    result.field_names.push_back(trimmed(field_name, MED_NAME_SIZE));
    result.field_units.push_back(trimmed(units.data(), MED_SNAME_SIZE));
    std::vector<std::string>& component_list = result.field_components.emplace_back();
    for (med_int c = 0; c < components; ++c)
      component_list.push_back(trimmed(names.data() + c * MED_SNAME_SIZE, MED_SNAME_SIZE));
    result.time_units.push_back(trimmed(field_dt_unit, MED_SNAME_SIZE));
  }
  for (const FieldLayout& field : kFields)
    if (std::find(result.field_names.begin(), result.field_names.end(), field.name) ==
        result.field_names.end())
      fail(path, std::string("no field \"") + field.name + "\"");
  const bool has_displacement = std::find(result.field_names.begin(), result.field_names.end(),
                                          kMedDisplacementField) != result.field_names.end();

  // Computing steps, from the pressure field; the other fields must have the same steps.
  char names[MED_SNAME_SIZE + 1], units[MED_SNAME_SIZE + 1], field_dt_unit[MED_SNAME_SIZE + 1];
  char field_mesh[MED_NAME_SIZE + 1];
  med_bool local;
  med_field_type type;
  med_int step_count = 0;
  check(MEDfieldInfoByName(file, kMedPressureField, field_mesh, &local, &type, names, units,
                           field_dt_unit, &step_count),
        path, "MEDfieldInfoByName");
  for (int s = 1; s <= step_count; ++s) {
    med_int numdt = 0, numit = 0;
    med_float time = 0.0;
    check(MEDfieldComputingStepInfo(file, kMedPressureField, s, &numdt, &numit, &time), path,
          "MEDfieldComputingStepInfo");
    LoadFrame frame;
    frame.time = time;
    for (const FieldLayout& field : kFields) {
      const med_int count = MEDfieldnValue(file, field.name, numdt, numit, field.entity,
                                           field.geometry);
      if (count < 0) fail(path, std::string("field ") + field.name + " lacks a step");
      std::vector<double> values(static_cast<std::size_t>(count) * field.components);
      check(MEDfieldValueRd(file, field.name, numdt, numit, field.entity, field.geometry,
                            MED_FULL_INTERLACE, MED_ALL_CONSTITUENT,
                            reinterpret_cast<unsigned char*>(values.data())),
            path, std::string("MEDfieldValueRd ") + field.name);
      if (std::strcmp(field.name, kMedPressureField) == 0) frame.pressure = values;
      else if (std::strcmp(field.name, kMedShearField) == 0) frame.shear_stress = unflatten(values);
      else if (std::strcmp(field.name, kMedForceField) == 0) frame.force = unflatten(values);
      else frame.nodal_force = unflatten(values);
    }
    if (has_displacement) {
      const med_int count = MEDfieldnValue(file, kMedDisplacementField, numdt, numit, MED_NODE, MED_NONE);
      if (count < 0) fail(path, std::string("field ") + kMedDisplacementField + " lacks a step");
      std::vector<double> values(3 * static_cast<std::size_t>(count));
      check(MEDfieldValueRd(file, kMedDisplacementField, numdt, numit, MED_NODE, MED_NONE, MED_FULL_INTERLACE,
                            MED_ALL_CONSTITUENT, reinterpret_cast<unsigned char*>(values.data())),
            path, std::string("MEDfieldValueRd ") + kMedDisplacementField);
      result.displacements.push_back(unflatten(values));
    }
    result.step_numbers.push_back(numdt);
    result.frames.push_back(std::move(frame));
  }
  return result;
}

}  // namespace quarry::fem_export
