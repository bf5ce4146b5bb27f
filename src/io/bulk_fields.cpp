// Lexer of bulk data: lines -> cards of located fields. From OptiStruct's "Bulk Data
// Guidelines" (2021): a comma in the first 10 characters makes a line free format; a '*' after
// the card name or at the start of a continuation line makes it large-field (16-column fields,
// two half-lines per line of 8 fields); a line starting with a blank, '+' or '*' continues the
// card above; characters after column 80 of a fixed-format line are ignored; tabs are not
// allowed. As in MSC Nastran: '$' starts a comment and a free-format line may also start with
// ',' (an empty field 1) to continue. Quarry also skips blank lines and lines starting with
// '//' or '#'.
#include "io/bulk_fields.h"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

namespace quarry::bulk_detail {

namespace fs = std::filesystem;

void Problems::error(const Place& place, std::string message, std::string hint) {
  items_.push_back({Severity::error, place, std::move(message), std::move(hint)});
  ++error_count_;
}

void Problems::warning(const Place& place, std::string message, std::string hint) {
  items_.push_back({Severity::warning, place, std::move(message), std::move(hint)});
}

void Problems::note(const Place& place, std::string message, std::string hint) {
  items_.push_back({Severity::note, place, std::move(message), std::move(hint)});
}

SourceLocation Problems::location(const Place& place) const {
  if (place.file < 0 || place.file >= static_cast<std::int32_t>(files_.size())) return {};
  return {files_[static_cast<std::size_t>(place.file)], place.line, place.column};
}

Diagnostics Problems::sorted(bool with_errors, bool with_warnings, bool with_notes) const {
  std::vector<const Item*> chosen;
  for (const Item& item : items_) {
    const bool wanted = (item.severity == Severity::error && with_errors) ||
                        (item.severity == Severity::warning && with_warnings) ||
                        (item.severity == Severity::note && with_notes);
    if (wanted) chosen.push_back(&item);
  }
  // Items without a line (ordinal 0) go last.
  const auto key = [](const Item* item) {
    const std::int64_t ordinal =
        item->place.ordinal > 0 ? item->place.ordinal : std::numeric_limits<std::int64_t>::max();
    return std::make_pair(ordinal, item->place.column);
  };
  std::stable_sort(chosen.begin(), chosen.end(),
                   [&](const Item* a, const Item* b) { return key(a) < key(b); });
  Diagnostics result;
  for (const Item* item : chosen) {
    switch (item->severity) {
      case Severity::error:
        result.error(location(item->place), item->message, item->hint);
        break;
      case Severity::warning:
        result.warning(location(item->place), item->message, item->hint);
        break;
      case Severity::note:
        result.note(location(item->place), item->message, item->hint);
        break;
    }
  }
  return result;
}

std::string upper(std::string_view text) {
  std::string result(text);
  for (char& c : result)
    if (c >= 'a' && c <= 'z') c = static_cast<char>(c - 'a' + 'A');
  return result;
}

namespace {

bool is_digit(char c) {
  return c >= '0' && c <= '9';
}

bool is_blank(char c) {
  return c == ' ' || c == '\t';
}

}  // namespace

std::optional<double> parse_real(std::string_view text) {
  std::size_t i = 0;
  std::string normal;  // rewritten as C syntax for from_chars
  if (i < text.size() && (text[i] == '+' || text[i] == '-')) {
    if (text[i] == '-') normal += '-';
    ++i;
  }
  int digits = 0;
  bool point = false;
  while (i < text.size() && (is_digit(text[i]) || (text[i] == '.' && !point))) {
    if (text[i] == '.')
      point = true;
    else
      ++digits;
    normal += text[i++];
  }
  if (digits == 0) return std::nullopt;
  if (i < text.size()) {
    const char marker = text[i];
    if (marker == 'E' || marker == 'e' || marker == 'D' || marker == 'd') {
      ++i;
    } else if ((marker == '+' || marker == '-') && point) {
      // Nastran's shorthand: the sign itself starts the exponent.
    } else {
      return std::nullopt;
    }
    normal += 'e';
    if (i < text.size() && (text[i] == '+' || text[i] == '-')) normal += text[i++];
    int exponent_digits = 0;
    while (i < text.size() && is_digit(text[i])) {
      normal += text[i++];
      ++exponent_digits;
    }
    if (exponent_digits == 0 || i != text.size()) return std::nullopt;
  }
  double value = 0.0;
  const auto [end, error] = std::from_chars(normal.data(), normal.data() + normal.size(), value);
  if (error != std::errc() || end != normal.data() + normal.size() || !std::isfinite(value))
    return std::nullopt;
  return value;
}

std::optional<std::int64_t> parse_integer(std::string_view text) {
  if (!text.empty() && text.front() == '+') text.remove_prefix(1);
  if (text.empty() || text.front() == '+') return std::nullopt;
  std::int64_t value = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc() || end != text.data() + text.size()) return std::nullopt;
  return value;
}

namespace {

constexpr int kFixedLineLength = 80;  // columns read in fixed format; the rest is ignored
constexpr int kMaxIncludeDepth = 16;

// The field [begin, begin + width) of a fixed-format line, trimmed and placed.
Field fixed_field(std::string_view line, int begin, int width, Place place) {
  const int size = static_cast<int>(line.size());
  const int end = std::min(size, begin + width);
  int first = begin;
  while (first < end && line[static_cast<std::size_t>(first)] == ' ') ++first;
  int last = end;
  while (last > first && line[static_cast<std::size_t>(last - 1)] == ' ') --last;
  Field field;
  if (first < last)
    field.text = std::string(
        line.substr(static_cast<std::size_t>(first), static_cast<std::size_t>(last - first)));
  place.column = (first < last ? first : begin) + 1;
  field.place = place;
  return field;
}

// A piece of a free-format line between commas, trimmed and placed; `begin` is its first
// character's index in the line.
Field free_field(std::string_view line, std::size_t begin, std::size_t end, Place place) {
  std::size_t first = begin;
  while (first < end && is_blank(line[first])) ++first;
  std::size_t last = end;
  while (last > first && is_blank(line[last - 1])) --last;
  Field field;
  field.text = std::string(line.substr(first, last - first));
  place.column = static_cast<std::int32_t>(first) + 1;
  field.place = place;
  return field;
}

// True if `name` is a card name: a letter, then letters and digits.
bool is_card_name(const std::string& name) {
  if (name.empty() || !(name[0] >= 'A' && name[0] <= 'Z')) return false;
  return std::all_of(name.begin(), name.end(),
                     [](char c) { return (c >= 'A' && c <= 'Z') || is_digit(c); });
}

bool starts_with_word(std::string_view line, std::string_view word) {
  if (line.size() < word.size() || upper(line.substr(0, word.size())) != word) return false;
  return line.size() == word.size() || !std::isalnum(static_cast<unsigned char>(line[word.size()]));
}

// Words of an I/O options line: separated by blanks, commas, parentheses and '='.
std::vector<std::pair<std::string, std::size_t>> control_words(std::string_view line) {
  std::vector<std::pair<std::string, std::size_t>> words;
  std::size_t i = 0;
  const auto separator = [](char c) {
    return c == ' ' || c == '\t' || c == ',' || c == '(' || c == ')' || c == '=';
  };
  while (i < line.size()) {
    while (i < line.size() && separator(line[i])) ++i;
    const std::size_t begin = i;
    while (i < line.size() && !separator(line[i])) ++i;
    if (i > begin) words.emplace_back(std::string(line.substr(begin, i - begin)), begin);
  }
  return words;
}

bool is_begin_bulk(std::string_view line) {
  while (!line.empty() && is_blank(line.front())) line.remove_prefix(1);
  if (line.empty() || (line.front() != 'B' && line.front() != 'b')) return false;
  const auto words = control_words(line);
  return words.size() >= 2 && upper(words[0].first) == "BEGIN" && upper(words[1].first) == "BULK";
}

std::string_view without_comment(std::string_view line) {
  const std::size_t dollar = line.find('$');
  return dollar == std::string_view::npos ? line : line.substr(0, dollar);
}

class Lexer {
 public:
  Lexer(std::vector<std::string>& files, Problems& problems, const LexerEvents& events)
      : files_(files), problems_(problems), events_(events) {}

  // Reads one file; `in_bulk` says whether its first line is in the bulk data section and is
  // updated when a BEGIN BULK line is met.
  void read(const std::string& text, const std::string& display_name, bool& in_bulk) {
    const int file_index = static_cast<int>(files_.size());
    files_.push_back(display_name);
    std::error_code ignored;
    const fs::path canonical = fs::weakly_canonical(fs::path(display_name), ignored);
    open_files_.push_back(canonical);
    std::istringstream lines(text);
    int line_number = 0;
    bool overlong_reported = false;
    for (std::string line; !ended_ && std::getline(lines, line);) {
      ++line_number;
      ++ordinal_;
      if (!line.empty() && line.back() == '\r') line.pop_back();
      const Place place{file_index, line_number, 1, ordinal_};
      if (!in_bulk) {
        control_line(line, place, in_bulk);
        continue;
      }
      bulk_line(line, place, overlong_reported, in_bulk);
    }
    flush();
    open_files_.pop_back();
  }

  bool in_bulk_initially(const std::string& text) const {
    std::istringstream lines(text);
    for (std::string line; std::getline(lines, line);)
      if (is_begin_bulk(without_comment(line))) return false;
    return true;
  }

  void finish() { flush(); }

 private:
  void control_line(std::string_view line, const Place& place, bool& in_bulk) {
    line = without_comment(line);
    if (is_begin_bulk(line)) {
      in_bulk = true;
      return;
    }
    const auto words = control_words(line);
    if (words.empty()) return;
    const std::string keyword = upper(words[0].first);
    if (keyword == "INCLUDE") {
      include(line, place, in_bulk);
    } else if (keyword == "UNITS" && events_.units_statement) {
      Place at = place;
      if (words.size() >= 2) {
        at.column = static_cast<std::int32_t>(words[1].second) + 1;
        events_.units_statement(words[1].first, at);
      } else {
        at.column = static_cast<std::int32_t>(words[0].second) + 1;
        events_.units_statement("", at);
      }
    }
  }

  void bulk_line(std::string_view line, const Place& place, bool& overlong_reported,
                 bool& in_bulk) {
    line = without_comment(line);
    if (std::all_of(line.begin(), line.end(), is_blank)) return;
    if (line.substr(0, 2) == "//" || line.front() == '#') return;
    if (starts_with_word(line, "INCLUDE")) {
      flush();
      include(line, place, in_bulk);
      return;
    }
    if (is_begin_bulk(line)) return;
    // A model without BEGIN BULK may still start with OptiStruct's UNITS statement.
    if (starts_with_word(line, "UNITS") && line.find('=') != std::string_view::npos) {
      flush();
      bool unused = true;
      control_line(line, place, unused);
      return;
    }

    const std::size_t comma = line.find(',');
    const bool free_format = comma != std::string_view::npos && comma < 10;
    const char first = line.front();
    const bool continuation =
        first == ' ' || first == '\t' || first == '+' || first == '*' || first == ',';

    std::vector<Field> line_fields;  // field 1 first, then the data fields
    if (free_format) {
      split_free(line, place, line_fields);
    } else {
      if (!split_fixed(line, place, line_fields, overlong_reported)) {
        // A line that cannot be split loses its card; its continuation lines go with it.
        has_open_ = false;
        skipping_ = true;
        return;
      }
    }

    const std::string name_field = upper(line_fields[0].text);
    // The EDEM card's CONTROL and COUPLING lines are continuations even when their flag is
    // written in field 1 (one reading of the card's format table; docs/fem.md).
    const bool edem_flag_line = !continuation && has_open_ && open_.name == "EDEM" &&
                                (name_field == "CONTROL" || name_field == "COUPLING");
    if (continuation || edem_flag_line) {
      if (skipping_) return;
      if (!has_open_) {
        problems_.error(place, "continuation line without a card before it",
                        "a line starting with a blank, '+', '*' or ',' continues the card above "
                        "it; start a card's name in column 1");
        skipping_ = true;
        return;
      }
      if (edem_flag_line) {
        open_.fields.push_back(line_fields[0]);
        open_.fields.back().text = name_field;
      }
      for (std::size_t i = 1; i < line_fields.size(); ++i)
        open_.fields.push_back(std::move(line_fields[i]));
      return;
    }

    flush();
    skipping_ = false;
    std::string name = name_field;
    const bool large = !name.empty() && name.back() == '*';
    if (large) name.pop_back();
    if (name == "ENDDATA") {
      ended_ = true;
      return;
    }
    if (!is_card_name(name)) {
      const bool spaced = name.find(' ') != std::string::npos;
      problems_.error(line_fields[0].place,
                      fmt::format("\"{}\" is not a card name", line_fields[0].text),
                      spaced ? "fixed-format fields are 8 columns wide: the card name in columns "
                               "1-8, the first value from column 9 (or separate fields with "
                               "commas)"
                             : "a card name is a letter followed by letters and digits, from "
                               "column 1");
      skipping_ = true;
      return;
    }
    open_.name = std::move(name);
    open_.place = line_fields[0].place;
    open_.missing.place = open_.place;
    open_.fields.clear();
    for (std::size_t i = 1; i < line_fields.size(); ++i)
      open_.fields.push_back(std::move(line_fields[i]));
    has_open_ = true;
  }

  // Field 1 and the data fields of a free-format line: 8 of them, or 4 when large (a '*' after
  // the card name, or a continuation starting with '*'). A last field after them is field 10,
  // the continuation mark, and is not read.
  void split_free(std::string_view line, const Place& place, std::vector<Field>& fields) {
    std::size_t begin = 0;
    while (true) {
      const std::size_t comma = line.find(',', begin);
      const std::size_t end = comma == std::string_view::npos ? line.size() : comma;
      fields.push_back(free_field(line, begin, end, place));
      if (comma == std::string_view::npos) break;
      begin = comma + 1;
    }
    const std::string& first = fields[0].text;
    const bool large =
        (!first.empty() && first.back() == '*') || (!first.empty() && first.front() == '*');
    const std::size_t data = large ? 4 : 8;
    if (fields.size() > data + 2) {
      problems_.error(fields[data + 2].place,
                      fmt::format("more than {} fields on one free-format line", data + 2),
                      fmt::format("a {}free-format line holds the card name, {} data fields and a "
                                  "continuation mark; continue on a line starting with ','",
                                  large ? "large-field " : "", data));
    }
    fields.resize(data + 1,
                  Field{{},
                        Place{place.file, place.line, static_cast<std::int32_t>(line.size()) + 1,
                              place.ordinal}});
  }

  // Field 1 and the data fields of a fixed-format line: 8 fields of 8 columns, or 4 of 16 when
  // large. False (reported) when the line cannot be read.
  bool split_fixed(std::string_view line, const Place& place, std::vector<Field>& fields,
                   bool& overlong_reported) {
    const std::size_t tab = line.find('\t');
    if (tab != std::string_view::npos) {
      Place at = place;
      at.column = static_cast<std::int32_t>(tab) + 1;
      problems_.error(at, "tab character in a fixed-format line",
                      "bulk data does not allow tabs: use spaces (fields are 8 columns wide) or "
                      "separate the fields with commas");
      return false;
    }
    if (static_cast<int>(line.size()) > kFixedLineLength && !overlong_reported) {
      const std::string_view rest = line.substr(kFixedLineLength);
      if (!std::all_of(rest.begin(), rest.end(), is_blank)) {
        Place at = place;
        at.column = kFixedLineLength + 1;
        problems_.warning(at, "text after column 80 of a fixed-format line is ignored",
                          "use free format (commas) for longer lines");
        overlong_reported = true;
      }
    }
    const std::string_view read = line.substr(0, std::min<std::size_t>(line.size(), 80));
    fields.push_back(fixed_field(read, 0, 8, place));
    std::string name = fields[0].text;
    const bool large = (!name.empty() && name.back() == '*') || line.front() == '*';
    const int width = large ? 16 : 8;
    const int count = large ? 4 : 8;
    for (int i = 0; i < count; ++i)
      fields.push_back(fixed_field(read, 8 + i * width, width, place));
    return true;
  }

  void include(std::string_view line, const Place& place, bool& in_bulk) {
    std::size_t i = line.find_first_of(" \t'\"", 7);
    while (i != std::string_view::npos && i < line.size() && is_blank(line[i])) ++i;
    Place at = place;
    if (i == std::string_view::npos || i >= line.size()) {
      at.column = static_cast<std::int32_t>(line.size()) + 1;
      problems_.error(at, "INCLUDE names no file", "write INCLUDE 'file.bdf'");
      return;
    }
    at.column = static_cast<std::int32_t>(i) + 1;
    std::string name;
    if (line[i] == '\'' || line[i] == '"') {
      const std::size_t close = line.find(line[i], i + 1);
      if (close == std::string_view::npos) {
        problems_.error(at, "INCLUDE file name has no closing quote",
                        "write the name on one line: INCLUDE 'file.bdf'");
        return;
      }
      name = std::string(line.substr(i + 1, close - i - 1));
    } else {
      std::size_t end = i;
      while (end < line.size() && !is_blank(line[end])) ++end;
      name = std::string(line.substr(i, end - i));
    }
    const fs::path including = fs::path(files_[static_cast<std::size_t>(place.file)]);
    const fs::path target =
        fs::path(name).is_absolute() ? fs::path(name) : including.parent_path() / name;
    std::error_code ignored;
    const fs::path canonical = fs::weakly_canonical(target, ignored);
    if (std::find(open_files_.begin(), open_files_.end(), canonical) != open_files_.end()) {
      problems_.error(at, fmt::format("INCLUDE of \"{}\" includes itself", name),
                      "a file cannot include a file that (directly or not) includes it");
      return;
    }
    if (static_cast<int>(open_files_.size()) > kMaxIncludeDepth) {
      problems_.error(at, fmt::format("INCLUDE files nested deeper than {}", kMaxIncludeDepth));
      return;
    }
    std::ifstream in(target, std::ios::binary);
    if (!in) {
      problems_.error(at, fmt::format("cannot open the included file \"{}\"", name),
                      "the path is relative to the folder of the file that includes it");
      return;
    }
    std::ostringstream text;
    text << in.rdbuf();
    flush();
    read(text.str(), target.string(), in_bulk);
  }

  void flush() {
    if (has_open_ && events_.card) events_.card(open_);
    has_open_ = false;
  }

  std::vector<std::string>& files_;
  Problems& problems_;
  const LexerEvents& events_;
  std::vector<fs::path> open_files_;  // the chain of INCLUDEs being read
  Card open_;                         // the card being assembled, when has_open_
  bool has_open_ = false;
  bool skipping_ = false;  // dropping continuation lines of an unreadable card
  bool ended_ = false;     // ENDDATA seen
  std::int32_t ordinal_ = 0;
};

}  // namespace

void lex_model(const std::string& text, const std::string& display_name,
               std::vector<std::string>& files, Problems& problems, const LexerEvents& events) {
  Lexer lexer(files, problems, events);
  bool in_bulk = lexer.in_bulk_initially(text);
  lexer.read(text, display_name, in_bulk);
  lexer.finish();
}

}  // namespace quarry::bulk_detail
