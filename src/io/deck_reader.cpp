// Typed, located reads of yaml-cpp nodes for the deck parser. Errors are collected, never
// thrown, so a deck with several mistakes is answered with all of them in one run.
#include "io/deck_reader.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace quarry::deck_detail {

SourceLocation DeckContext::where(const YAML::Node& node) const {
  const YAML::Mark mark = node.Mark();
  if (mark.is_null() || mark.line < 0) return {display_name, 0, 0};
  // yaml-cpp marks are 0-based; users and editors count from 1.
  return {display_name, mark.line + 1, mark.column + 1};
}

SourceLocation DeckContext::where(const YAML::Node& value, const YAML::Node& fallback) const {
  // An empty value (`key:` with nothing after it) is marked at the next token, which may be
  // lines below; the key is where the user has to look.
  if (value.IsNull() || value.Mark().is_null()) return where(fallback);
  return where(value);
}

void DeckContext::error(SourceLocation where_, std::string message, std::string hint) {
  diagnostics.error(std::move(where_), std::move(message), std::move(hint));
}

bool Range::contains(double value) const {
  const bool above = lower_inclusive ? value >= lower : value > lower;
  const bool below = upper_inclusive ? value <= upper : value < upper;
  return above && below;
}

namespace {
std::string unit_suffix(const std::string& unit) {
  return unit.empty() || unit == "1" ? std::string() : " " + unit;
}
}  // namespace

std::string Range::describe(const std::string& unit) const {
  const bool has_lower = std::isfinite(lower);
  const bool has_upper = std::isfinite(upper);
  const std::string suffix = unit_suffix(unit);
  if (has_lower && has_upper)
    return fmt::format("in {}{}, {}{}{}", lower_inclusive ? "[" : "(", lower, upper,
                       upper_inclusive ? "]" : ")", suffix);
  if (has_lower) return fmt::format("{} {}{}", lower_inclusive ? "≥" : ">", lower, suffix);
  if (has_upper) return fmt::format("{} {}{}", upper_inclusive ? "≤" : "<", upper, suffix);
  return "a number";
}

Range any_number() {
  return {};
}
Range positive() {
  return interval(0.0, false, std::numeric_limits<double>::infinity(), true);
}
Range non_negative() {
  return at_least(0.0);
}
Range at_least(double lower) {
  return interval(lower, true, std::numeric_limits<double>::infinity(), true);
}
Range interval(double lower, bool lower_inclusive, double upper, bool upper_inclusive) {
  Range range;
  range.lower = lower;
  range.lower_inclusive = lower_inclusive;
  range.upper = upper;
  range.upper_inclusive = upper_inclusive;
  return range;
}

std::string with_unit(double value, const std::string& unit) {
  return fmt::format("{}{}", value, unit_suffix(unit));
}

std::string describe_node(const YAML::Node& node) {
  switch (node.Type()) {
    case YAML::NodeType::Null:
    case YAML::NodeType::Undefined:
      return "nothing";
    case YAML::NodeType::Scalar:
      return "\"" + node.Scalar() + "\"";
    case YAML::NodeType::Sequence:
      return fmt::format("a list of {}", node.size());
    case YAML::NodeType::Map:
      return "a map";
  }
  return "nothing";
}

std::string suggestion_hint(const std::string& word, const std::vector<std::string>& choices,
                            const std::string& list_intro) {
  const std::string close = did_you_mean(word, choices);
  if (!close.empty()) return close;
  std::string list;
  for (const auto& choice : choices) list += (list.empty() ? "" : ", ") + choice;
  return list_intro + list;
}

namespace {
// A quoted scalar (`"2500"`) is text in YAML (yaml-cpp gives it the non-specific tag "!"), and so
// is one tagged `!!str` (the tag resolves to the core schema's str).
bool is_quoted(const YAML::Node& node) {
  return node.Tag() == "!";
}
bool is_tagged_text(const YAML::Node& node) {
  return node.Tag() == "tag:yaml.org,2002:str";
}
bool is_text(const YAML::Node& node) { return is_quoted(node) || is_tagged_text(node); }
}  // namespace

std::optional<double> read_number(DeckContext& context, const YAML::Node& value,
                                  const YAML::Node& fallback, const std::string& key) {
  const SourceLocation at = context.where(value, fallback);
  double number = 0.0;
  if (!value.IsScalar() || !YAML::convert<double>::decode(value, number)) {
    context.error(at,
                  fmt::format("expected a number for \"{}\", got {}", key, describe_node(value)));
    return std::nullopt;
  }
  if (is_text(value)) {
    context.error(
        at, fmt::format("expected a number for \"{}\", got the text {}", key, describe_node(value)),
        is_quoted(value) ? "remove the quotes" : "remove the !!str tag: it makes the value text");
    return std::nullopt;
  }
  if (!std::isfinite(number)) {
    context.error(at,
                  fmt::format("\"{}\" must be a finite number, got {}", key, describe_node(value)));
    return std::nullopt;
  }
  return number;
}

std::optional<std::int64_t> read_integer(DeckContext& context, const YAML::Node& value,
                                         const YAML::Node& fallback, const std::string& key) {
  long long number = 0;
  if (!value.IsScalar() || is_text(value) || !YAML::convert<long long>::decode(value, number)) {
    context.error(context.where(value, fallback),
                  fmt::format("expected an integer for \"{}\", got {}", key, describe_node(value)));
    return std::nullopt;
  }
  return static_cast<std::int64_t>(number);
}

std::optional<bool> read_boolean(DeckContext& context, const YAML::Node& value,
                                 const YAML::Node& fallback, const std::string& key) {
  bool flag = false;
  if (!value.IsScalar() || is_text(value) || !YAML::convert<bool>::decode(value, flag)) {
    context.error(
        context.where(value, fallback),
        fmt::format("expected true or false for \"{}\", got {}", key, describe_node(value)));
    return std::nullopt;
  }
  return flag;
}

std::optional<std::string> read_string(DeckContext& context, const YAML::Node& value,
                                       const YAML::Node& fallback, const std::string& key) {
  if (!value.IsScalar() || value.Scalar().empty()) {
    context.error(
        context.where(value, fallback),
        fmt::format("expected a name or text for \"{}\", got {}", key, describe_node(value)));
    return std::nullopt;
  }
  return value.Scalar();
}

std::optional<Vec3> read_vector(DeckContext& context, const YAML::Node& value,
                                const YAML::Node& fallback, const std::string& key) {
  if (!value.IsSequence() || value.size() != 3) {
    context.error(
        context.where(value, fallback),
        fmt::format("expected a list of 3 numbers for \"{}\", got {}", key, describe_node(value)),
        fmt::format("write it as {}: [x, y, z]", key));
    return std::nullopt;
  }
  Vec3 vector;
  bool valid = true;
  for (int component = 0; component < 3; ++component) {
    const std::optional<double> number =
        read_number(context, value[component], value, fmt::format("{}[{}]", key, component));
    if (number)
      vector[component] = *number;
    else
      valid = false;
  }
  if (!valid) return std::nullopt;
  return vector;
}

bool check_range(DeckContext& context, const SourceLocation& where, const std::string& key,
                 double value, const Range& range, const std::string& unit) {
  if (range.contains(value)) return true;
  context.error(where, fmt::format("{} must be {}, got {}", key, range.describe(unit),
                                   with_unit(value, unit)));
  return false;
}

bool check_box_corners(DeckContext& context, const std::string& what, const Located<Vec3>& lower,
                       const Located<Vec3>& upper) {
  static const char* const kAxisNames[] = {"x", "y", "z"};
  for (int axis = 0; axis < 3; ++axis) {
    if (upper.value[axis] > lower.value[axis]) continue;
    context.error(upper.where,
                  fmt::format("{0} max must exceed min in every component, but max.{1} = {2} m "
                              "≤ min.{1} = {3} m",
                              what, kAxisNames[axis], upper.value[axis], lower.value[axis]));
    return false;
  }
  return true;
}

bool check_nonzero_direction(DeckContext& context, const std::string& key,
                             const Located<Vec3>& direction) {
  if (norm2(direction.value) > 0.0) return true;
  context.error(direction.where, fmt::format("{} must be a non-zero vector, got [0, 0, 0]", key));
  return false;
}

MapReader::MapReader(DeckContext& context, const YAML::Node& node, const YAML::Node& fallback,
                     std::string what)
    : context_(context), what_(std::move(what)), location_(context.where(node, fallback)) {
  if (!node.IsMap()) {
    context_.error(location_, fmt::format("expected a map of keys for {}, got {}", what_,
                                          describe_node(node)));
    return;
  }
  is_map_ = true;
  for (const auto& entry : node) {
    const YAML::Node& key = entry.first;
    if (!key.IsScalar()) {
      context_.error(context_.where(key), fmt::format("expected a plain key in {}", what_));
      continue;
    }
    const auto previous = std::find(key_names_.begin(), key_names_.end(), key.Scalar());
    if (previous != key_names_.end()) {
      const int first_line = context_.where(entries_[previous - key_names_.begin()].first).line;
      context_.error(context_.where(key),
                     fmt::format("duplicate key \"{}\" in {}", key.Scalar(), what_),
                     fmt::format("first given on line {}", first_line));
      continue;
    }
    entries_.emplace_back(key, entry.second);
    key_names_.push_back(key.Scalar());
  }
}

const YAML::Node* MapReader::find(const std::string& key) const {
  const auto found = std::find(key_names_.begin(), key_names_.end(), key);
  return found == key_names_.end() ? nullptr : &entries_[found - key_names_.begin()].second;
}

const YAML::Node* MapReader::find_key(const std::string& key) const {
  const auto found = std::find(key_names_.begin(), key_names_.end(), key);
  return found == key_names_.end() ? nullptr : &entries_[found - key_names_.begin()].first;
}

SourceLocation MapReader::where_value(const std::string& key) const {
  const YAML::Node* value = find(key);
  if (!value) return location_;
  return context_.where(*value, *find_key(key));
}

void MapReader::reject_unknown_keys(const std::vector<std::string>& allowed_keys,
                                    const std::vector<std::string>& keys_of_other_variants,
                                    const std::string& variant_description) {
  const auto contains = [](const std::vector<std::string>& list, const std::string& word) {
    return std::find(list.begin(), list.end(), word) != list.end();
  };
  for (std::size_t index = 0; index < entries_.size(); ++index) {
    const std::string& key = key_names_[index];
    if (contains(allowed_keys, key)) continue;
    const SourceLocation at = context_.where(entries_[index].first);
    if (contains(keys_of_other_variants, key)) {
      context_.error(at, fmt::format("key \"{}\" does not apply to {}", key, variant_description),
                     suggestion_hint(key, allowed_keys, "keys allowed here: "));
    } else {
      context_.error(at, fmt::format("unknown key \"{}\" in {}", key, what_),
                     suggestion_hint(key, allowed_keys, "keys allowed here: "));
      const std::string close = closest_match(key, allowed_keys);
      if (!close.empty()) suggested_keys_.push_back(close);
    }
  }
}

bool MapReader::require(const std::string& key, const std::string& hint) {
  if (has(key)) return true;
  const bool misspelled =
      std::find(suggested_keys_.begin(), suggested_keys_.end(), key) != suggested_keys_.end();
  if (is_map_ && !misspelled)  // a non-map was reported already, not each of its keys
    context_.error(location_, fmt::format("missing required key \"{}\" in {}", key, what_), hint);
  return false;
}

bool MapReader::read(const std::string& key, Located<double>& out, const Range& range,
                     const std::string& unit, Presence presence) {
  const YAML::Node* value = find(key);
  if (!value) {
    if (presence == Presence::required) require(key);
    return false;
  }
  const std::optional<double> number = read_number(context_, *value, *find_key(key), key);
  if (!number) return false;
  out = Located<double>(*number, where_value(key));
  return check_range(context_, out.where, key, *number, range, unit);
}

bool MapReader::read(const std::string& key, Located<std::int64_t>& out, const Range& range,
                     Presence presence) {
  const YAML::Node* value = find(key);
  if (!value) {
    if (presence == Presence::required) require(key);
    return false;
  }
  const std::optional<std::int64_t> number = read_integer(context_, *value, *find_key(key), key);
  if (!number) return false;
  out = Located<std::int64_t>(*number, where_value(key));
  return check_range(context_, out.where, key, static_cast<double>(*number), range, "1");
}

bool MapReader::read(const std::string& key, Located<int>& out, const Range& range,
                     Presence presence) {
  Located<std::int64_t> wide(out.value, out.where);
  // Counts in a deck (threads, steps, segments) are far below the int limit; the range
  // check keeps the narrowing exact.
  const Range bounded = interval(
      std::max(range.lower, double{std::numeric_limits<int>::min()}), range.lower_inclusive,
      std::min(range.upper, double{std::numeric_limits<int>::max()}), range.upper_inclusive);
  if (!read(key, wide, bounded, presence)) return false;
  out = Located<int>(static_cast<int>(wide.value), wide.where);
  return true;
}

bool MapReader::read(const std::string& key, Located<bool>& out, Presence presence) {
  const YAML::Node* value = find(key);
  if (!value) {
    if (presence == Presence::required) require(key);
    return false;
  }
  const std::optional<bool> flag = read_boolean(context_, *value, *find_key(key), key);
  if (!flag) return false;
  out = Located<bool>(*flag, where_value(key));
  return true;
}

bool MapReader::read(const std::string& key, Located<std::string>& out, Presence presence) {
  const YAML::Node* value = find(key);
  if (!value) {
    if (presence == Presence::required) require(key);
    return false;
  }
  const std::optional<std::string> text = read_string(context_, *value, *find_key(key), key);
  if (!text) return false;
  out = Located<std::string>(*text, where_value(key));
  return true;
}

bool MapReader::read(const std::string& key, Located<Vec3>& out, Presence presence) {
  const YAML::Node* value = find(key);
  if (!value) {
    if (presence == Presence::required) require(key);
    return false;
  }
  const std::optional<Vec3> vector = read_vector(context_, *value, *find_key(key), key);
  if (!vector) return false;
  out = Located<Vec3>(*vector, where_value(key));
  return true;
}

std::vector<YAML::Node> read_list(MapReader& parent, const std::string& key) {
  const YAML::Node* value = parent.find(key);
  if (!value || value->IsNull()) return {};
  if (!value->IsSequence()) {
    parent.context().error(
        parent.where_value(key),
        fmt::format("expected a list for \"{}\", got {}", key, describe_node(*value)),
        "write each entry on its own line starting with \"- \"");
    return {};
  }
  std::vector<YAML::Node> elements;
  for (const auto& element : *value) elements.push_back(element);
  return elements;
}

}  // namespace quarry::deck_detail
