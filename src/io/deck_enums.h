// The spellings of the deck's enumerated values, one table per key: the parser accepts them
// (deck_settings.cpp, deck_geometry.cpp) and the writer writes them (deck_writer.cpp), so the two
// cannot disagree.
#pragma once

#include <stdexcept>
#include <string>

#include "core/simulation_spec.h"
#include "io/deck_reader.h"

namespace quarry::deck_detail {

extern const EnumChoices<Integrator> kIntegrators;
extern const EnumChoices<NormalModel> kContactModels;
extern const EnumChoices<RollingModel> kRollingModels;
extern const EnumChoices<CohesionModel> kCohesionModels;
extern const EnumChoices<SizeDistributionKind> kSizeDistributions;
extern const EnumChoices<ExportFormat> kExportFormats;
extern const EnumChoices<CalculixAnalysis> kCalculixAnalyses;
extern const EnumChoices<SupportFixity> kSupportFixities;
extern const EnumChoices<MeshLengthUnit> kMeshLengthUnits;
extern const EnumChoices<SurfaceKind> kSurfaceKinds;
extern const EnumChoices<MotionKind> kMotionKinds;
extern const EnumChoices<RegionKind> kRegionKinds;
extern const EnumChoices<MonitorKind> kMonitorKinds;
extern const EnumChoices<Axis> kAxes;

// The first spelling of `value` in `choices`. Throws std::logic_error for a value the table has
// no spelling for (a new enumerator added to the spec but not to its table).
template <class Enum>
const std::string& spelling(const EnumChoices<Enum>& choices, Enum value) {
  for (const auto& [name, v] : choices.names)
    if (v == value) return name;
  throw std::logic_error("deck: a " + choices.noun + " has no spelling in the deck's table");
}

}  // namespace quarry::deck_detail
