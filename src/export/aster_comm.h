// code_aster command file (.comm) written beside an exported surface's MED file: it reads the
// mesh (LIRE_MAILLAGE) and, for every export record, the nodal forces and the pressure (and the
// displacement of a moving surface) (LIRE_CHAMP at the record's instant), so a structural study
// starts from the loads as written.
// A template: material, supports and the analysis are left for the user (commented outline).
#pragma once

#include <string>
#include <vector>

namespace quarry::fem_export {

struct AsterCommInput {
  std::string surface;                   // surface name (for the comments)
  std::string med_file;                  // file name of the MED file, beside the .comm
  std::string mesh_name;                 // mesh name inside the MED file (NOM_MED of the mesh)
  std::vector<double> times;             // s, the instant of each record (MED computing step k+1)
  std::vector<std::string> node_groups;  // GROUP_NO names in the MED file (the supports)
  bool displacement = false;             // the MED file has the node field displacement
};

// Logical unit the MED file is attached to in the study (.export: "F mmed FILE D 20").
inline constexpr int kAsterMedUnit = 20;

// The .comm text (code_aster 15+ syntax, Python). Cost: O(records).
std::string aster_comm_text(const AsterCommInput& input);

}  // namespace quarry::fem_export
