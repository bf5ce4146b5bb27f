// Diagnostics: collection, "did you mean" suggestions and gcc-style formatting with the
// user's source line echoed under the message.
#include "core/diagnostics.h"

#include <fmt/format.h>

#include <algorithm>
#include <fstream>
#include <map>

namespace quarry {

void Diagnostics::error(SourceLocation where, std::string message, std::string hint) {
  items_.push_back({Severity::error, std::move(where), std::move(message), std::move(hint)});
}

void Diagnostics::warning(SourceLocation where, std::string message, std::string hint) {
  items_.push_back({Severity::warning, std::move(where), std::move(message), std::move(hint)});
}

void Diagnostics::note(SourceLocation where, std::string message, std::string hint) {
  items_.push_back({Severity::note, std::move(where), std::move(message), std::move(hint)});
}

bool Diagnostics::has_errors() const {
  return std::any_of(items_.begin(), items_.end(),
                     [](const Diagnostic& d) { return d.severity == Severity::error; });
}

namespace {
const char* severity_word(Severity s) {
  switch (s) {
    case Severity::error: return "error";
    case Severity::warning: return "warning";
    case Severity::note: return "note";
  }
  return "error";
}

// Reads a file's lines once per format() call; missing files give no echo.
class LineCache {
 public:
  const std::string* line(const std::string& file, int number) {
    auto it = files_.find(file);
    if (it == files_.end()) {
      std::vector<std::string> lines;
      std::ifstream in(file);
      for (std::string text; std::getline(in, text);) lines.push_back(text);
      it = files_.emplace(file, std::move(lines)).first;
    }
    if (number < 1 || number > static_cast<int>(it->second.size())) return nullptr;
    return &it->second[number - 1];
  }

 private:
  std::map<std::string, std::vector<std::string>> files_;
};
}  // namespace

std::string Diagnostics::format() const {
  LineCache cache;
  std::string out;
  for (const auto& d : items_) {
    std::string place = d.where.file.empty() ? std::string("quarry") : d.where.file;
    if (d.where.line > 0) place += fmt::format(":{}", d.where.line);
    if (d.where.line > 0 && d.where.column > 0) place += fmt::format(":{}", d.where.column);
    out += fmt::format("{}: {}: {}\n", place, severity_word(d.severity), d.message);
    if (d.where.line > 0 && !d.where.file.empty()) {
      if (const std::string* text = cache.line(d.where.file, d.where.line)) {
        out += fmt::format("{:>5} | {}\n", d.where.line, *text);
        if (d.where.column > 0)
          out += fmt::format("{:>5} | {}^\n", "", std::string(d.where.column - 1, ' '));
      }
    }
    if (!d.hint.empty()) out += fmt::format("  hint: {}\n", d.hint);
  }
  return out;
}

namespace {
std::string first_message(const Diagnostics& d) {
  for (const auto& item : d.all())
    if (item.severity == Severity::error) return item.message;
  return "invalid input";
}
}  // namespace

UserError::UserError(Diagnostics d) : std::runtime_error(first_message(d)), diagnostics_(std::move(d)) {}

UserError::UserError(SourceLocation where, std::string message, std::string hint)
    : std::runtime_error(message) {
  diagnostics_.error(std::move(where), std::move(message), std::move(hint));
}

int edit_distance(const std::string& a, const std::string& b) {
  std::vector<int> previous(b.size() + 1), current(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) previous[j] = static_cast<int>(j);
  for (std::size_t i = 1; i <= a.size(); ++i) {
    current[0] = static_cast<int>(i);
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const int substitution = previous[j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1);
      current[j] = std::min({previous[j] + 1, current[j - 1] + 1, substitution});
    }
    std::swap(previous, current);
  }
  return previous[b.size()];
}

std::string closest_match(const std::string& word, const std::vector<std::string>& candidates) {
  std::string best;
  int best_distance = 1 << 30;
  for (const auto& c : candidates) {
    const int d = edit_distance(word, c);
    if (d < best_distance) {
      best_distance = d;
      best = c;
    }
  }
  // A plausible typo: at most a third of the word's letters wrong (at least one allowed).
  const int allowed = std::max<int>(1, static_cast<int>(word.size()) / 3);
  return best_distance <= allowed ? best : std::string();
}

std::string did_you_mean(const std::string& word, const std::vector<std::string>& candidates) {
  const std::string match = closest_match(word, candidates);
  return match.empty() ? std::string() : fmt::format("did you mean \"{}\"?", match);
}

}  // namespace quarry
