// Typed reads of a card's fields (FieldReader) and the card formats quoted in hints: fields as
// in the Nastran/OptiStruct manuals (MSC Nastran Quick Reference Guide; Altair OptiStruct
// Reference Guide). Each read reports a bad value at its field and lets the reader go on.
#include <fmt/format.h>

#include <algorithm>

#include "io/bulk_model.h"

namespace quarry::bulk_detail {

namespace {

const char* const kRealHint = "reals are written 1.5, 1.5E3, 7.85-9 (= 7.85E-9) or 2.1+5 (= 2.1E5)";
const char* const kSpilledHint =
    "a blank inside a field: fixed-format fields are 8 columns wide (16 in large format), so a "
    "value may have spilled into its neighbour's columns";

// The hint for a value that cannot be read: a blank inside it points at misaligned columns.
std::string unreadable_hint(const std::string& text, const std::string& otherwise) {
  return text.find(' ') != std::string::npos ? kSpilledHint : otherwise;
}

}  // namespace

std::string card_format(const std::string& name) {
  if (name == "GRID") return "GRID  ID  CP  X1  X2  X3  CD  PS  SEID";
  if (name == "CQUAD4") return "CQUAD4  EID  PID  G1  G2  G3  G4  THETA/MCID  ZOFFS";
  if (name == "CTRIA3") return "CTRIA3  EID  PID  G1  G2  G3  THETA/MCID  ZOFFS";
  if (name == "PSHELL")
    return "PSHELL  PID  MID1  T  MID2  12I/T**3  MID3  TS/T  NSM, then  Z1  Z2  MID4";
  if (name == "MAT1") return "MAT1  MID  E  G  NU  RHO  A  TREF  GE, then  ST  SC  SS  MCSID";
  if (name == "MATS1") return "MATS1  MID  TID  TYPE  H  YF  HR  LIMIT1  LIMIT2";
  if (name == "SPC") return "SPC  SID  G1  C1  D1  G2  C2  D2";
  if (name == "SPC1") return "SPC1  SID  C  G1  G2 ... (or G1 THRU G2)";
  if (name == "SET")
    return "SET  SID  TYPE  SUBTYPE, then the ids on continuation lines (THRU, EXCEPT, ENDTHRU)";
  if (name == "SURF")
    return "SURF  SRFID  ELFACE, then one line per element: EID  GA  GB  NORMAL (or SURF  SRFID  "
           "ELEM  LIST with the ids on continuation lines, as SET)";
  if (name == "EDEM")
    return "EDEM  ID, then  CONTROL  PERIOD  FILTER, then  COUPLING  TYPE  ID  LABEL";
  if (name == "DTI") return "DTI  UNITS  1  MASS  FORCE  LENGTH  TIME";
  if (name == "PARAM") return "PARAM  NAME  VALUE";
  return name;
}

FieldReader::FieldReader(const Card& card, ModelState& state) : card_(card), state_(state) {}

void FieldReader::error(std::size_t index, std::string message, std::string hint) {
  state_.problems.error(at(index).place, std::move(message), std::move(hint));
  ok_ = false;
}

void FieldReader::missing(std::size_t index, std::string_view what) {
  error(index, fmt::format("{} {} is missing", card_.name, what), card_format(card_.name));
}

std::optional<int> FieldReader::id(std::size_t index, std::string_view what, bool required) {
  const Field& field = at(index);
  if (field.blank()) {
    if (required) missing(index, what);
    return std::nullopt;
  }
  const std::optional<std::int64_t> value = parse_integer(field.text);
  if (!value || *value < 1 || *value > kMaxId) {
    error(index,
          fmt::format("{} {} must be an id (an integer from 1 to {}), got \"{}\"", card_.name, what,
                      kMaxId, field.text),
          unreadable_hint(field.text, card_format(card_.name)));
    return std::nullopt;
  }
  return static_cast<int>(*value);
}

std::optional<std::int64_t> FieldReader::integer(std::size_t index, std::string_view what) {
  const Field& field = at(index);
  if (field.blank()) return std::nullopt;
  const std::optional<std::int64_t> value = parse_integer(field.text);
  if (!value) {
    error(index, fmt::format("{} {} must be an integer, got \"{}\"", card_.name, what, field.text),
          unreadable_hint(field.text, card_format(card_.name)));
    return std::nullopt;
  }
  return value;
}

std::optional<double> FieldReader::real(std::size_t index, std::string_view what, bool required) {
  const Field& field = at(index);
  if (field.blank()) {
    if (required) missing(index, what);
    return std::nullopt;
  }
  const std::optional<double> value = parse_real(field.text);
  if (!value) {
    error(index,
          fmt::format("{} {} must be a real number, got \"{}\"", card_.name, what, field.text),
          unreadable_hint(field.text, kRealHint));
    return std::nullopt;
  }
  return value;
}

std::optional<DofSet> FieldReader::dofs(std::size_t index, std::string_view what, bool required,
                                        bool zero_allowed) {
  const Field& field = at(index);
  if (field.blank()) {
    if (required) missing(index, what);
    return std::nullopt;
  }
  if (zero_allowed && field.text == "0") return DofSet{};
  DofSet set;
  bool valid = !field.text.empty();
  for (const char c : field.text) {
    const int dof = c - '0';
    if (dof < 1 || dof > 6 || set.has(dof)) {
      valid = false;
      break;
    }
    set.add(dof);
  }
  if (!valid) {
    error(index,
          fmt::format("{} {} must be a code of DOFs 1-6 (such as 123456), got \"{}\"", card_.name,
                      what, field.text),
          "1-3 are the translations along x, y, z and 4-6 the rotations about them, each digit "
          "at most once");
    return std::nullopt;
  }
  return set;
}

void FieldReader::reject_from(std::size_t first, std::size_t end) {
  for (std::size_t i = first; i < std::min(end, card_.fields.size()); ++i) {
    if (card_.fields[i].blank()) continue;
    error(i,
          fmt::format("{} has no field here: \"{}\" would not be read", card_.name,
                      card_.fields[i].text),
          card_format(card_.name));
    return;
  }
}

}  // namespace quarry::bulk_detail
