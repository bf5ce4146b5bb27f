// Reader of LAMMPS data files of atom_style sphere (write_data output), line by line. The
// grammar is that of the LAMMPS manual's read_data page: title line, header lines
// "<numbers> <keyword>", then sections "<Keyword> [# style]" followed by exactly one line per
// item. Every error names the file, line and column of the offending word.
#include "bench/lammps_data.h"

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <string_view>
#include <string>
#include <system_error>
#include <type_traits>
#include <vector>

#include "core/diagnostics.h"

namespace quarry::bench {

namespace {

constexpr std::string_view kAtomsFormat = "atom-ID atom-type diameter density x y z [ix iy iz]";
constexpr std::string_view kVelocitiesFormat = "atom-ID vx vy vz wx wy wz";
constexpr std::string_view kWrittenBy =
    "the file should be the output of LAMMPS 'write_data FILE nocoeff' for atom_style sphere, "
    "as bench/peers/in.lmp.settle writes it";

// Header keywords of the read_data manual that can carry a count; in a sphere file only
// "atoms" and "atom types" may be non-zero (the rest are molecular or other atom styles).
const std::vector<std::string> kCountKeywords = {
    "atoms",          "bonds",          "angles",          "dihedrals",     "impropers",
    "atom types",     "bond types",     "angle types",     "dihedral types", "improper types",
    "extra bond per atom", "extra angle per atom", "extra dihedral per atom",
    "extra improper per atom", "extra special per atom", "ellipsoids", "lines", "triangles",
    "bodies"};
const std::vector<std::string> kSections = {"Atoms", "Velocities", "Masses", "Pair Coeffs",
                                            "PairIJ Coeffs"};

struct Word {
  std::string_view text;
  int column = 0;  // 1-based
};

std::string_view trim(std::string_view s) {
  const auto first = s.find_first_not_of(" \t");
  if (first == std::string_view::npos) return {};
  const auto last = s.find_last_not_of(" \t");
  return s.substr(first, last - first + 1);
}

// The whitespace-separated words of a line, up to a "#" (read_data: "#" starts a comment).
std::vector<Word> split_words(std::string_view line) {
  std::vector<Word> words;
  std::size_t i = 0;
  while (i < line.size()) {
    if (line[i] == '#') break;
    if (line[i] == ' ' || line[i] == '\t') {
      ++i;
      continue;
    }
    const std::size_t start = i;
    while (i < line.size() && line[i] != ' ' && line[i] != '\t' && line[i] != '#') ++i;
    words.push_back({line.substr(start, i - start), static_cast<int>(start) + 1});
  }
  return words;
}

bool is_number(std::string_view text) {
  double value = 0.0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  return error == std::errc() && end == text.data() + text.size();
}

// One data file, read a line at a time; knows where it is for the messages.
class LineReader {
 public:
  explicit LineReader(const std::string& path) : path_(path), in_(path) {
    if (!in_)
      throw UserError(SourceLocation{path, 0, 0}, "cannot open the LAMMPS data file",
                      "give the path of a file written by LAMMPS write_data (bench/run.sh writes "
                      "bench/_work/runs/bed_<size>.rst.data)");
  }

  // The next line; false at the end of the file.
  bool next() {
    if (!std::getline(in_, text_)) return false;
    ++line_;
    if (!text_.empty() && text_.back() == '\r') text_.pop_back();  // written on Windows
    words_ = split_words(text_);
    return true;
  }
  // The next line that has words (blank and comment-only lines are skipped, as read_data
  // does between header lines and after a section keyword); false at the end of the file.
  bool next_with_words() {
    while (next())
      if (!words_.empty()) return true;
    return false;
  }

  const std::string& text() const { return text_; }
  const std::vector<Word>& words() const { return words_; }
  int line() const { return line_; }
  // The comment of the current line (after "#"), trimmed; read_data's section style hint.
  std::string_view comment() const {
    const auto hash = text_.find('#');
    return hash == std::string::npos ? std::string_view{} : trim(std::string_view(text_).substr(hash + 1));
  }
  int comment_column() const {
    const auto hash = text_.find('#');
    return hash == std::string::npos ? 0 : static_cast<int>(hash) + 1;
  }
  // The column just past the last word (for "more values expected").
  int end_column() const {
    const std::string_view code = std::string_view(text_).substr(0, text_.find('#'));
    const auto last = code.find_last_not_of(" \t");
    return last == std::string_view::npos ? 1 : static_cast<int>(last) + 2;
  }

  [[noreturn]] void fail_at(int line, int column, const std::string& message,
                            const std::string& hint) const {
    throw UserError(SourceLocation{path_, line, column}, message, hint);
  }
  [[noreturn]] void fail(int column, const std::string& message, const std::string& hint) const {
    fail_at(line_, column, message, hint);
  }

  // Word k of the current line as a number of type T (a double: finite).
  template <class T>
  T number(std::size_t k, std::string_view what, std::string_view hint) const {
    const Word& word = words_[k];
    T value{};
    const auto [end, error] = std::from_chars(word.text.data(), word.text.data() + word.text.size(), value);
    const bool whole = error == std::errc() && end == word.text.data() + word.text.size();
    bool finite = true;
    if constexpr (std::is_floating_point_v<T>) finite = std::isfinite(value);
    if (!whole || !finite) {
      const char* kind = std::is_floating_point_v<T> ? "a finite number" : "an integer";
      const std::string why = error == std::errc::result_out_of_range ? " (out of range)" : "";
      fail(word.column, fmt::format("expected {} for {}, got \"{}\"{}", kind, what, word.text, why),
           std::string(hint));
    }
    return value;
  }

 private:
  std::string path_;
  std::ifstream in_;
  std::string text_;
  std::vector<Word> words_;
  int line_ = 0;
};

struct Header {
  bool have_atoms = false, have_types = false;
  bool have_box[3] = {false, false, false};
};

// One header line "<numbers> <keyword>" (read_data manual, "header" keywords).
void read_header_line(LineReader& in, std::size_t numbers, LammpsData& data, Header& header) {
  const auto& words = in.words();
  if (numbers == words.size())
    in.fail(in.end_column(), "a header line needs a keyword after its numbers",
            "header lines read \"50000 atoms\", \"1 atom types\", \"0 0.084 xlo xhi\"");
  std::string keyword(words[numbers].text);
  for (std::size_t k = numbers + 1; k < words.size(); ++k) keyword += fmt::format(" {}", words[k].text);
  const int keyword_column = words[numbers].column;
  const std::string header_hint = std::string(kWrittenBy);

  static const char* const kBoxKeywords[3] = {"xlo xhi", "ylo yhi", "zlo zhi"};
  for (int d = 0; d < 3; ++d) {
    if (keyword != kBoxKeywords[d]) continue;
    if (numbers != 2)
      in.fail(words[0].column, fmt::format("\"{}\" needs two numbers (lower and upper bound, m), found {}",
                                           keyword, numbers), header_hint);
    const double lo = in.number<double>(0, fmt::format("the lower box bound of \"{}\"", keyword), header_hint);
    const double hi = in.number<double>(1, fmt::format("the upper box bound of \"{}\"", keyword), header_hint);
    if (!(lo < hi))
      in.fail(words[1].column, fmt::format("the box bounds of \"{}\" must rise, got {} {}", keyword, lo, hi),
              header_hint);
    data.box_lo[d] = lo;
    data.box_hi[d] = hi;
    header.have_box[d] = true;
    return;
  }
  if (keyword == "xy xz yz") {  // tilt factors: a triclinic box
    for (std::size_t k = 0; k < numbers; ++k)
      if (in.number<double>(k, "a tilt factor", header_hint) != 0.0)
        in.fail(words[k].column, "a triclinic box (non-zero tilt factor) is not supported",
                "the settled-bed problem is an orthogonal box");
    return;
  }
  const bool known = std::find(kCountKeywords.begin(), kCountKeywords.end(), keyword) != kCountKeywords.end();
  if (!known) {
    const std::string close = did_you_mean(keyword, kCountKeywords);
    in.fail(keyword_column, fmt::format("unknown header keyword \"{}\"", keyword),
            close.empty() ? header_hint : close);
  }
  if (numbers != 1)
    in.fail(words[0].column, fmt::format("\"{}\" needs one count, found {} numbers", keyword, numbers),
            header_hint);
  const std::int64_t count = in.number<std::int64_t>(0, fmt::format("the count of \"{}\"", keyword), header_hint);
  if (count < 0) in.fail(words[0].column, fmt::format("negative count of \"{}\"", keyword), header_hint);
  if (keyword == "atoms") {
    data.atom_count = static_cast<std::size_t>(count);
    header.have_atoms = true;
  } else if (keyword == "atom types") {
    if (count < 1) in.fail(words[0].column, "a data file needs at least 1 atom type", header_hint);
    data.atom_types = static_cast<int>(std::min<std::int64_t>(count, 1 << 30));
    header.have_types = true;
  } else if (count != 0) {
    in.fail(words[0].column,
            fmt::format("{} {}: only atom_style sphere files (no bonds, no other particle shapes) "
                        "are supported", count, keyword),
            header_hint);
  }
}

// The next data line of a section of `expected` lines, `done` of them read so far.
void next_section_line(LineReader& in, std::string_view section, std::size_t done, std::size_t expected,
                       std::string_view format) {
  const std::string hint = fmt::format("the header's count is {}; each line of the {} section reads "
                                       "\"{}\"", expected, section, format);
  if (!in.next_with_words())
    in.fail(0, fmt::format("the file ends after {} of the {} lines of the {} section", done, expected, section),
            "the file is cut short (was write_data interrupted?) or the header's count is wrong");
  if (!is_number(in.words()[0].text))
    in.fail(in.words()[0].column,
            fmt::format("the {} section ends after {} of its {} lines (found \"{}\")", section, done,
                        expected, trim(in.text())), hint);
}

void check_value_count(const LineReader& in, std::size_t count_a, std::size_t count_b, std::string_view section,
                       std::string_view format) {
  const std::size_t found = in.words().size();
  if (found == count_a || found == count_b) return;
  const std::string counts = count_a == count_b ? fmt::format("{}", count_a) : fmt::format("{} or {}", count_a, count_b);
  const int column = found < count_a ? in.end_column() : in.words()[found < count_b ? count_a : count_b].column;
  in.fail(column, fmt::format("expected {} values in this {} line, found {}", counts, section, found),
          fmt::format("each line of the {} section reads \"{}\" (LAMMPS read_data manual)", section, format));
}

void read_atoms(LineReader& in, LammpsData& data, const Header& header) {
  const int keyword_line = in.line();
  const std::string_view style = in.comment();
  if (!style.empty() && style != "sphere")
    in.fail(in.comment_column(),
            fmt::format("an Atoms section of atom_style \"{}\": only atom_style sphere is supported", style),
            fmt::format("atom_style sphere lines read \"{}\"", kAtomsFormat));
  if (!header.have_atoms)
    in.fail(1, "the header has no \"N atoms\" line before the Atoms section", std::string(kWrittenBy));
  if (!header.have_types)
    in.fail(1, "the header has no \"N atom types\" line before the Atoms section", std::string(kWrittenBy));
  static const char* const kBoxKeywords[3] = {"xlo xhi", "ylo yhi", "zlo zhi"};
  for (int d = 0; d < 3; ++d)
    if (!header.have_box[d])
      in.fail(1, fmt::format("the header has no \"{}\" line before the Atoms section", kBoxKeywords[d]),
              std::string(kWrittenBy));

  const std::string hint = fmt::format("atom_style sphere Atoms lines read \"{}\" (SI units: m, kg/m³)",
                                       kAtomsFormat);
  const std::size_t n = data.atom_count;
  // Reserve at most 16M up front: the count is the file's word, the lines may not follow.
  data.atoms.reserve(std::min<std::size_t>(n, std::size_t{1} << 24));
  static const char* const kCoordinate[3] = {"x", "y", "z"};
  static const char* const kImage[3] = {"image flag ix", "image flag iy", "image flag iz"};
  for (std::size_t k = 0; k < n; ++k) {
    next_section_line(in, "Atoms", k, n, kAtomsFormat);
    check_value_count(in, 7, 10, "Atoms", kAtomsFormat);
    const auto& words = in.words();
    const bool image = words.size() == 10;
    if (k == 0) data.has_image_flags = image;
    if (image != data.has_image_flags)  // read_data takes the format from the first line
      in.fail(words.size() > 7 ? words[7].column : in.end_column(),
              image ? "image flags, where the first Atoms line has none"
                    : "no image flags, where the first Atoms line has them",
              "either every Atoms line ends in \"ix iy iz\" or none does");
    LammpsAtom atom;
    atom.line = in.line();
    atom.id = in.number<std::uint64_t>(0, "the atom-ID", hint);
    if (atom.id == 0) in.fail(words[0].column, "atom-IDs start at 1, got 0", hint);
    const std::int64_t type = in.number<std::int64_t>(1, "the atom-type", hint);
    if (type < 1 || type > data.atom_types)
      in.fail(words[1].column, fmt::format("atom-type {} is outside 1 … {} (header \"{} atom types\")", type,
                                           data.atom_types, data.atom_types), hint);
    atom.type = static_cast<int>(type);
    atom.diameter = in.number<double>(2, "the diameter (m)", hint);
    if (!(atom.diameter > 0.0))
      in.fail(words[2].column, fmt::format("the diameter must be positive, got {} m", atom.diameter),
              "a diameter of 0 is a LAMMPS point particle (its density column is then a mass); "
              "Quarry needs spheres");
    atom.density = in.number<double>(3, "the density (kg/m³)", hint);
    if (!(atom.density > 0.0))
      in.fail(words[3].column, fmt::format("the density must be positive, got {} kg/m³", atom.density), hint);
    for (int d = 0; d < 3; ++d) {
      const double x = in.number<double>(4 + d, fmt::format("the coordinate {} (m)", kCoordinate[d]), hint);
      if (x < data.box_lo[d] || x > data.box_hi[d])
        in.fail(words[4 + d].column,
                fmt::format("{} = {} m lies outside the box [{}, {}] of the header", kCoordinate[d], x,
                            data.box_lo[d], data.box_hi[d]),
                "write_data writes every atom inside its box; was the file edited?");
      atom.position[d] = x;
    }
    if (image)
      for (int d = 0; d < 3; ++d) atom.image[d] = in.number<int>(7 + d, kImage[d], hint);
    data.atoms.push_back(atom);
  }

  // Ascending id, so that the result does not depend on the order of the writing ranks and the
  // Velocities lines find their atom by binary search.
  std::stable_sort(data.atoms.begin(), data.atoms.end(),
                   [](const LammpsAtom& a, const LammpsAtom& b) { return a.id < b.id; });
  for (std::size_t k = 1; k < data.atoms.size(); ++k)
    if (data.atoms[k].id == data.atoms[k - 1].id) {
      const int first = std::min(data.atoms[k].line, data.atoms[k - 1].line);
      const int second = std::max(data.atoms[k].line, data.atoms[k - 1].line);
      in.fail_at(second, 1, fmt::format("atom-ID {} appears twice in the Atoms section (also line {})",
                                        data.atoms[k].id, first),
                 fmt::format("every atom-ID once (Atoms section from line {})", keyword_line));
    }
}

void read_velocities(LineReader& in, LammpsData& data, bool atoms_read) {
  if (!atoms_read)
    in.fail(1, "a Velocities section before the Atoms section",
            "read_data needs the Atoms first; write_data writes them first");
  const std::string hint =
      fmt::format("atom_style sphere Velocities lines read \"{}\" (SI units: m/s, rad/s)", kVelocitiesFormat);
  const std::size_t n = data.atom_count;
  std::vector<int> line_of(data.atoms.size(), 0);  // the velocity line of each atom, 0: none yet
  for (std::size_t k = 0; k < n; ++k) {
    next_section_line(in, "Velocities", k, n, kVelocitiesFormat);
    check_value_count(in, 7, 7, "Velocities", kVelocitiesFormat);
    const std::uint64_t id = in.number<std::uint64_t>(0, "the atom-ID", hint);
    const auto it = std::lower_bound(data.atoms.begin(), data.atoms.end(), id,
                                     [](const LammpsAtom& a, std::uint64_t v) { return a.id < v; });
    if (it == data.atoms.end() || it->id != id)
      in.fail(in.words()[0].column, fmt::format("atom-ID {} is not in the Atoms section", id), hint);
    const std::size_t index = static_cast<std::size_t>(it - data.atoms.begin());
    if (line_of[index] != 0)
      in.fail(in.words()[0].column,
              fmt::format("a second velocity line for atom-ID {} (the first on line {})", id, line_of[index]), hint);
    line_of[index] = in.line();
    static const char* const kNames[6] = {"vx (m/s)", "vy (m/s)", "vz (m/s)",
                                          "wx (rad/s)", "wy (rad/s)", "wz (rad/s)"};
    for (int d = 0; d < 3; ++d) {
      it->velocity[d] = in.number<double>(1 + d, kNames[d], hint);
      it->angular_velocity[d] = in.number<double>(4 + d, kNames[3 + d], hint);
    }
  }
  // n lines, each a different atom of the n: every atom has its velocity.
  data.has_velocities = true;
}

// Masses / Pair Coeffs / PairIJ Coeffs (write_data without nocoeff, or a hand-made file): not
// needed here (sphere masses come from density and diameter; Quarry has its own contact model).
void skip_section(LineReader& in, std::string_view section, std::size_t lines, bool have_types) {
  if (!have_types)
    in.fail(1, fmt::format("the header has no \"N atom types\" line before the {} section", section),
            std::string(kWrittenBy));
  for (std::size_t k = 0; k < lines; ++k) next_section_line(in, section, k, lines, "type values…");
}

}  // namespace

LammpsData read_lammps_data(const std::string& path) {
  LineReader in(path);
  LammpsData data;
  data.path = path;
  if (!in.next()) in.fail(0, "the file is empty", std::string(kWrittenBy));
  data.title = std::string(trim(in.text()));  // read_data skips the first line

  Header header;
  bool in_sections = false;
  while (in.next_with_words()) {
    const auto& words = in.words();
    std::size_t numbers = 0;
    while (numbers < words.size() && is_number(words[numbers].text)) ++numbers;
    if (numbers == 0) {  // the first section keyword ends the header
      in_sections = true;
      break;
    }
    read_header_line(in, numbers, data, header);
  }

  bool atoms_read = false;
  while (in_sections) {
    const std::string keyword(trim(in.text().substr(0, in.text().find('#'))));
    const auto types = static_cast<std::size_t>(std::max(data.atom_types, 0));
    if (keyword == "Atoms") {
      if (atoms_read) in.fail(1, "a second Atoms section", std::string(kWrittenBy));
      read_atoms(in, data, header);
      atoms_read = true;
    } else if (keyword == "Velocities") {
      if (data.has_velocities) in.fail(1, "a second Velocities section", std::string(kWrittenBy));
      read_velocities(in, data, atoms_read);
    } else if (keyword == "Masses" || keyword == "Pair Coeffs") {
      skip_section(in, keyword, types, header.have_types);
    } else if (keyword == "PairIJ Coeffs") {
      skip_section(in, keyword, types * (types + 1) / 2, header.have_types);
    } else if (is_number(in.words()[0].text)) {
      in.fail(in.words()[0].column, "a data line where a section keyword (Atoms, Velocities, …) belongs",
              "the section above has more lines than the header's count");
    } else {
      const std::string close = did_you_mean(keyword, kSections);
      in.fail(1, fmt::format("unsupported section \"{}\"", keyword),
              close.empty() ? "an atom_style sphere data file has Atoms and Velocities (and, "
                              "without nocoeff, Pair Coeffs)"
                            : close);
    }
    in_sections = in.next_with_words();
  }
  if (!atoms_read && data.atom_count > 0)
    in.fail_at(in.line(), 0, fmt::format("no Atoms section (the header announces {} atoms)", data.atom_count),
               std::string(kWrittenBy));
  return data;
}

std::string lammps_data_text(const LammpsData& data) {
  // %.17g keeps every double exact, so the reader gives back the very same bits.
  std::string text = (data.title.empty() ? std::string("LAMMPS data file") : data.title) + "\n\n";
  text += fmt::format("{} atoms\n{} atom types\n\n", data.atoms.size(), std::max(data.atom_types, 1));
  for (int d = 0; d < 3; ++d)
    text += fmt::format("{:.17g} {:.17g} {}lo {}hi\n", data.box_lo[d], data.box_hi[d], "xyz"[d], "xyz"[d]);
  text += "\nAtoms # sphere\n\n";
  for (const LammpsAtom& a : data.atoms)
    text += fmt::format("{} {} {:.17g} {:.17g} {:.17g} {:.17g} {:.17g}\n", a.id, a.type, a.diameter, a.density,
                        a.position.x, a.position.y, a.position.z);
  text += "\nVelocities\n\n";
  for (const LammpsAtom& a : data.atoms)
    text += fmt::format("{} {:.17g} {:.17g} {:.17g} {:.17g} {:.17g} {:.17g}\n", a.id, a.velocity.x, a.velocity.y,
                        a.velocity.z, a.angular_velocity.x, a.angular_velocity.y, a.angular_velocity.z);
  return text;
}

}  // namespace quarry::bench
