// StructureModel: a shell structure as plain data in SI units — grid points, CQUAD4/CTRIA3
// shells, PSHELL properties, MAT1 (+ MATS1) materials, single-point constraints, sets, surfaces
// and the OptiStruct EDEM coupling card. Produced by io/bulk_data (Nastran/OptiStruct bulk data)
// and io/gmsh_reader; consumed by the shell solver and the coupling. No solver state here.
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "core/diagnostics.h"
#include "core/vec3.h"

namespace quarry {

// The unit system a model file is written in. Values in a StructureModel are always SI; this
// records what the file declared (docs/fem.md, "Units").
enum class UnitSystem {
  si,               // m, kg, s, N, Pa
  mm_tonne_second,  // mm, t, s, N, MPa (OptiStruct UNITS = MPA)
};

// Where a card of the model was written: an index into StructureModel::source_files and the
// 1-based line of the card's first line (compact: a model holds one per node and element).
struct CardLocation {
  std::int32_t file_index = -1;  // -1 = not from a file
  std::int32_t line = 0;
};

// Degrees of freedom of a grid point, numbered as Nastran does: 1-3 translations along x, y, z;
// 4-6 rotations about x, y, z. Written in cards as a code of digits such as 123456.
struct DofSet {
  std::uint8_t mask = 0;  // bit (dof - 1)

  static constexpr DofSet all() { return DofSet{0x3F}; }
  constexpr bool has(int dof) const { return dof >= 1 && dof <= 6 && (mask >> (dof - 1)) & 1; }
  constexpr bool empty() const { return mask == 0; }
  constexpr void add(int dof) { mask = static_cast<std::uint8_t>(mask | (1u << (dof - 1))); }
  friend constexpr bool operator==(DofSet, DofSet) = default;
};

// GRID: a node in the basic (global Cartesian) system.
struct GridPoint {
  Vec3 position;                 // m
  DofSet permanent_constraints;  // the GRID's PS field: fixed for every load case
  CardLocation where;
};

enum class ShellShape { quad4, tria3 };  // CQUAD4, CTRIA3

// A shell element: nodes in the order written (it defines the element normal by the right-hand
// rule). Thickness and material come from the property.
struct ShellElement {
  int id = 0;
  int property_id = 0;  // PSHELL id; 0 = none given (a Gmsh mesh: the deck supplies it)
  ShellShape shape = ShellShape::quad4;
  std::array<int, 4> nodes{};  // grid ids; nodes[3] = 0 for a triangle
  CardLocation where;

  int node_count() const { return shape == ShellShape::quad4 ? 4 : 3; }
};

// PSHELL. Nastran's meaning of the optional materials is kept: no MID2 = no bending stiffness
// (a membrane), no MID3 = no transverse shear flexibility; the solver decides what it accepts.
struct ShellProperty {
  int id = 0;
  double thickness = 0.0;                   // T (m)
  int membrane_material_id = 0;             // MID1
  std::optional<int> bending_material_id;   // MID2
  double bending_inertia_ratio = 1.0;       // 12I/T³ (1)
  std::optional<int> shear_material_id;     // MID3
  double shear_thickness_ratio = 0.833333;  // TS/T (1)
  double nonstructural_mass = 0.0;          // NSM (kg/m²)
  double fiber_bottom = 0.0;                // Z1 (m); default −T/2
  double fiber_top = 0.0;                   // Z2 (m); default +T/2
  CardLocation where;
};

// MATS1 TYPE PLASTIC, YF 1 (von Mises), HR 1 (isotropic), with a constant hardening slope:
// yield stress σ_y = LIMIT1 + H · ε_p (ε_p the effective plastic strain).
struct J2Plasticity {
  double initial_yield_stress = 0.0;  // LIMIT1 (Pa)
  double hardening_modulus = 0.0;     // H: slope of stress against plastic strain (Pa); 0 = ideal
  CardLocation where;
};

// MAT1, isotropic and linear elastic; E, G and ν satisfy E = 2(1 + ν)G when one was left blank.
struct IsotropicMaterial {
  int id = 0;
  double youngs_modulus = 0.0;             // E (Pa)
  double shear_modulus = 0.0;              // G (Pa)
  double poisson_ratio = 0.0;              // NU (1)
  double density = 0.0;                    // RHO (kg/m³); blank = 0, as Nastran
  std::optional<J2Plasticity> plasticity;  // from a MATS1 with the same id
  CardLocation where;
};

// SPC or SPC1: the listed DOFs of the listed grid points are fixed (zero displacement). Cards
// with the same set id form one constraint set, selected by the deck.
struct SinglePointConstraint {
  int set_id = 0;
  DofSet dofs;
  std::vector<int> nodes;  // grid ids, in the order written
  CardLocation where;
};

enum class SetKind { grid, element };

// SET of TYPE GRID or ELEM (or a Gmsh physical group of surfaces): ids sorted, each once.
struct IdSet {
  int id = 0;
  SetKind kind = SetKind::grid;
  std::string name;  // Gmsh physical name; empty for bulk data
  std::vector<int> members;
  CardLocation where;
};

// SURF: a surface made of shell elements (ELFACE lines, or the SET form with TYPE ELEM);
// element ids sorted, each once.
struct Surface {
  int id = 0;
  std::vector<int> elements;
  CardLocation where;
};

// One COUPLING line of the EDEM card: TYPE SURF, ID, LABEL.
struct CouplingSurfaceRef {
  int surface_id = 0;                // the SURF's id
  std::optional<std::string> label;  // LABEL as written; absent when blank (it is optional)
  CardLocation where;
};

// The OptiStruct EDEM card (seed 000): coupling control and the coupling surfaces. Absent values
// keep the seed's defaults for the coupling to apply, since they depend on the run:
// PERIOD = TTERM / 100, FILTER = PERIOD.
struct EdemCoupling {
  int id = 0;
  std::optional<double> period;  // s, > 0; absent = TTERM / 100
  std::optional<double> filter;  // s, > PERIOD; absent = PERIOD
  std::vector<CouplingSurfaceRef> surfaces;
  CardLocation where;
};

struct StructureModel {
  UnitSystem declared_units = UnitSystem::si;      // what the file said; all values below are SI
  std::map<int, GridPoint> nodes;                  // by grid id
  std::vector<ShellElement> shells;                // in file order
  std::map<int, ShellProperty> properties;         // by PSHELL id
  std::map<int, IsotropicMaterial> materials;      // by MAT1 id
  std::vector<SinglePointConstraint> constraints;  // in file order
  std::map<int, IdSet> sets;                       // by SET id
  std::map<int, Surface> surfaces;                 // by SURF id
  std::vector<EdemCoupling> couplings;             // in file order
  // Gmsh: the named physical groups of points and curves, as node sets (kind grid, id = the
  // physical tag, members = node ids): a deck's supports name them. Empty for bulk data.
  std::vector<IdSet> node_groups;
  std::vector<std::string> source_files;           // the files read, as named (CardLocation index)
  // Cards read but not used (e.g. PARAM, output requests) and warnings, one note per card name
  // at its first occurrence; print with notes.format().
  Diagnostics notes;

  // The file:line:column of a card, for messages: its first line, column 1 (where its name is).
  SourceLocation where(const CardLocation& location) const {
    if (location.file_index < 0 ||
        location.file_index >= static_cast<std::int32_t>(source_files.size()))
      return {};
    return {source_files[static_cast<std::size_t>(location.file_index)], location.line, 1};
  }
};

}  // namespace quarry
