// Gmsh MSH 4.1 ASCII reader (format: Gmsh reference manual, "MSH file format", version 4.1):
// $MeshFormat, $PhysicalNames, $Entities (physical tags of each surface), $Nodes and $Elements
// are read as a stream of whitespace-separated tokens; other sections are skipped. A token
// that breaks the layout stops the read; problems of content (element types, tags, names) are
// collected and reported together.
#include "io/gmsh_reader.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <string_view>
#include <vector>

namespace quarry {

namespace {

// Nodes of each Gmsh element type (the manual's element table); types not listed are unknown.
int nodes_of_type(int type) {
  switch (type) {
    case 15:
      return 1;  // point
    case 1:
      return 2;  // 2-node line
    case 2:
      return 3;  // 3-node triangle
    case 3:
      return 4;  // 4-node quadrangle
    case 4:
      return 4;  // 4-node tetrahedron
    case 5:
      return 8;  // 8-node hexahedron
    case 6:
      return 6;  // 6-node prism
    case 7:
      return 5;  // 5-node pyramid
    case 8:
      return 3;  // 3-node line
    case 9:
      return 6;  // 6-node triangle
    case 10:
      return 9;  // 9-node quadrangle
    case 11:
      return 10;  // 10-node tetrahedron
    case 12:
      return 27;  // 27-node hexahedron
    case 13:
      return 18;  // 18-node prism
    case 14:
      return 14;  // 14-node pyramid
    case 16:
      return 8;  // 8-node quadrangle
    case 17:
      return 20;  // 20-node hexahedron
    case 18:
      return 15;  // 15-node prism
    case 19:
      return 13;  // 13-node pyramid
    default:
      return 0;
  }
}

struct Token {
  std::string_view text;
  int line = 0;
  int column = 0;
};

// Ends the read at once: the layout is broken, so nothing after this token can be trusted.
struct LayoutError {
  SourceLocation where;
  std::string message;
  std::string hint;
};

class GmshParser {
 public:
  GmshParser(const std::string& text, std::string display_name, double length_scale)
      : display_name_(std::move(display_name)), length_scale_(length_scale) {
    tokenize(text);
  }

  StructureModel parse() {
    bool format_read = false;
    bool nodes_read = false;
    bool elements_read = false;
    while (next_ < tokens_.size()) {
      const Token& header = take("a section");
      if (header.text.empty() || header.text.front() != '$')
        fail(header, fmt::format("expected a section such as $Nodes, got \"{}\"", header.text),
             "a .msh file is a sequence of sections $Name ... $EndName");
      const std::string_view name = header.text.substr(1);
      if (!format_read && name != "MeshFormat")
        fail(header, "the file does not start with $MeshFormat",
             "is this a Gmsh .msh file? Save it from Gmsh as version 4.1 ASCII");
      if (name == "MeshFormat") {
        mesh_format();
        format_read = true;
      } else if (name == "PhysicalNames") {
        physical_names();
      } else if (name == "Entities") {
        entities();
      } else if (name == "Nodes") {
        nodes();
        nodes_read = true;
      } else if (name == "Elements") {
        if (!nodes_read)
          fail(header, "$Elements before $Nodes", "Gmsh writes $Nodes first; re-save the mesh");
        elements();
        elements_read = true;
      } else {
        skip_section(header, name);
        continue;
      }
      expect(fmt::format("$End{}", name));
    }
    const Token end{"", static_cast<int>(line_count_), 1};
    if (!format_read)
      fail(end, "the file is empty", "save the mesh from Gmsh as version 4.1 ASCII");
    if (!nodes_read || !elements_read)
      fail(end, fmt::format("the mesh has no {} section", nodes_read ? "$Elements" : "$Nodes"),
           "save the mesh from Gmsh as version 4.1 ASCII");
    build_sets();
    if (model_.shells.empty() && !errors_.has_errors())
      errors_.error(location(end), "the mesh has no triangles or quadrangles",
                    "mesh the surfaces (2-D) in Gmsh; volume meshes are not shell models");
    if (errors_.has_errors()) throw UserError(errors_);
    if (skipped_lower_dimension_ > 0)
      model_.notes.note(
          location(first_skipped_),
          fmt::format("{} element{} of points and curves skipped", skipped_lower_dimension_,
                      skipped_lower_dimension_ == 1 ? "" : "s"),
          "a shell model is made of the surfaces' triangles and quadrangles");
    model_.source_files = {display_name_};
    return std::move(model_);
  }

 private:
  void tokenize(const std::string& text) {
    std::string_view rest(text);
    int line = 0;
    while (!rest.empty()) {
      const std::size_t end = rest.find('\n');
      std::string_view content = rest.substr(0, end);
      rest = end == std::string_view::npos ? std::string_view() : rest.substr(end + 1);
      ++line;
      std::size_t i = 0;
      while (i < content.size()) {
        while (i < content.size() && std::isspace(static_cast<unsigned char>(content[i]))) ++i;
        if (i >= content.size()) break;
        const std::size_t begin = i;
        if (content[i] == '"') {
          const std::size_t close = content.find('"', i + 1);
          i = close == std::string_view::npos ? content.size() : close + 1;
        } else {
          while (i < content.size() && !std::isspace(static_cast<unsigned char>(content[i]))) ++i;
        }
        tokens_.push_back({content.substr(begin, i - begin), line, static_cast<int>(begin) + 1});
      }
    }
    line_count_ = static_cast<std::size_t>(std::max(line, 1));
  }

  SourceLocation location(const Token& token) const {
    return {display_name_, token.line, token.column};
  }

  [[noreturn]] void fail(const Token& token, std::string message, std::string hint = {}) {
    errors_.error(location(token), std::move(message), std::move(hint));
    throw UserError(errors_);
  }

  const Token& take(const char* what) {
    if (next_ >= tokens_.size()) {
      const Token end{"", static_cast<int>(line_count_), 1};
      fail(end, fmt::format("the file ends where {} is expected", what),
           "the file is cut short; save it again from Gmsh");
    }
    return tokens_[next_++];
  }

  void expect(const std::string& word) {
    const Token& token = take(word.c_str());
    if (token.text != word)
      fail(token, fmt::format("expected {}, got \"{}\"", word, token.text),
           "the counts at the start of the section do not match its content");
  }

  std::int64_t integer(const char* what) {
    const Token& token = take(what);
    std::int64_t value = 0;
    const auto [end, error] =
        std::from_chars(token.text.data(), token.text.data() + token.text.size(), value);
    if (error != std::errc() || end != token.text.data() + token.text.size())
      fail(token, fmt::format("expected an integer ({}), got \"{}\"", what, token.text));
    return value;
  }

  std::size_t count(const char* what) {
    const Token& token = tokens_[std::min(next_, tokens_.size() - 1)];
    const std::int64_t value = integer(what);
    if (value < 0) fail(token, fmt::format("{} must be ≥ 0, got {}", what, value));
    return static_cast<std::size_t>(value);
  }

  double real(const char* what) {
    const Token& token = take(what);
    double value = 0.0;
    const auto [end, error] =
        std::from_chars(token.text.data(), token.text.data() + token.text.size(), value);
    if (error != std::errc() || end != token.text.data() + token.text.size() ||
        !std::isfinite(value))
      fail(token, fmt::format("expected a number ({}), got \"{}\"", what, token.text));
    return value;
  }

  void skip_section(const Token& header, std::string_view name) {
    const std::string end = fmt::format("$End{}", name);
    while (next_ < tokens_.size())
      if (tokens_[next_++].text == end) return;
    fail(header, fmt::format("section ${} has no {}", name, end));
  }

  void mesh_format() {
    const Token& version = take("the format version");
    if (version.text != "4.1")
      fail(version, fmt::format("MSH format version {} is not supported", version.text),
           "save the mesh as version 4.1 ASCII (Gmsh: Mesh.MshFileVersion = 4.1, or "
           "gmsh -format msh41)");
    const Token& file_type = take("the file type");
    if (file_type.text != "0")
      fail(file_type, "binary .msh files are not supported",
           "save the mesh as ASCII (Gmsh: Mesh.Binary = 0)");
    integer("the data size");
  }

  void physical_names() {
    const std::size_t n = count("the number of physical names");
    for (std::size_t i = 0; i < n; ++i) {
      const int dimension = static_cast<int>(integer("a physical group's dimension"));
      const int tag = static_cast<int>(integer("a physical tag"));
      const Token& name = take("a physical name");
      if (name.text.size() < 2 || name.text.front() != '"' || name.text.back() != '"')
        fail(name, fmt::format("expected a quoted physical name, got {}", name.text));
      physical_names_[{dimension, tag}] = {std::string(name.text.substr(1, name.text.size() - 2)),
                                           name};
    }
  }

  // Physical tags of each surface entity (points, curves and volumes are read past).
  void entities() {
    std::size_t counts[4];
    counts[0] = count("the number of points");
    counts[1] = count("the number of curves");
    counts[2] = count("the number of surfaces");
    counts[3] = count("the number of volumes");
    for (int dimension = 0; dimension < 4; ++dimension) {
      for (std::size_t i = 0; i < counts[dimension]; ++i) {
        const int tag = static_cast<int>(integer("an entity tag"));
        const int coordinates = dimension == 0 ? 3 : 6;  // a point, or a bounding box
        for (int k = 0; k < coordinates; ++k) real("an entity coordinate");
        const std::size_t physicals = count("the number of physical tags");
        std::vector<int> tags;
        for (std::size_t k = 0; k < physicals; ++k)
          tags.push_back(static_cast<int>(integer("a physical tag")));
        if (dimension == 2) surface_physicals_[tag] = std::move(tags);
        else if (dimension < 2) lower_physicals_[{dimension, tag}] = std::move(tags);
        if (dimension > 0) {
          const std::size_t bounding = count("the number of bounding entities");
          for (std::size_t k = 0; k < bounding; ++k) integer("a bounding entity tag");
        }
      }
    }
  }

  void nodes() {
    const std::size_t blocks = count("the number of node blocks");
    count("the number of nodes");
    integer("the smallest node tag");
    integer("the largest node tag");
    for (std::size_t b = 0; b < blocks; ++b) {
      const int dimension = static_cast<int>(integer("a node block's entity dimension"));
      integer("a node block's entity tag");
      const bool parametric = integer("the parametric flag") != 0;
      const std::size_t n = count("the number of nodes in a block");
      std::vector<const Token*> tags;
      tags.reserve(n);
      for (std::size_t i = 0; i < n; ++i) {
        tags.push_back(&tokens_[std::min(next_, tokens_.size() - 1)]);
        integer("a node tag");
      }
      for (std::size_t i = 0; i < n; ++i) {
        const Token& first = tokens_[std::min(next_, tokens_.size() - 1)];
        Vec3 position;
        position.x = real("a node's x");
        position.y = real("a node's y");
        position.z = real("a node's z");
        if (parametric)
          for (int k = 0; k < std::clamp(dimension, 0, 3); ++k) real("a parametric coordinate");
        add_node(*tags[i], position * length_scale_, first.line);
      }
    }
  }

  void add_node(const Token& tag_token, const Vec3& position, int line) {
    std::int64_t tag = 0;
    std::from_chars(tag_token.text.data(), tag_token.text.data() + tag_token.text.size(), tag);
    if (tag < 1 || tag > std::numeric_limits<int>::max()) {
      errors_.error(location(tag_token), fmt::format("node tag {} is out of range", tag));
      return;
    }
    GridPoint node;
    node.position = position;
    node.where = {0, line};
    const auto [entry, inserted] = model_.nodes.emplace(static_cast<int>(tag), node);
    if (!inserted)
      errors_.error(location(tag_token), fmt::format("duplicate node tag {}", tag),
                    fmt::format("first defined on line {}", entry->second.where.line));
  }

  void elements() {
    const std::size_t blocks = count("the number of element blocks");
    count("the number of elements");
    integer("the smallest element tag");
    integer("the largest element tag");
    for (std::size_t b = 0; b < blocks; ++b) {
      const int dimension = static_cast<int>(integer("an element block's entity dimension"));
      const int entity = static_cast<int>(integer("an element block's entity tag"));
      const Token& type_token = tokens_[std::min(next_, tokens_.size() - 1)];
      const int type = static_cast<int>(integer("an element type"));
      const std::size_t n = count("the number of elements in a block");
      const int node_count = nodes_of_type(type);
      if (node_count == 0)
        fail(type_token, fmt::format("unknown Gmsh element type {}", type),
             "save the mesh with first-order triangles and quadrangles");
      const bool shell = dimension == 2 && (type == 2 || type == 3);
      if (!shell && dimension >= 2)
        errors_.error(
            location(type_token),
            dimension == 3 ? fmt::format("volume elements (Gmsh type {}) are not supported", type)
                           : fmt::format("surface element type {} is not supported", type),
            dimension == 3 ? "a shell model is a surface mesh: mesh the surfaces only (2-D)"
                           : "only first-order triangles (type 2) and quadrangles (type 3) are "
                             "read; mesh with Mesh.ElementOrder = 1");
      for (std::size_t i = 0; i < n; ++i) {
        const Token& tag_token = tokens_[std::min(next_, tokens_.size() - 1)];
        const std::int64_t tag = integer("an element tag");
        std::array<const Token*, 4> node_tokens{};
        std::array<std::int64_t, 4> node_tags{};
        for (int k = 0; k < node_count; ++k) {
          const Token& node_token = tokens_[std::min(next_, tokens_.size() - 1)];
          const std::int64_t node = integer("an element's node tag");
          if (k < 4) {
            node_tokens[static_cast<std::size_t>(k)] = &node_token;
            node_tags[static_cast<std::size_t>(k)] = node;
          }
        }
        if (dimension < 2) {
          if (skipped_lower_dimension_++ == 0) first_skipped_ = tag_token;
          // Its nodes join its entity's physical groups (supports named in the deck).
          if (const auto groups = lower_physicals_.find({dimension, entity});
              groups != lower_physicals_.end())
            for (int k = 0; k < std::min(node_count, 4); ++k) {
              const std::int64_t node = node_tags[static_cast<std::size_t>(k)];
              if (!known_node(tag, node, *node_tokens[static_cast<std::size_t>(k)])) break;
              for (const int group : groups->second)
                group_nodes_[{dimension, group}].push_back(static_cast<int>(node));
            }
          continue;
        }
        if (shell) add_shell(tag_token, tag, entity, type == 3 ? 4 : 3, node_tokens, node_tags);
      }
    }
  }

  // Whether element `tag`'s node tag `node` (at `token`) is in $Nodes; an error there if not.
  bool known_node(std::int64_t tag, std::int64_t node, const Token& token) {
    if (node >= 1 && node <= std::numeric_limits<int>::max() &&
        model_.nodes.count(static_cast<int>(node)))
      return true;
    errors_.error(location(token),
                  fmt::format("element {} names node {}, which is not in $Nodes", tag, node));
    return false;
  }

  // Whether `name` (at `where`) is the first group of its kind (`groups`, for the message) so
  // named; an error there if not, since the deck names groups.
  bool first_named(std::map<std::string, const Token*>& seen, const std::string& name,
                   const Token& where, std::string_view groups) {
    const auto [entry, inserted] = seen.emplace(name, &where);
    if (!inserted)
      errors_.error(location(where), fmt::format("two {} are named \"{}\"", groups, name),
                    fmt::format("first on line {}; the deck names groups, so each name must "
                                "be unique",
                                entry->second->line));
    return inserted;
  }

  void add_shell(const Token& tag_token, std::int64_t tag, int entity, int node_count,
                 const std::array<const Token*, 4>& node_tokens,
                 const std::array<std::int64_t, 4>& node_tags) {
    if (tag < 1 || tag > std::numeric_limits<int>::max()) {
      errors_.error(location(tag_token), fmt::format("element tag {} is out of range", tag));
      return;
    }
    ShellElement element;
    element.id = static_cast<int>(tag);
    element.shape = node_count == 4 ? ShellShape::quad4 : ShellShape::tria3;
    element.where = {0, tag_token.line};
    for (int k = 0; k < node_count; ++k) {
      const std::size_t index = static_cast<std::size_t>(k);
      const std::int64_t node = node_tags[index];
      if (!known_node(tag, node, *node_tokens[index])) return;
      element.nodes[index] = static_cast<int>(node);
    }
    if (!element_ids_.insert(element.id).second) {
      errors_.error(location(tag_token), fmt::format("duplicate element tag {}", tag));
      return;
    }
    model_.shells.push_back(element);
    entity_of_shell_.push_back(entity);
  }

  // One element set per physical group of dimension 2.
  void build_sets() {
    std::map<std::string, const Token*> names_in_use;
    for (const auto& [key, named] : physical_names_)
      if (key.first == 2)
        first_named(names_in_use, named.first, named.second, "surface physical groups");
    for (const auto& [entity, tags] : surface_physicals_) {
      for (const int tag : tags) {
        IdSet& set = model_.sets[tag];
        set.id = tag;
        set.kind = SetKind::element;
        if (auto name = physical_names_.find({2, tag}); name != physical_names_.end()) {
          set.name = name->second.first;
          set.where = {0, name->second.second.line};
        }
      }
    }
    for (std::size_t i = 0; i < model_.shells.size(); ++i) {
      const auto tags = surface_physicals_.find(entity_of_shell_[i]);
      if (tags == surface_physicals_.end()) continue;
      for (const int tag : tags->second) model_.sets[tag].members.push_back(model_.shells[i].id);
    }
    for (auto& entry : model_.sets) {
      std::vector<int>& members = entry.second.members;
      std::sort(members.begin(), members.end());
      members.erase(std::unique(members.begin(), members.end()), members.end());
    }
    // The named physical groups of points and curves: their elements' nodes.
    std::map<std::string, const Token*> node_names;
    for (const auto& [key, named] : physical_names_) {
      if (key.first >= 2 || !first_named(node_names, named.first, named.second,
                                         "physical groups of points or curves"))
        continue;
      IdSet group;
      group.id = key.second;
      group.kind = SetKind::grid;
      group.name = named.first;
      group.where = {0, named.second.line};
      if (const auto nodes = group_nodes_.find(key); nodes != group_nodes_.end()) {
        group.members = nodes->second;
        std::sort(group.members.begin(), group.members.end());
        group.members.erase(std::unique(group.members.begin(), group.members.end()),
                            group.members.end());
      }
      model_.node_groups.push_back(std::move(group));
    }
  }

  std::string display_name_;
  double length_scale_;
  std::vector<Token> tokens_;
  std::size_t next_ = 0;
  std::size_t line_count_ = 1;
  Diagnostics errors_;
  StructureModel model_;
  std::map<std::pair<int, int>, std::pair<std::string, Token>> physical_names_;  // (dim, tag)
  std::map<int, std::vector<int>> surface_physicals_;  // surface entity -> physical tags
  // (dimension, point or curve entity) -> physical tags; (dimension, physical tag) -> nodes.
  std::map<std::pair<int, int>, std::vector<int>> lower_physicals_, group_nodes_;
  std::set<int> element_ids_;
  std::vector<int> entity_of_shell_;  // parallel to model_.shells
  std::size_t skipped_lower_dimension_ = 0;
  Token first_skipped_;
};

}  // namespace

StructureModel read_gmsh_string(const std::string& text, const std::string& display_name,
                                const GmshReadOptions& options) {
  if (!options.units)
    throw UserError({display_name, 1, 1}, "a Gmsh mesh does not say its length unit",
                    "state the units in the deck: SI (coordinates in m) or MPA (in mm)");
  const double length_scale = *options.units == UnitSystem::si ? 1.0 : 1e-3;  // m per unit
  GmshParser parser(text, display_name, length_scale);
  StructureModel model = parser.parse();
  model.declared_units = *options.units;
  return model;
}

StructureModel read_gmsh(const std::string& path, const GmshReadOptions& options) {
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw UserError({path, 0, 0}, "cannot open the mesh file",
                    "check the path; it is relative to the current directory");
  std::ostringstream text;
  text << in.rdbuf();
  return read_gmsh_string(text.str(), path, options);
}

}  // namespace quarry
