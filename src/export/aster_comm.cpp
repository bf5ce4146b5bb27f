// code_aster command file template (aster_comm.h). Commands after the code_aster user manual
// (LIRE_MAILLAGE U7.01.01, LIRE_CHAMP U7.02.02, AFFE_MODELE U4.41.01): the fields are read with
// NOM_CMP_IDEM='OUI', which needs the MED components to carry code_aster's names (med_file.h).
#include "export/aster_comm.h"

#include <fmt/format.h>

#include "export/med_file.h"

namespace quarry::fem_export {

std::string aster_comm_text(const AsterCommInput& input) {
  std::string text;
  text += fmt::format(
      "# code_aster command file written by Quarry for the DEM loads on surface '{}'.\n"
      "# A template: it reads the mesh and every export record of {}; add the material, the\n"
      "# supports and the analysis below. Units SI: m, N, Pa, s.\n"
      "# Attach the MED file to logical unit {} in the study's .export file:\n"
      "#   F mmed {} D {}\n"
      "# Fields (NOM_MED), time means over each export interval, record k = MED step k:\n"
      "#   '{}'  per node, N, FX FY FZ: consistent nodal forces of the particles on the surface\n"
      "#   '{}'  per cell, Pa, PRES: compressive normal stress (mean over the cell)\n"
      "#   '{}'  per cell, Pa, FX FY FZ: tangential traction (shear stress vector)\n"
      "#   '{}'  per cell, N, FX FY FZ: total force on the cell\n",
      input.surface, input.med_file, kAsterMedUnit, input.med_file, kAsterMedUnit,
      kMedNodalForceField, kMedPressureField, kMedShearField, kMedForceField);
  if (input.displacement)
    text += fmt::format(
        "#   '{}'  per node, m, DX DY DZ: the surface's displacement from the mesh (its reference\n"
        "#                  positions), the mean over the interval: the surface moved during the run\n",
        kMedDisplacementField);
  text += "\n";
  text += "DEBUT(LANG='EN')\n\n";
  text += fmt::format("mesh = LIRE_MAILLAGE(UNITE={}, FORMAT='MED', NOM_MED='{}')\n", kAsterMedUnit,
                      input.mesh_name);
  text += "# Kirchhoff plates (DKT) on the TRIA3 cells; thickness in AFFE_CARA_ELEM below.\n";
  text +=
      "model = AFFE_MODELE(MAILLAGE=mesh,\n"
      "                    AFFE=_F(TOUT='OUI', PHENOMENE='MECANIQUE', MODELISATION='DKT'))\n\n";
  text += "# s, end of each export interval (the instant of MED step k is instants[k - 1])\n";
  text += "instants = [";
  for (std::size_t k = 0; k < input.times.size(); ++k)
    text += fmt::format("{}{:.17g}", k == 0 ? "" : ", ", input.times[k]);
  text += "]\n\n";
  text += "nodal_forces = []  # cham_no FORC_R (N) per record\n";
  text += "pressures = []     # cham_elem PRES_R (Pa) per record\n";
  if (input.displacement) text += "displacements = []  # cham_no DEPL_R (m) per record\n";
  text += "for instant in instants:\n";
  text += fmt::format(
      "    nodal_forces.append(LIRE_CHAMP(UNITE={}, FORMAT='MED', MAILLAGE=mesh, NOM_MED='{}',\n"
      "                                   TYPE_CHAM='NOEU_FORC_R', NOM_CMP_IDEM='OUI', "
      "INST=instant))\n",
      kAsterMedUnit, kMedNodalForceField);
  text += fmt::format(
      "    pressures.append(LIRE_CHAMP(UNITE={}, FORMAT='MED', MAILLAGE=mesh, MODELE=model,\n"
      "                                NOM_MED='{}', TYPE_CHAM='ELEM_PRES_R', NOM_CMP_IDEM='OUI',\n"
      "                                INST=instant))\n",
      kAsterMedUnit, kMedPressureField);
  if (input.displacement)
    text += fmt::format(
        "    displacements.append(LIRE_CHAMP(UNITE={}, FORMAT='MED', MAILLAGE=mesh, NOM_MED='{}',\n"
        "                                    TYPE_CHAM='NOEU_DEPL_R', NOM_CMP_IDEM='OUI', "
        "INST=instant))\n",
        kAsterMedUnit, kMedDisplacementField);
  text += "\n";
  if (input.displacement) {
    text +=
        "# The deformed surface of record k, if the study wants it (the loads act on it):\n"
        "# MODI_MAILLAGE(reuse=mesh, MAILLAGE=mesh, DEFORME=_F(OPTION='TRAN', DEPL=displacements[k]))\n\n";
  }
  text += "# To complete: material and shell thickness, the supports, the analysis, e.g.\n";
  text += "# steel = DEFI_MATERIAU(ELAS=_F(E=2.1e11, NU=0.3, RHO=7850.0))\n";
  text += "# material = AFFE_MATERIAU(MAILLAGE=mesh, AFFE=_F(TOUT='OUI', MATER=steel))\n";
  text += "# shell = AFFE_CARA_ELEM(MODELE=model, COQUE=_F(TOUT='OUI', EPAIS=0.006))\n";
  if (input.node_groups.empty()) {
    text +=
        "# supports = AFFE_CHAR_MECA(MODELE=model, DDL_IMPO=_F(GROUP_NO=..., DX=0.0, DY=0.0, "
        "DZ=0.0))\n";
  } else {
    text += "# Node groups in the MED file (the export's supports):";
    for (const std::string& group : input.node_groups) text += " '" + group + "'";
    text += "\n";
    for (const std::string& group : input.node_groups)
      text += fmt::format(
          "# support_{} = AFFE_CHAR_MECA(MODELE=model, DDL_IMPO=_F(GROUP_NO='{}', "
          "DX=0.0, DY=0.0, DZ=0.0))\n",
          group, group);
  }
  text += "# then a static or dynamic analysis loaded by nodal_forces[k] at instants[k].\n\n";
  text += "FIN()\n";
  return text;
}

}  // namespace quarry::fem_export
