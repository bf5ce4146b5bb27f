// User-facing diagnostics: source locations in the user's files, errors collected so that
// every error of a deck is reported at once, formatted as `file:line:col: error: message`,
// the offending line echoed with a caret, and a hint. Exit code 2 for user errors.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

namespace quarry {

// A position in a user's file; line and column are 1-based (0 = unknown).
struct SourceLocation {
  std::string file;
  int line = 0;
  int column = 0;
};

// A value together with where the user wrote it, so that later stages (world building,
// time-step checks) can still point at the deck.
template <class T>
struct Located {
  T value{};
  SourceLocation where;
  Located() = default;
  Located(T v) : value(std::move(v)) {}  // NOLINT: implicit on purpose, for defaults
  Located(T v, SourceLocation w) : value(std::move(v)), where(std::move(w)) {}
  operator const T&() const { return value; }  // NOLINT
  const T& operator*() const { return value; }
  const T* operator->() const { return &value; }
};

enum class Severity { error, warning, note };

struct Diagnostic {
  Severity severity = Severity::error;
  SourceLocation where;
  std::string message;
  std::string hint;  // "did you mean …", "increase …"; empty if none
};

// Collects diagnostics; formats them against the source text.
class Diagnostics {
 public:
  void error(SourceLocation where, std::string message, std::string hint = {});
  void warning(SourceLocation where, std::string message, std::string hint = {});
  // Information the caller may print (e.g. cards a model reader ignored); never fails a read.
  void note(SourceLocation where, std::string message, std::string hint = {});
  bool has_errors() const;
  const std::vector<Diagnostic>& all() const { return items_; }
  // Full text: for each diagnostic "file:line:col: error: message", the source line, a caret
  // under the column, and "  hint: …". Reads the files named in the locations to echo lines.
  std::string format() const;
  void clear() { items_.clear(); }

 private:
  std::vector<Diagnostic> items_;
};

// Thrown when user input is invalid; carries all diagnostics. The CLI prints them and exits 2.
class UserError : public std::runtime_error {
 public:
  explicit UserError(Diagnostics d);
  UserError(SourceLocation where, std::string message, std::string hint = {});
  const Diagnostics& diagnostics() const { return diagnostics_; }

 private:
  Diagnostics diagnostics_;
};

// Thrown when the physics goes wrong at run time (NaN, excessive overlap, …): the message
// names the step, the particle, the values and what to change. The CLI exits 3.
class PhysicsError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A file or folder of the user's environment that cannot be read or written — disk full, no
// permission, a file where a folder should be: not a bug of ours, so the CLI exits 2 and says
// which path and why.
class FileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Levenshtein distance, for "did you mean" suggestions.
int edit_distance(const std::string& a, const std::string& b);
// The candidate closest to `word` if it is close enough to be a plausible typo, else "".
std::string closest_match(const std::string& word, const std::vector<std::string>& candidates);
// " did you mean \"x\"?" or "" — ready to append to a message or to use as a hint.
std::string did_you_mean(const std::string& word, const std::vector<std::string>& candidates);

}  // namespace quarry
