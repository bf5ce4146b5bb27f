// Readers of the cards that list ids: SPC1, SET and SURF, with Nastran's THRU, EXCEPT and
// ENDTHRU (OptiStruct Reference Guide, SET and SURF; MSC Nastran QRG, SPC1). The lists are
// resolved against the defined grids and elements once every card is read (bulk_data.cpp).
#include <fmt/format.h>

#include <algorithm>

#include "io/bulk_model.h"

namespace quarry::bulk_detail {

namespace {

// True if a field at index `first` or later holds something (read_id_list reports what it
// cannot read; an empty list is reported only when there was nothing to read).
bool has_values_from(const Card& card, std::size_t first) {
  for (std::size_t i = first; i < card.fields.size(); ++i)
    if (!card.fields[i].blank()) return true;
  return false;
}

}  // namespace

void read_spc1(const Card& card, ModelState& state) {
  FieldReader fields(card, state);
  const std::optional<int> set = fields.id(0, "SID");
  const std::optional<DofSet> dofs = fields.dofs(1, "C", true, false);
  IdList list = read_id_list(card, 2, false, set.value_or(0), state);
  if (list.ids.empty() && list.ranges.empty() && !has_values_from(card, 2)) {
    fields.error(2, "SPC1 lists no grid point", card_format(card.name));
    return;
  }
  if (!set || !dofs) return;
  SinglePointConstraint constraint;
  constraint.set_id = *set;
  constraint.dofs = *dofs;
  constraint.where = state.location(card.place);
  state.spc1_lists.emplace_back(state.model.constraints.size(), std::move(list));
  state.model.constraints.push_back(std::move(constraint));
}

IdList read_id_list(const Card& card, std::size_t first, bool allow_except, int owner,
                    ModelState& state) {
  IdList list;
  FieldReader fields(card, state);
  bool previous_is_id = false;  // the last item read is a single id (a THRU may follow)
  bool after_range = false;     // the last item is a range (an EXCEPT may follow)
  bool excepting = false;       // in the EXCEPT list of the last range
  const bool grids = card.name == "SPC1";
  for (std::size_t i = first; i < card.fields.size(); ++i) {
    const Field& field = card.fields[i];
    if (field.blank()) continue;
    const std::string word = upper(field.text);
    if (word == "THRU") {
      std::size_t next = i + 1;
      while (next < card.fields.size() && card.fields[next].blank()) ++next;
      if (!previous_is_id) {
        fields.error(i, fmt::format("{} THRU needs an id before it", card.name));
        continue;
      }
      previous_is_id = false;
      if (next >= card.fields.size()) {
        fields.error(i, fmt::format("{} THRU needs an id after it", card.name));
        continue;
      }
      const std::optional<int> last = fields.id(next, "THRU end");
      i = next;
      if (!last) continue;
      const Reference start = list.ids.back();
      list.ids.pop_back();
      if (*last < start.id) {
        fields.error(next, fmt::format("{} range {} THRU {} goes down", card.name, start.id, *last),
                     "write the smaller id first");
        continue;
      }
      list.ranges.push_back(IdRange{start.id, *last, {}, start.place});
      after_range = true;
      excepting = false;
      continue;
    }
    if (word == "EXCEPT" || word == "ENDTHRU") {
      if (!allow_except)
        fields.error(i, fmt::format("{} does not take {}", card.name, word),
                     card_format(card.name));
      else if (word == "EXCEPT" && !after_range)
        fields.error(i, fmt::format("{} EXCEPT needs a THRU range before it", card.name));
      else if (word == "ENDTHRU" && !excepting)
        fields.error(i, fmt::format("{} ENDTHRU without EXCEPT before it", card.name));
      excepting = word == "EXCEPT" && after_range;
      after_range = false;
      previous_is_id = false;
      continue;
    }
    if (word == "ALL") {
      fields.error(i, fmt::format("{} ALL is not supported", card.name),
                   "list the ids, with THRU for ranges");
      continue;
    }
    const std::optional<std::int64_t> value = parse_integer(field.text);
    if (!value || *value < 1 || *value > kMaxId) {
      fields.error(i,
                   fmt::format("{} {} must be {} (an integer from 1 to {}) or THRU{}, got "
                               "\"{}\"",
                               card.name, grids ? "G" : "ID", grids ? "a grid id" : "an id", kMaxId,
                               allow_except ? ", EXCEPT, ENDTHRU" : "", field.text),
                   card_format(card.name));
      previous_is_id = false;
      continue;
    }
    const int id = static_cast<int>(*value);
    if (excepting) {
      IdRange& range = list.ranges.back();
      if (id >= range.first && id <= range.last) {
        range.excepted.push_back(id);
        continue;
      }
      excepting = false;  // an id outside the range ends the EXCEPT list and is listed
    }
    list.ids.push_back(Reference{id, field.place, static_card_name(card.name), owner});
    previous_is_id = true;
    after_range = false;
  }
  return list;
}

void read_set(const Card& card, ModelState& state) {
  FieldReader fields(card, state);
  const std::optional<int> id = fields.id(0, "SID");
  const std::string type = fields.word(1);
  SetKind kind = SetKind::grid;
  if (type == "GRID") {
    kind = SetKind::grid;
  } else if (type == "ELEM") {
    kind = SetKind::element;
  } else if (type.empty()) {
    fields.missing(1, "TYPE");
  } else {
    // Sets of properties, design variables, modes, frequencies, ... select nothing Quarry
    // reads; listed as ignored.
    state.ignore(fmt::format("SET of TYPE {}", type), card.place);
    return;
  }
  const std::string subtype = fields.word(2);
  if (!subtype.empty() && subtype != "LIST")
    fields.error(2, fmt::format("SET SUBTYPE {} is not supported", fields.at(2).text),
                 "SUBTYPE LIST (or blank), with the ids on the continuation lines");
  for (std::size_t i = 3; i < Card::index(1, 2); ++i) {
    if (fields.blank(i)) continue;
    fields.error(i, "SET ids start on the continuation line", card_format(card.name));
    break;
  }
  IdList list = read_id_list(card, Card::index(1, 2), true, id.value_or(0), state);
  if (list.ids.empty() && list.ranges.empty() && !has_values_from(card, Card::index(1, 2)))
    fields.error(0, fmt::format("SET {} lists no ids", id.value_or(0)), card_format(card.name));
  if (!id) return;
  const auto [entry, inserted] =
      state.set_or_surface_ids.try_emplace(*id, state.location(card.place));
  if (!inserted) {
    fields.error(0, fmt::format("duplicate SET id {} (SET and SURF ids share one range)", *id),
                 state.first_defined(entry->second));
    return;
  }
  IdSet set;
  set.id = *id;
  set.kind = kind;
  set.where = state.location(card.place);
  state.model.sets.emplace(*id, std::move(set));
  state.set_lists.emplace_back(*id, std::move(list));
}

void read_surf(const Card& card, ModelState& state) {
  FieldReader fields(card, state);
  const std::optional<int> id = fields.id(0, "SRFID");
  const std::string form = fields.word(1);
  IdList list;
  if (form == "ELFACE") {
    fields.reject_from(2, Card::index(1, 2));  // the element lines follow
    for (int line = 1; Card::index(line, 2) < card.fields.size(); ++line) {
      const std::size_t eid = Card::index(line, 2);
      if (!fields.blank(eid + 1) || !fields.blank(eid + 2))
        fields.error(fields.blank(eid + 1) ? eid + 2 : eid + 1,
                     "SURF GA and GB select a face of a solid element; leave them blank for "
                     "shells");
      if (!fields.blank(eid + 3))
        fields.error(eid + 3, "SURF NORMAL is not supported",
                     "leave it blank: particles meet a coupled shell on both of its faces");
      for (std::size_t rest = eid + 4; rest < Card::index(line + 1, 2); ++rest) {
        if (fields.blank(rest)) continue;
        fields.error(rest, "SURF ELFACE lines hold EID  GA  GB  NORMAL only",
                     card_format(card.name));
        break;
      }
      if (fields.blank(eid)) continue;
      if (const std::optional<int> element = fields.id(eid, "EID"))
        list.ids.push_back(
            Reference{*element, fields.at(eid).place, static_card_name(card.name), id.value_or(0)});
    }
  } else if (form == "ELEM") {
    const std::string subtype = fields.word(2);
    if (!subtype.empty() && subtype != "LIST")
      fields.error(2, fmt::format("SURF SUBTYPE {} is not supported", fields.at(2).text),
                   "SUBTYPE LIST (or blank), with the ids on the continuation lines");
    for (std::size_t i = 3; i < Card::index(1, 2); ++i) {
      if (fields.blank(i)) continue;
      fields.error(i, "SURF ids start on the continuation line", card_format(card.name));
      break;
    }
    list = read_id_list(card, Card::index(1, 2), true, id.value_or(0), state);
  } else if (form == "FACE") {
    fields.error(1, "SURF FACE (a surface of grid facets) is not supported",
                 "define the coupling surface by shell elements: SURF ELFACE or SURF ELEM");
    return;
  } else if (form.empty()) {
    fields.missing(1, "ELFACE or ELEM");
    return;
  } else {
    fields.error(1, fmt::format("unknown SURF form \"{}\"", fields.at(1).text),
                 "ELFACE (one line per element) or ELEM (ids as on a SET)");
    return;
  }
  if (list.ids.empty() && list.ranges.empty() && !has_values_from(card, Card::index(1, 2)))
    fields.error(0, fmt::format("SURF {} lists no element", id.value_or(0)),
                 card_format(card.name));
  if (!id) return;
  const auto [entry, inserted] =
      state.set_or_surface_ids.try_emplace(*id, state.location(card.place));
  if (!inserted) {
    fields.error(0, fmt::format("duplicate SURF id {} (SET and SURF ids share one range)", *id),
                 state.first_defined(entry->second));
    return;
  }
  Surface surface;
  surface.id = *id;
  surface.where = state.location(card.place);
  state.model.surfaces.emplace(*id, std::move(surface));
  state.surface_lists.emplace_back(*id, std::move(list));
}

}  // namespace quarry::bulk_detail
