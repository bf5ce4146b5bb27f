// MED (Salome / code_aster) output of an exported surface: the triangle mesh (TRIA3 cells in
// input order, nodes in input order, at their reference positions) and, at every export time,
// the cell fields pressure, shear_stress, force and the node field nodal_force, unit-tagged (Pa,
// N; time unit s); for a moving surface also the node field displacement (m).
// Written through libmedC (MED-fichier 4), read back by read_med_loads for tests and tools.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "core/vec3.h"
#include "geometry/load_window.h"

namespace quarry::fem_export {

// Field names in the file, as code_aster's LIRE_CHAMP / LIRE_RESU name them (NOM_MED).
inline constexpr const char* kMedPressureField = "pressure";          // Pa, 1 component, cells
inline constexpr const char* kMedShearField = "shear_stress";         // Pa, 3 components, cells
inline constexpr const char* kMedForceField = "force";                // N, 3 components, cells
inline constexpr const char* kMedNodalForceField = "nodal_force";     // N, 3 components, nodes
inline constexpr const char* kMedDisplacementField = "displacement";  // m, 3 components, nodes
// Component names, as code_aster names them (quantities PRES_R and FORC_R), so that LIRE_CHAMP
// with NOM_CMP_IDEM='OUI' reads them as they are: PRES for the pressure; FX FY FZ for the
// forces and the shear traction (global axes).
inline constexpr const char* kMedPressureComponent = "PRES";
inline constexpr const char* kMedForceComponents[3] = {"FX", "FY", "FZ"};
// DX DY DZ of the DEPL_R quantity for the displacement (LIRE_CHAMP TYPE_CHAM='NOEU_DEPL_R').
inline constexpr const char* kMedDisplacementComponents[3] = {"DX", "DY", "DZ"};

// A named set of mesh nodes (0-based), written to MED as a node group (code_aster: GROUP_NO),
// e.g. the supports of the CalculiX section, so the structural model can fix them by name.
struct MedNodeGroup {
  std::string name;                  // ≤ 80 characters (MED_LNAME_SIZE)
  std::vector<std::uint32_t> nodes;  // 0-based mesh node indices
};

class MedLoadWriter {
 public:
  // Fresh: creates `path` (replacing it) with mesh `mesh_name` (≤ 64 characters) of `nodes`
  // (m) and `triangles` (0-based vertex indices; written 1-based) and the four empty fields.
  // Resume (`resume` true and the file exists): keeps it; steps written again overwrite the
  // old ones. Throws std::runtime_error naming the file on any MED error.
  // `groups` become node groups (one MED family per distinct combination of groups).
  // `displacement`: the file also has the node field displacement (a moving surface).
  MedLoadWriter(const std::string& path, const std::string& mesh_name,
                std::span<const Vec3> nodes,
                std::span<const std::array<std::uint32_t, 3>> triangles, bool resume,
                std::span<const MedNodeGroup> groups = {}, bool displacement = false);

  // Writes the four fields of `frame` (and `displacement`, m per node, when the file has that
  // field) as computing step `step_number` (≥ 1, the MED numdt; numit = MED_NO_IT) at time
  // frame.time (s). Pre: sizes match the mesh; `displacement` has one entry per node exactly
  // when has_displacement().
  // The file is opened and closed around each write, so it is complete on disk afterwards.
  // Cost: O(elements + nodes), four or five HDF5 dataset writes, one file open (~1 ms).
  void write(int step_number, const LoadFrame& frame, std::span<const Vec3> displacement = {});
  bool has_displacement() const { return displacement_; }
  // Closes the file (HDF5 completes it on disk); the next write reopens it.
  void close();
  // The mesh's name in the file (the given name cut to 64 characters).
  const std::string& mesh_name() const { return mesh_name_; }

  ~MedLoadWriter();
  MedLoadWriter(const MedLoadWriter&) = delete;
  MedLoadWriter& operator=(const MedLoadWriter&) = delete;

 private:
  long long file_ = -1;  // med_idt of the open file, −1 when closed
  std::string path_;
  std::string mesh_name_;
  std::size_t node_count_ = 0, element_count_ = 0;
  bool displacement_ = false;
};

// Everything read_med_loads finds in a file written by MedLoadWriter.
struct MedLoadFile {
  std::string mesh_name;
  int space_dimension = 0, mesh_dimension = 0;
  std::vector<Vec3> nodes;                                  // m
  std::vector<std::array<std::uint32_t, 3>> triangles;      // 0-based
  std::vector<int> step_numbers;                            // numdt of each frame
  std::vector<LoadFrame> frames;                            // duration is not stored (0)
  std::vector<std::vector<Vec3>> displacements;             // m per node, per frame; empty: none
  std::vector<std::string> field_names;                     // in file order
  std::vector<std::string> field_units;                     // first component's unit, per field
  std::vector<std::vector<std::string>> field_components;   // component names, per field
  std::vector<std::string> time_units;                      // per field
  std::vector<MedNodeGroup> node_groups;                    // sorted by name, nodes ascending
};

// Reads the mesh and every computing step of the four fields (and of displacement if present). Throws std::runtime_error on a
// missing file, a missing field or a MED error. Memory: the whole file (tests, small files).
MedLoadFile read_med_loads(const std::string& path);

}  // namespace quarry::fem_export
