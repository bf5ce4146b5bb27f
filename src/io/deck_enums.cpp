// The tables of the deck's enumerated values (deck_enums.h).
#include "io/deck_enums.h"

namespace quarry::deck_detail {

const EnumChoices<Integrator> kIntegrators{"integrator",
                                           {{"velocity_verlet", Integrator::velocity_verlet},
                                            {"symplectic_euler", Integrator::symplectic_euler}}};

const EnumChoices<NormalModel> kContactModels{
    "contact model",
    {{"hertz_mindlin", NormalModel::hertz_mindlin}, {"linear", NormalModel::linear}}};

const EnumChoices<RollingModel> kRollingModels{"rolling model",
                                               {{"constant_torque", RollingModel::constant_torque},
                                                {"epsd", RollingModel::epsd},
                                                {"none", RollingModel::none}}};

const EnumChoices<CohesionModel> kCohesionModels{
    "cohesion model", {{"sjkr", CohesionModel::sjkr}, {"jkr", CohesionModel::jkr}}};

const EnumChoices<SizeDistributionKind> kSizeDistributions{
    "size distribution",
    {{"fixed", SizeDistributionKind::fixed},
     {"uniform", SizeDistributionKind::uniform},
     {"normal", SizeDistributionKind::normal},
     {"log_normal", SizeDistributionKind::log_normal},
     {"discrete", SizeDistributionKind::discrete}}};

const EnumChoices<ExportFormat> kExportFormats{"export format",
                                               {{"med", ExportFormat::med},
                                                {"calculix", ExportFormat::calculix},
                                                {"vtu", ExportFormat::vtu},
                                                {"csv", ExportFormat::csv}}};

const EnumChoices<CalculixAnalysis> kCalculixAnalyses{
    "CalculiX analysis",
    {{"static", CalculixAnalysis::static_step}, {"dynamic", CalculixAnalysis::dynamic}}};

const EnumChoices<SupportFixity> kSupportFixities{
    "support fixity", {{"clamped", SupportFixity::clamped}, {"pinned", SupportFixity::pinned}}};

const EnumChoices<MeshLengthUnit> kMeshLengthUnits{
    "length unit of the mesh", {{"m", MeshLengthUnit::metre}, {"mm", MeshLengthUnit::millimetre}}};

const EnumChoices<SurfaceKind> kSurfaceKinds{"surface type",
                                             {{"stl", SurfaceKind::stl},
                                              {"plane", SurfaceKind::plane},
                                              {"box", SurfaceKind::box},
                                              {"cylinder", SurfaceKind::cylinder},
                                              {"mesh", SurfaceKind::mesh}}};

const EnumChoices<MotionKind> kMotionKinds{"motion type",
                                           {{"rotation", MotionKind::rotation},
                                            {"translation", MotionKind::translation},
                                            {"vibration", MotionKind::vibration}}};

const EnumChoices<RegionKind> kRegionKinds{
    "region type", {{"box", RegionKind::box}, {"cylinder", RegionKind::cylinder}, {"point", RegionKind::point}}};

const EnumChoices<MonitorKind> kMonitorKinds{"monitor type",
                                             {{"mass", MonitorKind::mass},
                                              {"particle", MonitorKind::particle},
                                              {"mass_flow", MonitorKind::mass_flow},
                                              {"stress", MonitorKind::stress},
                                              {"velocity_profile", MonitorKind::velocity_profile}}};

const EnumChoices<Axis> kAxes{"axis", {{"x", Axis::x}, {"y", Axis::y}, {"z", Axis::z}}};

}  // namespace quarry::deck_detail
