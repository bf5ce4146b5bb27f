// A structure of the deck's `structures:` section: a shell model coupled two-way to the
// particles (issue #17 §5). The model file's EDEM card gives the coupling surface, PERIOD and
// FILTER; the entries here name what the bulk data does not say or override it.
#pragma once

#include <optional>
#include <string>

#include "core/diagnostics.h"

namespace quarry {

struct StructureSpec {
  Located<std::string> name;      // the coupled DEM surface's name (unique among surfaces)
  Located<std::string> model;     // bulk data file; relative to the deck, stored absolute
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
  SourceLocation where;                           // the entry, for messages
};

}  // namespace quarry
