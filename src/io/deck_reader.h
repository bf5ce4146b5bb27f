// Typed, located reads of yaml-cpp nodes for the deck parser (io/deck*.cpp only): every
// problem (wrong type, unknown key, bad enum value, out-of-range number) is recorded in
// Diagnostics and reading goes on, so that one run reports all errors of a deck.
#pragma once

#include <yaml-cpp/yaml.h>

#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/diagnostics.h"
#include "core/vec3.h"

namespace quarry::deck_detail {

// State of one deck parse: the file name written into locations and the collected errors.
struct DeckContext {
  std::string display_name;
  Diagnostics diagnostics;

  // 1-based location of a node; a node without a mark (null values) gives line 0.
  SourceLocation where(const YAML::Node& node) const;
  // Location of `value`, or of `fallback` when the value has no usable mark (an empty value
  // such as `density:` has its mark on the next token, so the key is the better place).
  SourceLocation where(const YAML::Node& value, const YAML::Node& fallback) const;
  void error(SourceLocation where, std::string message, std::string hint = {});
};

// Allowed interval of a number; rendered for messages as "> 0 s", "in (0, 1]".
struct Range {
  double lower = -std::numeric_limits<double>::infinity();
  bool lower_inclusive = true;
  double upper = std::numeric_limits<double>::infinity();
  bool upper_inclusive = true;

  bool contains(double value) const;
  std::string describe(const std::string& unit) const;
};
Range any_number();
Range positive();      // > 0
Range non_negative();  // ≥ 0
Range at_least(double lower);
Range interval(double lower, bool lower_inclusive, double upper, bool upper_inclusive);

// "5 kg/m³"; the dimensionless unit "1" is not printed.
std::string with_unit(double value, const std::string& unit);
// "a map", "a list", "nothing", or the scalar in quotes: what the user wrote instead.
std::string describe_node(const YAML::Node& node);

// Readers of a single value node; `key` names it in messages, `fallback` (the key node)
// locates errors for empty values. Each reports its error and returns nullopt on failure.
std::optional<double> read_number(DeckContext& context, const YAML::Node& value,
                                  const YAML::Node& fallback, const std::string& key);
std::optional<std::int64_t> read_integer(DeckContext& context, const YAML::Node& value,
                                         const YAML::Node& fallback, const std::string& key);
std::optional<bool> read_boolean(DeckContext& context, const YAML::Node& value,
                                 const YAML::Node& fallback, const std::string& key);
std::optional<std::string> read_string(DeckContext& context, const YAML::Node& value,
                                       const YAML::Node& fallback, const std::string& key);
std::optional<Vec3> read_vector(DeckContext& context, const YAML::Node& value,
                                const YAML::Node& fallback, const std::string& key);

// Reports "`key` must be <range> <unit>, got <value> <unit>" if value is outside range.
bool check_range(DeckContext& context, const SourceLocation& where, const std::string& key,
                 double value, const Range& range, const std::string& unit);

// Reports unless max exceeds min in every component (an empty or flat box); `what` names
// the box in the message ("domain").
bool check_box_corners(DeckContext& context, const std::string& what, const Located<Vec3>& lower,
                       const Located<Vec3>& upper);
// Reports a zero vector where a direction is needed (a normal, an axis).
bool check_nonzero_direction(DeckContext& context, const std::string& key,
                             const Located<Vec3>& direction);

// The spellings an enumerated key accepts; `noun` names the concept in messages
// ("unknown contact model \"hertz_mindln\"").
template <class Enum>
struct EnumChoices {
  std::string noun;
  std::vector<std::pair<std::string, Enum>> names;

  std::vector<std::string> spellings() const {
    std::vector<std::string> result;
    for (const auto& entry : names) result.push_back(entry.first);
    return result;
  }
};

// "a, b, c": the spellings of an enumerated key, for hints.
template <class Enum>
std::string join_choices(const EnumChoices<Enum>& choices) {
  std::string list;
  for (const auto& entry : choices.names) list += (list.empty() ? "" : ", ") + entry.first;
  return list;
}

// Hint for an unknown word: "did you mean …" when close to a choice, else the full list
// after `list_intro`.
std::string suggestion_hint(const std::string& word, const std::vector<std::string>& choices,
                            const std::string& list_intro = "expected one of: ");

template <class Enum>
std::optional<Enum> read_enum(DeckContext& context, const YAML::Node& value,
                              const YAML::Node& fallback, const std::string& key,
                              const EnumChoices<Enum>& choices) {
  const std::optional<std::string> word = read_string(context, value, fallback, key);
  if (!word) return std::nullopt;
  for (const auto& [spelling, enum_value] : choices.names)
    if (spelling == *word) return enum_value;
  context.error(context.where(value, fallback), "unknown " + choices.noun + " \"" + *word + "\"",
                suggestion_hint(*word, choices.spellings()));
  return std::nullopt;
}

enum class Presence { optional, required };

// One YAML map of the deck being read: finds keys, reads typed located values, reports
// unknown, duplicate and missing keys. `what` names the map in messages ("material").
class MapReader {
 public:
  // A node that is not a map is reported (unless it is absent) and then reads as empty.
  MapReader(DeckContext& context, const YAML::Node& node, const YAML::Node& fallback,
            std::string what);

  bool is_map() const { return is_map_; }
  const std::string& what() const { return what_; }
  SourceLocation location() const { return location_; }
  DeckContext& context() const { return context_; }

  // The value node of `key`, or nullptr when absent.
  const YAML::Node* find(const std::string& key) const;
  // The key node of `key` (for locating messages about its value), or nullptr.
  const YAML::Node* find_key(const std::string& key) const;
  bool has(const std::string& key) const { return find(key) != nullptr; }
  SourceLocation where_value(const std::string& key) const;

  // Reports keys outside `allowed_keys`: a key that belongs to another variant of this map
  // (`keys_of_other_variants`) "does not apply to `variant_description`"; any other key is
  // unknown, with "did you mean" among the allowed keys.
  void reject_unknown_keys(const std::vector<std::string>& allowed_keys,
                           const std::vector<std::string>& keys_of_other_variants = {},
                           const std::string& variant_description = {});

  // Reports "missing required key" at this map's location when `key` is absent (unless a
  // misspelling of it was reported as an unknown key with "did you mean").
  bool require(const std::string& key, const std::string& hint = {});

  // Read `key` into `out` (value and location). Absent keys keep the default in `out`
  // (and are reported when required). True when a valid value was stored.
  bool read(const std::string& key, Located<double>& out, const Range& range,
            const std::string& unit, Presence presence = Presence::optional);
  bool read(const std::string& key, Located<int>& out, const Range& range,
            Presence presence = Presence::optional);
  bool read(const std::string& key, Located<std::int64_t>& out, const Range& range,
            Presence presence = Presence::optional);
  bool read(const std::string& key, Located<bool>& out, Presence presence = Presence::optional);
  bool read(const std::string& key, Located<std::string>& out,
            Presence presence = Presence::optional);
  bool read(const std::string& key, Located<Vec3>& out, Presence presence = Presence::optional);

  template <class Enum>
  bool read(const std::string& key, Located<Enum>& out, const EnumChoices<Enum>& choices,
            Presence presence = Presence::optional) {
    const YAML::Node* value = find(key);
    if (!value) {
      if (presence == Presence::required) require(key);
      return false;
    }
    const std::optional<Enum> parsed = read_enum(context_, *value, *find_key(key), key, choices);
    if (!parsed) return false;
    out = Located<Enum>(*parsed, where_value(key));
    return true;
  }

 private:
  DeckContext& context_;
  bool is_map_ = false;
  std::string what_;
  SourceLocation location_;
  std::vector<std::pair<YAML::Node, YAML::Node>> entries_;  // key node, value node
  std::vector<std::string> key_names_;                      // parallel to entries_
  // Keys suggested for misspelled ones: already reported, so not reported again as missing.
  std::vector<std::string> suggested_keys_;
};

// The elements of a list-valued key (reporting a non-list value); an absent key gives none.
std::vector<YAML::Node> read_list(MapReader& parent, const std::string& key);

}  // namespace quarry::deck_detail
