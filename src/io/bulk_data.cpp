// Bulk data reader entry points: lexes the files (bulk_fields), hands each card to its reader
// (bulk_cards, bulk_edem), then checks what spans cards — references, the unit system, cards
// that are refused or unknown — converts to SI and reports every error at once, in reading order.
#include "io/bulk_data.h"

#include <fmt/format.h>

#include <algorithm>
#include <fstream>
#include <set>
#include <sstream>
#include <string_view>

#include "io/bulk_model.h"

namespace quarry {

namespace bulk_detail {

std::string ModelState::first_defined(const CardLocation& location) const {
  const SourceLocation where = problems.location(Place{location.file_index, location.line, 0, 0});
  return fmt::format("first defined at {}:{}", where.file, where.line);
}

void ModelState::declare_units(UnitSystem system, const Place& place, std::string spelling) {
  if (!units) {
    units = UnitsDeclaration{system, place, std::move(spelling)};
    return;
  }
  if (units->system == system) return;
  const SourceLocation first = problems.location(units->place);
  problems.error(place,
                 fmt::format("{} disagrees with {} at {}:{}", spelling, units->spelling, first.file,
                             first.line),
                 "declare the model's units once");
}

void ModelState::ignore(const std::string& name, const Place& place) {
  CardTally& tally = ignored_cards[name];
  if (tally.count++ == 0) tally.first = place;
}

namespace {

using CardReaderFunction = void (*)(const Card&, ModelState&);

struct SupportedCard {
  std::string_view name;
  CardReaderFunction read;
};

constexpr SupportedCard kSupported[] = {
    {"GRID", read_grid},
    {"CQUAD4", read_shell_element},
    {"CTRIA3", read_shell_element},
    {"PSHELL", read_pshell},
    {"MAT1", read_mat1},
    {"MATS1", read_mats1},
    {"SPC", read_spc},
    {"SPC1", read_spc1},
    {"SET", read_set},
    {"SURF", read_surf},
    {"EDEM", read_edem},
    {"DTI", read_dti},
    {"PARAM", read_param},
};

// Cards that are read past: they do not change the structure Quarry builds. One note each.
struct CardGroup {
  std::vector<std::string_view> names;
  std::string_view why;
  std::set<int> ModelState::*refused_ids = nullptr;  // where a refused card's id is kept
};

const std::vector<CardGroup>& ignored_groups() {
  static const std::vector<CardGroup> groups = {
      {{"EIGRL", "EIGRD", "EIGR", "EIGC"}, "eigenvalue extraction is not a part of the model"},
      {{"NLPARM", "NLPARMX", "NLOUT", "NLADAPT", "NLMON", "TSTEP", "TSTEPNL", "TSTEPE"},
       "solution controls: the deck sets the end time and the time step"},
      {{"XSHLPRM", "XSOLPRM"},
       "explicit element formulation choices: Quarry's shell formulation is its own "
       "(docs/fem.md)"},
      {{"CORD1R", "CORD1C", "CORD1S", "CORD2R", "CORD2C", "CORD2S"},
       "coordinate systems: no GRID may use one (CP and CD must be blank or 0)"},
      {{"PLOTEL"}, "plot elements have no stiffness and no mass"},
      {{"TABLED1", "TABLED2", "TABLED3", "TABLED4", "TABLEM1", "TABLES1"},
       "tables: no card Quarry reads refers to them"},
      {{"DESVAR", "DRESP1", "DRESP2", "DRESP3", "DCONSTR", "DCONADD", "DOPTPRM", "DVPREL1",
        "DVPREL2", "DVGRID", "DSIZE", "DTPL", "DTPG", "DSHAPE"},
       "optimization entries"},
      {{"SET1", "SET3", "SEQGP", "MONPNT1"}, "no card Quarry reads refers to them"},
  };
  return groups;
}

// Cards that change the physics and that Quarry cannot honour: errors.
const std::vector<CardGroup>& refused_groups() {
  static const std::vector<CardGroup> groups = {
      {{"CBAR",   "CBEAM",  "CBEND",  "CROD",   "CONROD", "CTUBE",  "CBUSH",  "CBUSH1D",
        "CELAS1", "CELAS2", "CELAS3", "CELAS4", "CDAMP1", "CDAMP2", "CDAMP3", "CDAMP4",
        "CDAMP5", "CGAP",   "CHEXA",  "CPENTA", "CTETRA", "CPYRA",  "CQUAD8", "CQUADR",
        "CQUAD",  "CTRIA6", "CTRIAR", "CSHEAR", "CWELD",  "CFAST",  "CSEAM",  "CMASS1",
        "CMASS2", "CMASS3", "CMASS4", "CONM1",  "CONM2"},
       "Quarry's structural model has CQUAD4 and CTRIA3 shells only",
       &ModelState::refused_element_ids},
      {{"RBE1", "RBE2", "RBE3", "RBAR", "RBAR1", "RROD", "RTRPLT", "MPC", "MPCADD"},
       "rigid elements and multi-point constraints are not supported"},
      {{"PCOMP", "PCOMPG", "PCOMPP", "PSOLID", "PBAR", "PBARL", "PBEAM", "PBEAML", "PROD", "PBUSH",
        "PELAS", "PDAMP", "PGAP", "PSHEAR", "PMASS", "PSHELL1"},
       "only PSHELL properties (homogeneous isotropic shells) are supported",
       &ModelState::refused_property_ids},
      {{"MAT2", "MAT3", "MAT8", "MAT9", "MAT10", "MATT1", "MATS8", "MATHE", "MATX33", "MATX36",
        "MATX65", "MATVE", "MATHF", "MATS3"},
       "only MAT1 (with MATS1 plasticity) is supported",
       &ModelState::refused_material_ids},
      {{"FORCE",  "FORCE1", "FORCE2", "MOMENT", "MOMENT1", "MOMENT2", "PLOAD", "PLOAD1", "PLOAD2",
        "PLOAD4", "GRAV",   "ACCEL",  "ACCEL1", "RFORCE",  "LOAD",    "DLOAD", "TLOAD1", "TLOAD2",
        "RLOAD1", "RLOAD2", "DAREA",  "SPCD",   "TEMP",    "TEMPD",   "TIC",   "TICD"},
       "loads and initial conditions are not read from the model: the particles load the "
       "structure, and gravity and motion come from the deck; remove the card (or comment it "
       "out with $)"},
      {{"SPCADD", "SUPORT", "SUPORT1", "GRDSET"},
       "write the constraints on SPC/SPC1 cards (and CP, CD, PS on each GRID)"},
      {{"CONTACT", "TIE", "PCONT", "PCONTX", "CONTPRM", "BCTABLE", "BSURF", "BCPROP"},
       "contact between structural parts is not supported"},
  };
  return groups;
}

}  // namespace

std::string_view static_card_name(const std::string& name) {
  for (const SupportedCard& card : kSupported)
    if (card.name == name) return card.name;
  return "card";
}

namespace {

const CardGroup* find_group(const std::vector<CardGroup>& groups, const std::string& name) {
  for (const CardGroup& group : groups)
    if (std::find(group.names.begin(), group.names.end(), name) != group.names.end()) return &group;
  return nullptr;
}

std::vector<std::string> known_card_names() {
  std::vector<std::string> names;
  for (const SupportedCard& card : kSupported) names.emplace_back(card.name);
  for (const auto* groups : {&ignored_groups(), &refused_groups()})
    for (const CardGroup& group : *groups)
      for (const std::string_view name : group.names) names.emplace_back(name);
  return names;
}

void read_card(const Card& card, ModelState& state) {
  if (!state.first_card) state.first_card = card.place;
  for (const SupportedCard& supported : kSupported) {
    if (card.name != supported.name) continue;
    supported.read(card, state);
    return;
  }
  std::map<std::string, CardTally>* tallies = &state.unknown_cards;
  if (find_group(ignored_groups(), card.name)) {
    tallies = &state.ignored_cards;
  } else if (const CardGroup* refused = find_group(refused_groups(), card.name)) {
    tallies = &state.refused_cards;
    if (refused->refused_ids)
      if (const std::optional<std::int64_t> id = parse_integer(card.at(0).text))
        (state.*(refused->refused_ids)).insert(static_cast<int>(*id));
  }
  CardTally& tally = (*tallies)[card.name];
  if (tally.count++ == 0) tally.first = card.place;
}

std::string times(int count) {
  return count == 1 ? std::string("1 card") : fmt::format("{} cards", count);
}

void report_card_tallies(ModelState& state) {
  for (const auto& [name, tally] : state.refused_cards)
    state.problems.error(tally.first,
                         fmt::format("{} is not supported ({}{})", name, times(tally.count),
                                     tally.count > 1 ? ", the first here" : ""),
                         std::string(find_group(refused_groups(), name)->why));
  const std::vector<std::string> known = known_card_names();
  for (const auto& [name, tally] : state.unknown_cards) {
    const std::string close = did_you_mean(name, known);
    state.problems.error(
        tally.first,
        fmt::format("unknown card {} ({}{})", name, times(tally.count),
                    tally.count > 1 ? ", the first here" : ""),
        close.empty() ? "Quarry reads GRID, CQUAD4, CTRIA3, PSHELL, MAT1, MATS1, SPC, SPC1, SET, "
                        "SURF, EDEM and DTI,UNITS (docs/fem.md); comment a card out with $ if "
                        "it does not change the structure"
                      : close);
  }
  for (const auto& [name, tally] : state.ignored_cards) {
    const CardGroup* group = find_group(ignored_groups(), name);
    std::string why = group ? std::string(group->why) : std::string();
    if (name == "PARAM") why = "parameters of OptiStruct's own solution";
    if (name == "DTI") why = "DTI tables other than UNITS";
    if (name.rfind("SET of TYPE", 0) == 0) why = "Quarry reads sets of grids and elements";
    state.problems.note(tally.first, fmt::format("{} ignored ({})", name, times(tally.count)), why);
  }
}

// Reports missing targets of `references`; at most kShown per kind, then one summary.
constexpr std::size_t kShownMissingReferences = 50;

// References to a refused card (`refused`) are not reported: the refusal says it.
template <class Exists>
void check_references(ModelState& state, const std::vector<Reference>& references,
                      std::string_view target, Exists exists, const std::set<int>& refused = {}) {
  std::size_t missing = 0;
  const Reference* first_unshown = nullptr;
  for (const Reference& reference : references) {
    if (exists(reference.id) || refused.count(reference.id)) continue;
    if (++missing <= kShownMissingReferences)
      state.problems.error(reference.place,
                           fmt::format("{} {} names {} {}, which is not defined", reference.card,
                                       reference.owner, target, reference.id),
                           fmt::format("no {} {} in the model", target, reference.id));
    else if (!first_unshown)
      first_unshown = &reference;
  }
  if (first_unshown)
    state.problems.error(first_unshown->place,
                         fmt::format("{} more references to missing {} cards",
                                     missing - kShownMissingReferences, target));
}

// The ids in `list` that exist (all of them from ranges; explicit ones are checked as
// references), sorted and unique. `ids` is the sorted list of defined ids.
std::vector<int> resolve_list(ModelState& state, const IdList& list, const std::vector<int>& ids,
                              std::string_view target, std::vector<Reference>& references) {
  std::vector<int> members;
  for (const Reference& reference : list.ids) {
    members.push_back(reference.id);
    references.push_back(reference);
  }
  for (const IdRange& range : list.ranges) {
    std::size_t taken = 0;
    for (auto it = std::lower_bound(ids.begin(), ids.end(), range.first);
         it != ids.end() && *it <= range.last; ++it) {
      if (std::find(range.excepted.begin(), range.excepted.end(), *it) != range.excepted.end())
        continue;
      members.push_back(*it);
      ++taken;
    }
    if (taken == 0)
      state.problems.error(range.place,
                           fmt::format("{} THRU {} selects no {}", range.first, range.last, target),
                           fmt::format("no {} has an id in this range", target));
  }
  std::sort(members.begin(), members.end());
  members.erase(std::unique(members.begin(), members.end()), members.end());
  return members;
}

void check_cross_references(ModelState& state) {
  StructureModel& model = state.model;
  std::vector<int> node_ids;
  node_ids.reserve(model.nodes.size());
  for (const auto& entry : model.nodes) node_ids.push_back(entry.first);
  std::vector<int> element_ids;
  element_ids.reserve(model.shells.size());
  for (const ShellElement& shell : model.shells) element_ids.push_back(shell.id);
  std::sort(element_ids.begin(), element_ids.end());

  for (auto& [set_id, list] : state.set_lists) {
    IdSet& set = model.sets.at(set_id);
    const bool grids = set.kind == SetKind::grid;
    set.members =
        resolve_list(state, list, grids ? node_ids : element_ids, grids ? "GRID" : "element",
                     grids ? state.grid_references : state.element_references);
  }
  for (auto& [surface_id, list] : state.surface_lists)
    model.surfaces.at(surface_id).elements =
        resolve_list(state, list, element_ids, "element", state.element_references);
  for (auto& [index, list] : state.spc1_lists) {
    SinglePointConstraint& constraint = model.constraints[index];
    constraint.nodes = resolve_list(state, list, node_ids, "GRID", state.grid_references);
  }

  check_references(state, state.grid_references, "GRID",
                   [&](int id) { return model.nodes.count(id) > 0; });
  check_references(
      state, state.property_references, "PSHELL",
      [&](int id) { return model.properties.count(id) > 0; }, state.refused_property_ids);
  check_references(
      state, state.material_references, "MAT1",
      [&](int id) { return model.materials.count(id) > 0; }, state.refused_material_ids);
  check_references(
      state, state.element_references, "element",
      [&](int id) { return state.element_index.count(id) > 0; }, state.refused_element_ids);
  check_references(state, state.surface_references, "SURF",
                   [&](int id) { return model.surfaces.count(id) > 0; });
  check_references(
      state, state.plasticity_references, "MAT1",
      [&](int id) { return model.materials.count(id) > 0; }, state.refused_material_ids);
  for (const auto& [material_id, plasticity] : state.plasticity)
    if (auto it = model.materials.find(material_id); it != model.materials.end())
      it->second.plasticity = plasticity;
}

// Settles the unit system: the model's declaration, else the caller's; they must agree.
std::optional<UnitSystem> settle_units(ModelState& state, const BulkDataOptions& options) {
  const auto name = [](UnitSystem system) {
    return system == UnitSystem::si ? "SI (m, kg, s)" : "mm, tonne, s (MPA)";
  };
  if (state.units && options.units && state.units->system != *options.units) {
    state.problems.error(
        state.units->place,
        fmt::format("the model declares {} ({}) but the deck states {}", name(state.units->system),
                    state.units->spelling, name(*options.units)),
        "state the same units in both, or only in one of them");
    return std::nullopt;
  }
  if (state.units) return state.units->system;
  if (options.units) return options.units;
  // A declaration that could not be read was reported where it stands.
  if (state.first_card && !state.units_stated)
    state.problems.error(*state.first_card, "the model does not declare its units",
                         "add `UNITS = SI` or `UNITS = MPA` (mm, tonne, s) before BEGIN BULK, "
                         "a card `DTI,UNITS,1,KG,N,M,S` (or MGG,N,MM,S), or state the units "
                         "in the deck");
  return std::nullopt;
}

// Converts every value of a model written in mm, tonne, s to SI: length 1e-3 m/mm, mass
// 1e3 kg/t, time 1 s/s, hence force 1 N/N, stress 1e6 Pa/MPa, density 1e12 (kg/m³)/(t/mm³),
// mass per area 1e9 (kg/m²)/(t/mm²).
void convert_to_si(StructureModel& model, UnitSystem units) {
  if (units == UnitSystem::si) return;
  constexpr double kLength = 1e-3;    // m per mm
  constexpr double kStress = 1e6;     // Pa per MPa (N/mm²)
  constexpr double kDensity = 1e12;   // (kg/m³) per (t/mm³)
  constexpr double kArealMass = 1e9;  // (kg/m²) per (t/mm²)
  for (auto& entry : model.nodes) entry.second.position *= kLength;
  for (auto& entry : model.properties) {
    ShellProperty& property = entry.second;
    property.thickness *= kLength;
    property.fiber_bottom *= kLength;
    property.fiber_top *= kLength;
    property.nonstructural_mass *= kArealMass;
  }
  for (auto& entry : model.materials) {
    IsotropicMaterial& material = entry.second;
    material.youngs_modulus *= kStress;
    material.shear_modulus *= kStress;
    material.density *= kDensity;
    if (material.plasticity) {
      material.plasticity->initial_yield_stress *= kStress;
      material.plasticity->hardening_modulus *= kStress;
    }
  }
  // EDEM PERIOD and FILTER are times: seconds in both systems.
}

StructureModel read_model(const std::string& text, const std::string& display_name,
                          const BulkDataOptions& options) {
  std::vector<std::string> files;
  Problems problems(files);
  ModelState state(problems);
  LexerEvents events;
  events.card = [&](const Card& card) { read_card(card, state); };
  events.units_statement = [&](const std::string& system, const Place& place) {
    read_units_statement(system, place, state);
  };
  lex_model(text, display_name, files, problems, events);
  state.model.source_files = files;

  report_card_tallies(state);
  check_cross_references(state);
  const std::optional<UnitSystem> units = settle_units(state, options);
  if (!state.first_card)
    problems.error(Place{0, 0, 0, 0}, "the model has no bulk data cards",
                   "a model needs GRID, CQUAD4/CTRIA3, PSHELL and MAT1 cards");
  else if (state.model.shells.empty())
    problems.error(*state.first_card, "the model has no CQUAD4 or CTRIA3 element");
  if (problems.has_errors()) throw UserError(problems.sorted(true, true, false));
  state.model.declared_units = *units;
  convert_to_si(state.model, *units);
  state.model.notes = problems.sorted(false, true, true);
  return std::move(state.model);
}

}  // namespace

}  // namespace bulk_detail

StructureModel read_bulk_data(const std::string& path, const BulkDataOptions& options) {
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw UserError({path, 0, 0}, "cannot open the model file",
                    "check the path; it is relative to the current directory");
  std::ostringstream text;
  text << in.rdbuf();
  return bulk_detail::read_model(text.str(), path, options);
}

StructureModel read_bulk_data_string(const std::string& text, const std::string& display_name,
                                     const BulkDataOptions& options) {
  return bulk_detail::read_model(text, display_name, options);
}

std::string default_coupling_label(int edem_id, int surface_id) {
  return fmt::format("coupling_{}_interface_{}", edem_id, surface_id);
}

}  // namespace quarry
