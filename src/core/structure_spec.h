// A structure of the deck's `structures:` section: a shell model coupled two-way to the
// particles (issue #17 §5). The model file's EDEM card gives the coupling surface, PERIOD and
// FILTER; the entries here name what the bulk data does not say or override it. A Gmsh mesh
// says only nodes, elements and physical groups: its entry gives the rest (MeshStructureSpec).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "core/diagnostics.h"
#include "core/vec3.h"

namespace quarry {

enum class SupportFixity { clamped, pinned };  // clamped: DOFs 1–6 fixed; pinned: DOFs 1–3

// Nodes with a boundary condition: those inside the box [min, max] (m, inclusive), or (a Gmsh
// structure's) those of a physical group of points or curves. The CalculiX export's supports,
// and a Gmsh structure's.
struct SupportSpec {
  Located<std::string> name;
  Located<Vec3> min, max;
  Located<std::string> group;  // empty: the box
  Located<SupportFixity> fix{SupportFixity::clamped};
};

enum class MeshLengthUnit { metre, millimetre };  // a Gmsh mesh's coordinates: m or mm

// What bulk data's cards say and a Gmsh mesh does not: its length unit, the section (PSHELL),
// the material (MAT1 + MATS1), the supports (SPC) and the coupling surface (the EDEM card's
// COUPLING line: here a physical surface group, by name). SI, as every deck value.
struct MeshStructureSpec {
  Located<MeshLengthUnit> units{MeshLengthUnit::metre};
  Located<double> thickness{0.0};          // m
  Located<double> youngs_modulus{0.0};     // Pa
  Located<double> poisson_ratio{0.3};      // 1
  Located<double> density{0.0};            // kg/m³
  Located<double> yield_stress{0.0};       // Pa; 0: elastic
  Located<double> hardening_modulus{0.0};  // Pa, the slope of stress against plastic strain
  Located<std::string> coupling_group;     // the physical surface group the particles touch
  std::vector<SupportSpec> supports;       // boxes or groups; none: a free structure
};

struct StructureSpec {
  Located<std::string> name;      // the coupled DEM surface's name (unique among surfaces)
  Located<std::string> model;     // bulk data or Gmsh (.msh) file; relative to the deck, stored
                                  // absolute
  Located<std::string> material;  // the DEM material of the coupling surface (seed 000: "the
                                  // first equipment material" — here named)
  std::optional<Located<int>> constraint_set;  // SPC/SPC1 set id; absent: the model's only one
  std::optional<Located<int>> surface;         // SURF id; absent: the EDEM card's first COUPLING
  std::optional<Located<double>> period, filter;  // s; absent: the EDEM card's (or its defaults)
  Located<double> mass_scaling_time_step{0.0};    // s; 0: none (fem::ShellSolverOptions)
  Located<double> damping{0.0};                   // 1/s, mass-proportional
  // α of the drilling stiffness α G t A (1); absent: fem::SectionProperties' default.
  std::optional<Located<double>> drilling;
  Located<bool> export_loads{false};  // the coupling surface in the FEM load export (`export:`)
  std::optional<MeshStructureSpec> mesh;  // a Gmsh model; absent for bulk data
  SourceLocation where;                           // the entry, for messages
};

}  // namespace quarry
