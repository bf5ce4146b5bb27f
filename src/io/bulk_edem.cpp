// The OptiStruct EDEM card (seed 000) and the unit declarations (UNITS = ..., DTI,UNITS).
// EDEM fields: ID; a CONTROL flag followed by PERIOD and FILTER; one COUPLING flag per coupling
// surface followed by TYPE (SURF), ID and LABEL. The flags are read wherever they stand after
// the ID — on the first line (the seed's example, "EDEM 100 CONTROL 0.1 0.15 COUPLING SURF 2
// Surf_2") or each on its own continuation line (the manual's table) — and a flag's values
// are the fields after it, up to the next flag.
#include <fmt/format.h>

#include <algorithm>
#include <optional>
#include <vector>

#include "io/bulk_model.h"

namespace quarry::bulk_detail {

namespace {

bool is_flag(const std::string& word) {
  return word == "CONTROL" || word == "COUPLING";
}

// The indices of the (up to) `count` value fields after the flag at `flag`, stopping before
// the next flag. Indices past the card's end stand for blank fields.
std::vector<std::size_t> values_after(const FieldReader& fields, std::size_t flag,
                                      std::size_t count) {
  std::vector<std::size_t> indices;
  for (std::size_t i = flag + 1; i <= flag + count; ++i) {
    if (is_flag(fields.word(i))) break;
    indices.push_back(i);
  }
  return indices;
}

// True if the field at `index` continues the LABEL just before it: a fixed-format LABEL that
// fills its 8 columns with the next field's text starting in the very next column.
bool runs_on_from_label(const FieldReader& fields, std::size_t index,
                        const std::optional<std::size_t>& label_index) {
  if (!label_index || *label_index + 1 != index) return false;
  const Field& label = fields.at(*label_index);
  const Field& next = fields.at(index);
  constexpr int kFixedFieldWidth = 8;  // columns
  return label.text.size() == kFixedFieldWidth && next.place.line == label.place.line &&
         next.place.column == label.place.column + kFixedFieldWidth;
}

}  // namespace

void read_edem(const Card& card, ModelState& state) {
  FieldReader fields(card, state);
  const std::size_t end = card.fields.size();
  // A missing value is reported at the flag that asks for it when the card ends before it.
  const auto missing_at = [&](std::size_t index, std::size_t flag) {
    return index < end ? index : flag;
  };
  EdemCoupling coupling;
  const std::optional<int> id = fields.id(0, "ID");
  bool control_seen = false;
  std::optional<std::size_t> label_index;  // the last LABEL read
  std::vector<Reference> surfaces;
  for (std::size_t i = 1; i < end;) {
    if (fields.blank(i)) {
      ++i;
      continue;
    }
    const std::string word = fields.word(i);
    if (word == "CONTROL") {
      if (control_seen) fields.error(i, "EDEM CONTROL is given twice", card_format(card.name));
      control_seen = true;
      const std::vector<std::size_t> values = values_after(fields, i, 2);
      // PERIOD: <blank, 0 < real < TTERM>; FILTER: <blank, real > PERIOD> (seed 000). TTERM
      // is the run's end time, which the deck knows: the coupling checks PERIOD < TTERM.
      if (values.size() >= 1) {
        coupling.period = fields.real(values[0], "PERIOD");
        if (coupling.period && !(*coupling.period > 0.0)) {
          fields.error(values[0],
                       fmt::format("EDEM PERIOD must be > 0, got {}", fields.at(values[0]).text),
                       "leave PERIOD blank for the default, TTERM/100");
          coupling.period.reset();
        }
      }
      if (values.size() >= 2) {
        coupling.filter = fields.real(values[1], "FILTER");
        if (coupling.filter && coupling.period && !(*coupling.filter > *coupling.period)) {
          fields.error(values[1],
                       fmt::format("EDEM FILTER must be > PERIOD ({}), got {}",
                                   fields.at(values[0]).text, fields.at(values[1]).text),
                       "leave FILTER blank to smooth the forces over one PERIOD");
          coupling.filter.reset();
        } else if (coupling.filter && !(*coupling.filter > 0.0)) {
          fields.error(values[1],
                       fmt::format("EDEM FILTER must be > 0, got {}", fields.at(values[1]).text));
          coupling.filter.reset();
        }
      }
      i += 1 + values.size();
    } else if (word == "COUPLING") {
      const std::vector<std::size_t> values = values_after(fields, i, 3);
      const std::size_t flag = i;
      CouplingSurfaceRef surface;
      surface.where = state.location(fields.at(flag).place);
      const std::string type = values.size() >= 1 ? fields.word(values[0]) : std::string();
      bool valid = true;
      if (type.empty()) {
        fields.error(values.size() >= 1 ? missing_at(values[0], flag) : flag,
                     "EDEM COUPLING TYPE is missing",
                     "TYPE SURF: the coupling surface is a SURF, named by its id");
        valid = false;
      } else if (type != "SURF") {
        fields.error(
            values[0],
            fmt::format("EDEM COUPLING TYPE must be SURF, got \"{}\"", fields.at(values[0]).text),
            "SURF is the only entity type of the EDEM card");
        valid = false;
      }
      std::optional<int> surface_id;
      if (values.size() >= 2 && values[1] < end && !fields.blank(values[1]))
        surface_id = fields.id(values[1], "COUPLING ID");
      else
        fields.error(values.size() >= 2 ? missing_at(values[1], flag) : flag,
                     "EDEM COUPLING ID is missing", "the id of the SURF to couple");
      if (values.size() >= 3 && !fields.blank(values[2])) {
        surface.label = fields.at(values[2]).text;
        label_index = values[2];
      }
      if (valid && surface_id) {
        surface.surface_id = *surface_id;
        const bool repeated = std::any_of(
            coupling.surfaces.begin(), coupling.surfaces.end(),
            [&](const CouplingSurfaceRef& other) { return other.surface_id == *surface_id; });
        if (repeated)
          fields.error(values[1], fmt::format("EDEM couples SURF {} twice", *surface_id));
        else
          coupling.surfaces.push_back(surface);
        surfaces.push_back(Reference{*surface_id, fields.at(values[1]).place,
                                     static_card_name(card.name), id.value_or(0)});
      }
      i += 1 + values.size();
    } else if (runs_on_from_label(fields, i, label_index)) {
      fields.error(i,
                   fmt::format("EDEM LABEL \"{}\" runs on into the next field (\"{}\")",
                               fields.at(i - 1).text, fields.at(i).text),
                   "a fixed-format field holds 8 characters: write a longer LABEL in free "
                   "format (commas) or large-field format (16 characters)");
      ++i;
    } else {
      fields.error(i,
                   fmt::format("expected CONTROL or COUPLING in the EDEM card, got \"{}\"",
                               fields.at(i).text),
                   card_format(card.name));
      ++i;
    }
  }
  if (coupling.surfaces.empty() && fields.ok())
    fields.error(0, fmt::format("EDEM {} has no COUPLING line", id.value_or(0)),
                 "add a line  COUPLING  SURF  <surf id>  <label>  naming the coupling surface");
  if (!id) return;
  const auto repeated = std::find_if(state.model.couplings.begin(), state.model.couplings.end(),
                                     [&](const EdemCoupling& other) { return other.id == *id; });
  if (repeated != state.model.couplings.end()) {
    fields.error(0, fmt::format("duplicate EDEM id {}", *id), state.first_defined(repeated->where));
    return;
  }
  coupling.id = *id;
  coupling.where = state.location(card.place);
  state.model.couplings.push_back(std::move(coupling));
  state.surface_references.insert(state.surface_references.end(), surfaces.begin(), surfaces.end());
}

void read_dti(const Card& card, ModelState& state) {
  FieldReader fields(card, state);
  if (fields.word(0) != "UNITS") {
    state.ignore("DTI", card.place);
    return;
  }
  state.units_stated = true;
  const char* const names[] = {"MASS", "FORCE", "LENGTH", "TIME"};
  std::string words[4];
  bool complete = true;
  for (std::size_t k = 0; k < 4; ++k) {
    words[k] = fields.word(2 + k);
    if (!words[k].empty()) continue;
    fields.error(2 + k, fmt::format("DTI,UNITS {} is missing", names[k]),
                 "state all four units: OptiStruct's defaults (kg, N, mm, s) are not a "
                 "consistent set, so Quarry does not assume them");
    complete = false;
  }
  fields.reject_from(6);
  if (!complete) return;
  const std::string spelling =
      fmt::format("DTI,UNITS {} {} {} {}", words[0], words[1], words[2], words[3]);
  const auto is = [&](const char* mass, const char* force, const char* length, const char* time) {
    return words[0] == mass && words[1] == force && words[2] == length && words[3] == time;
  };
  if (is("KG", "N", "M", "S"))
    state.declare_units(UnitSystem::si, fields.at(2).place, spelling);
  else if (is("MGG", "N", "MM", "S"))
    state.declare_units(UnitSystem::mm_tonne_second, fields.at(2).place, spelling);
  else
    fields.error(
        2,
        fmt::format("unsupported unit system {} {} {} {}", words[0], words[1], words[2], words[3]),
        "Quarry reads KG N M S (SI) and MGG N MM S (mm, tonne, s)");
}

void read_units_statement(const std::string& system, const Place& place, ModelState& state) {
  state.units_stated = true;
  const std::string word = upper(system);
  const char* const hint = "UNITS = SI (m, kg, s) or UNITS = MPA (mm, tonne, s)";
  if (word == "SI")
    state.declare_units(UnitSystem::si, place, "UNITS = SI");
  else if (word == "MPA")
    state.declare_units(UnitSystem::mm_tonne_second, place, "UNITS = MPA");
  else if (word.empty())
    state.problems.error(place, "UNITS names no unit system", hint);
  else if (word == "CGS" || word == "BG")
    state.problems.error(place, fmt::format("UNITS = {} is not supported", word), hint);
  else
    state.problems.error(place, fmt::format("unknown unit system \"{}\"", system), hint);
}

}  // namespace quarry::bulk_detail
