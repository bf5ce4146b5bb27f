// State of one bulk data read and the card readers (io/bulk_data*.cpp only). Cards are read as
// the lexer delivers them; references between cards (element -> grid, SURF -> element, ...) and
// the unit conversion wait until every card is known (bulk_data.cpp).
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "core/structure_model.h"
#include "io/bulk_fields.h"

namespace quarry::bulk_detail {

// Largest id a Nastran card may carry (OptiStruct: fixed format holds -9,999,999..99,999,999).
constexpr std::int64_t kMaxId = 99999999;

// A reference from a field to an entity of another card, checked once every card is read.
struct Reference {
  int id = 0;
  Place place;            // the referencing field
  std::string_view card;  // the referencing card's name (static text), for messages
  int owner = 0;          // the referencing card's id
};

// A THRU range of an id list, with the ids its EXCEPT list removes.
struct IdRange {
  int first = 0;
  int last = 0;
  std::vector<int> excepted;
  Place place;
};

// The ids of a SET, SURF or SPC1: ids given one by one must exist; a THRU range takes the ids
// in it that exist (as Nastran's SPC1 and SET ranges do) and must take at least one.
struct IdList {
  std::vector<Reference> ids;
  std::vector<IdRange> ranges;
};

// How often a card name was met and where first, for one message per name.
struct CardTally {
  Place first;
  int count = 0;
};

// The unit system the file declares, and where.
struct UnitsDeclaration {
  UnitSystem system = UnitSystem::si;
  Place place;
  std::string spelling;  // as written, for messages ("UNITS = MPA", "DTI,UNITS KG N M S")
};

struct ModelState {
  explicit ModelState(Problems& problems_) : problems(problems_) {}

  Problems& problems;
  StructureModel model;  // values in the file's units until bulk_data.cpp converts them
  std::unordered_map<int, std::size_t> element_index;  // element id -> index in model.shells
  std::map<int, J2Plasticity> plasticity;              // MATS1 by MID, attached at the end
  std::map<int, CardLocation> set_or_surface_ids;      // SET and SURF share their ids

  std::vector<Reference> grid_references;
  std::vector<Reference> property_references;
  std::vector<Reference> material_references;
  std::vector<Reference> element_references;
  std::vector<Reference> surface_references;
  std::vector<Reference> plasticity_references;  // MATS1 -> MAT1 (by the MATS1's MID)
  // Id lists resolved at the end: SET members, SURF elements, SPC1 grid points.
  std::vector<std::pair<int, IdList>> set_lists;           // SET id
  std::vector<std::pair<int, IdList>> surface_lists;       // SURF id
  std::vector<std::pair<std::size_t, IdList>> spc1_lists;  // index into model.constraints

  std::optional<UnitsDeclaration> units;
  bool units_stated = false;  // a UNITS or DTI,UNITS was met (even one that is wrong)
  std::optional<Place> first_card;
  std::map<std::string, CardTally> ignored_cards;
  std::map<std::string, CardTally> refused_cards;
  std::map<std::string, CardTally> unknown_cards;
  // Ids of refused cards that other cards may name (a PCOMP, a CBEAM, a MAT8): a reference
  // to one is not reported again as a missing PSHELL, element or MAT1.
  std::set<int> refused_property_ids;
  std::set<int> refused_element_ids;
  std::set<int> refused_material_ids;

  CardLocation location(const Place& place) const { return {place.file, place.line}; }
  // "first defined at file:line", for duplicate ids.
  std::string first_defined(const CardLocation& location) const;
  // Records the declaration and reports a second one that disagrees.
  void declare_units(UnitSystem system, const Place& place, std::string spelling);
  // Counts a card that is read but not used (listed in the model's notes), under `name`.
  void ignore(const std::string& name, const Place& place);
};

// Typed reads of one card's fields (bulk_field_reader.cpp): each reports a bad value at its field
// (with the card's format as hint) and returns nullopt, so that a reader goes on and every error is
// reported.
class FieldReader {
 public:
  FieldReader(const Card& card, ModelState& state);

  const Card& card() const { return card_; }
  const Field& at(std::size_t index) const { return card_.at(index); }
  bool blank(std::size_t index) const { return card_.at(index).blank(); }
  std::string word(std::size_t index) const { return upper(card_.at(index).text); }
  bool ok() const { return ok_; }

  void error(std::size_t index, std::string message, std::string hint = {});
  void missing(std::size_t index, std::string_view what);
  // An id: an integer from 1 to 99,999,999. Blank: nullopt, reported when `required`.
  std::optional<int> id(std::size_t index, std::string_view what, bool required = true);
  std::optional<std::int64_t> integer(std::size_t index, std::string_view what);
  std::optional<double> real(std::size_t index, std::string_view what, bool required = false);
  // A DOF code (digits 1-6, each at most once). "0" is no DOF when `zero_allowed`.
  std::optional<DofSet> dofs(std::size_t index, std::string_view what, bool required,
                             bool zero_allowed);
  // Reports the first non-blank field at index `first` or later (before `end`): the card has
  // no such field.
  void reject_from(std::size_t first, std::size_t end = static_cast<std::size_t>(-1));

 private:
  const Card& card_;
  ModelState& state_;
  bool ok_ = true;
};

// The name of a supported card as static text (for references that outlive the card).
std::string_view static_card_name(const std::string& name);

// The fields of a card as its manual writes them, for hints ("GRID ID CP X1 X2 X3 CD PS SEID").
std::string card_format(const std::string& name);

// bulk_cards.cpp and bulk_sets.cpp (SPC1, SET, SURF): one reader per supported card. Each
// reports its errors and adds what it could read to the state.
void read_grid(const Card& card, ModelState& state);
void read_shell_element(const Card& card, ModelState& state);  // CQUAD4, CTRIA3
void read_pshell(const Card& card, ModelState& state);
void read_mat1(const Card& card, ModelState& state);
void read_mats1(const Card& card, ModelState& state);
void read_spc(const Card& card, ModelState& state);
void read_spc1(const Card& card, ModelState& state);
void read_set(const Card& card, ModelState& state);
void read_surf(const Card& card, ModelState& state);
void read_dti(const Card& card, ModelState& state);
void read_param(const Card& card, ModelState& state);
// bulk_edem.cpp
void read_edem(const Card& card, ModelState& state);

// Reads the units named by OptiStruct's `UNITS = <system>` statement.
void read_units_statement(const std::string& system, const Place& place, ModelState& state);

// Reads the id list in data fields [first, end of card) with THRU and, when allowed, EXCEPT and
// ENDTHRU; `owner` is the card's id, for messages.
IdList read_id_list(const Card& card, std::size_t first, bool allow_except, int owner,
                    ModelState& state);

}  // namespace quarry::bulk_detail
