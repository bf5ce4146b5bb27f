// Lexer of Nastran/OptiStruct bulk data for the model reader (io/bulk_data*.cpp only): splits the
// lines of a model and its INCLUDEd files into cards of located fields — fixed 8-column, large
// 16-column (`*`) and free (comma) formats, continuation lines, comments — and reads Nastran
// numbers (1.-3, 7.85-9, 2.1+5). Formats as in OptiStruct's "Bulk Data Guidelines" (docs/fem.md).
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/diagnostics.h"

namespace quarry::bulk_detail {

// A position in the files of one model. `ordinal` counts physical lines over all files in the
// order they are read, so that diagnostics from several files sort in reading order.
struct Place {
  std::int32_t file = -1;  // index into the reader's list of files
  std::int32_t line = 0;
  std::int32_t column = 0;
  std::int32_t ordinal = 0;
};

// The diagnostics of one model read. sorted() returns them in reading order (then column), so
// the first line printed is the first mistake met reading the files top to bottom.
class Problems {
 public:
  explicit Problems(const std::vector<std::string>& files) : files_(files) {}
  void error(const Place& place, std::string message, std::string hint = {});
  void warning(const Place& place, std::string message, std::string hint = {});
  void note(const Place& place, std::string message, std::string hint = {});
  bool has_errors() const { return error_count_ > 0; }
  SourceLocation location(const Place& place) const;
  // All items of the given severities, in reading order.
  Diagnostics sorted(bool with_errors, bool with_warnings, bool with_notes) const;

 private:
  struct Item {
    Severity severity;
    Place place;
    std::string message;
    std::string hint;
  };
  const std::vector<std::string>& files_;
  std::vector<Item> items_;
  int error_count_ = 0;
};

struct Field {
  std::string text;  // without surrounding blanks; empty = a blank field
  Place place;       // its first character, or where the field starts when it is blank
  bool blank() const { return text.empty(); }
};

// One bulk data entry with its continuation lines. Data fields are numbered from 0 = field 2 of
// the first line: a small-field line gives 8 of them (fields 2-9), a large-field line 4, so the
// data of continuation line k starts at 8k whichever format each line used.
struct Card {
  std::string name;  // upper case, without a large-field '*'
  Place place;       // of the name
  std::vector<Field> fields;
  Field missing;  // what at() gives past the last field: blank, placed at the name

  const Field& at(std::size_t index) const {
    return index < fields.size() ? fields[index] : missing;
  }
  // Data index of Nastran field `field` (2-9) on line `line` (0 = the first line).
  static constexpr std::size_t index(int line, int field) {
    return static_cast<std::size_t>(8 * line + field - 2);
  }
};

struct LexerEvents {
  std::function<void(const Card&)> card;
  // `UNITS = <system>` in the I/O options or subcase sections (before BEGIN BULK); `place` is
  // where the system is written (an empty word when none is).
  std::function<void(const std::string& system, const Place& place)> units_statement;
};

// Reads `text`, the model named `display_name`, and every file it INCLUDEs (paths relative to
// the folder of the including file). When the text has a BEGIN BULK line, what comes before it
// is the executive and case control part: only UNITS statements are read there. Reading stops
// at ENDDATA. `files` receives the name of each file read (Place::file indexes it).
void lex_model(const std::string& text, const std::string& display_name,
               std::vector<std::string>& files, Problems& problems, const LexerEvents& events);

// A Nastran real: [sign] digits with at most one '.', then an optional exponent written as
// E/D [sign] digits or, after a mantissa with a '.', as a bare sign and digits (7.85-9 =
// 7.85e-9, 2.1+5 = 2.1e5). An integer is accepted as a real. nullopt if not such a number or
// not finite.
std::optional<double> parse_real(std::string_view text);
// A decimal integer with an optional sign; nullopt otherwise (or out of the int64 range).
std::optional<std::int64_t> parse_integer(std::string_view text);

// Upper-case copy (ASCII), for card names and keywords.
std::string upper(std::string_view text);

}  // namespace quarry::bulk_detail
