// Self-documenting configuration: the schema (type, default, unit, one-line doc, range) of
// every key is declared once in code; from it come validation (unknown keys, wrong types,
// out-of-range values rejected with key path, value, file and line), defaults, and the
// printed reference (`--print-config-reference`).
//
// Paths use dots for maps and `[]` for list items: "solver.cfl", "regions[].density".
// A key is declared after its parent: a map ("solver", Type::kMap) or a list of maps
// ("regions", Type::kList); an undeclared parent map is declared implicitly (no doc).
// A required key must be present whenever its parent map is; an optional map that is absent
// is not looked into. A map declared with open_sections() also takes undeclared sections
// (maps) that another program validates. `config_version` is declared by every Schema and
// checked first.
//
// Declaring a key reads best with the helpers below:
//   schema.add(key("solver.cfl", Type::kDouble, "-", "Courant number").def("0.5").gt(0).le(1));
#pragma once

#include <yaml-cpp/yaml.h>

#include <array>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace mpmdem::config {

inline constexpr int kConfigVersion = 1;  // `config_version:` this build reads

enum class Type {
  kDouble,      // number
  kInt,         // integer
  kBool,        // true/false
  kString,      // any string (not_empty(): at least one character)
  kEnum,        // one of KeySpec::choices
  kVec3,        // [x, y, z]
  kNumberList,  // [a, b, ...] numbers, each within min/max; may be empty
  kStringList,  // [a, b, ...] each one of KeySpec::choices if choices are given
                // (a single word from a fixed set is a kEnum: kString takes no choices)
  kMap,         // nested map: its keys are declared with the path as prefix
  kList,        // list of maps: item keys are declared as "path[].key"
};

struct KeySpec {
  std::string path;
  Type type = Type::kDouble;
  std::string default_yaml;  // default as YAML text; empty: no default
  bool required = false;     // must be present (only meaningful with no default)
  std::string unit;          // "m", "Pa", "s", "-" ...
  std::string doc;           // one line
  double min = -std::numeric_limits<double>::infinity();
  double max = std::numeric_limits<double>::infinity();
  bool min_exclusive = false;  // value must be > min instead of >= min
  std::vector<std::string> choices;
  bool max_exclusive = false;  // value must be < max instead of <= max
  bool nonempty = false;       // kString: the empty string is refused
  // kMap: keys it does not declare are accepted when they hold maps, not looked into here:
  // sections another program validates (mpm_app's `coupling:` holds the DEM backends'
  // sections, which dem_app declares). Non-empty: the doc of those sections.
  std::string open_doc;

  // Fluent setters for readable declarations (see key() below).
  KeySpec& def(std::string yaml) {
    default_yaml = std::move(yaml);
    return *this;
  }
  KeySpec& req() {
    required = true;
    return *this;
  }
  KeySpec& ge(double v) {
    min = v;
    min_exclusive = false;
    return *this;
  }
  KeySpec& gt(double v) {
    min = v;
    min_exclusive = true;
    return *this;
  }
  KeySpec& le(double v) {
    max = v;
    max_exclusive = false;
    return *this;
  }
  KeySpec& lt(double v) {
    max = v;
    max_exclusive = true;
    return *this;
  }
  KeySpec& one_of(std::vector<std::string> c) {
    choices = std::move(c);
    return *this;
  }
  KeySpec& not_empty() {
    nonempty = true;
    return *this;
  }
  KeySpec& open_sections(std::string sections_doc) {
    open_doc = std::move(sections_doc);
    return *this;
  }
};

// Start a declaration: key("solver.cfl", Type::kDouble, "-", "Courant number").
inline KeySpec key(std::string path, Type type, std::string unit, std::string doc) {
  KeySpec k;
  k.path = std::move(path);
  k.type = type;
  k.unit = std::move(unit);
  k.doc = std::move(doc);
  return k;
}

// Human-readable name of a type ("number", "list of maps", ...).
std::string type_name(Type type);
// Allowed range of a numeric key as text ("> 0", "[0, 1)"), empty if unbounded.
std::string range_text(const KeySpec& spec);

// A user/config fault: names what to change. Exit code 2 in the programs.
class ConfigError : public std::runtime_error {
 public:
  ConfigError(const std::string& file, int line, const std::string& key, const std::string& what);
  const std::string& file() const { return file_; }
  int line() const { return line_; }
  const std::string& key() const { return key_; }

 private:
  std::string file_;
  int line_;
  std::string key_;
};

class Schema {
 public:
  Schema();  // declares `config_version`
  // Declare a key. Declaring a path twice is a programming error (std::logic_error), except
  // a map, which may be re-declared (the later non-empty doc wins). Defaults are validated.
  Schema& add(KeySpec spec);
  const KeySpec* find(const std::string& path) const;
  const std::vector<KeySpec>& keys() const { return keys_; }
  // Keys whose parent is `parent` ("" for the top level, "solver", "regions[]"), in
  // declaration order.
  std::vector<const KeySpec*> children(const std::string& parent) const;
  // Markdown reference of every key: path, type, default, unit, range/choices, doc.
  std::string reference() const;

 private:
  std::vector<KeySpec> keys_;
};

// A validated document (or a view of one list item). Accessors take full schema paths
// relative to this view ("solver.cfl"; inside a list item "density") and return the value
// or the schema default. Asking for an undeclared path is a programming error (throws
// std::logic_error).
class Config {
 public:
  // Parse and validate `file`. If `section` is not empty, only `config_version` and that
  // top-level section are validated; other top-level keys are ignored (dem_app reads only
  // `coupling:`). Throws ConfigError.
  static Config load(const std::string& file, const Schema& schema,
                     const std::string& section = "");
  static Config from_string(const std::string& yaml_text, const Schema& schema,
                            const std::string& file_label = "<string>",
                            const std::string& section = "");

  bool has(const std::string& path) const;  // present in the file (not just defaulted)
  double number(const std::string& path) const;
  std::int64_t integer(const std::string& path) const;
  bool boolean(const std::string& path) const;
  std::string string(const std::string& path) const;  // kString and kEnum
  std::array<double, 3> vec3(const std::string& path) const;
  std::vector<double> numbers(const std::string& path) const;  // kNumberList
  std::vector<std::string> strings(const std::string& path) const;
  std::vector<Config> list(const std::string& path) const;  // items of a kList
  // 1-based line of the key, or of its nearest present section; list items are indexed
  // ("velocity_constraints[1].release_time").
  int line(const std::string& path) const;
  const std::string& file() const { return file_; }
  // Raise a ConfigError about `path` (for cross-key checks done by loaders). The message is
  // "<shown path> <what> (<file> line <n>)", e.g. fail("max", "[0, 0, 2] lies outside ...")
  // in the view of regions[0] gives "regions[0].max [0, 0, 2] lies outside ... (f line 9)".
  // An empty path names the view itself ("regions[0]").
  [[noreturn]] void fail(const std::string& path, const std::string& what) const;
  // Path as shown in messages: "max" in the view of regions[0] -> "regions[0].max".
  std::string shown(const std::string& path) const;
  const YAML::Node& root() const { return root_; }
  const Schema& schema() const { return *schema_; }
  // Canonical text (see canonical_yaml) of the top-level map `section` with the schema
  // defaults filled in for absent keys and numbers normalised (60, 60.0 and 6e1 read the
  // same), so a file that omits a key and one that writes its default give the same text.
  std::string canonical_text(const std::string& section) const;

 private:
  Config(YAML::Node root, const Schema* schema, std::string file, std::string prefix,
         std::string display);
  YAML::Node lookup(const std::string& path) const;
  const KeySpec& spec(const std::string& path) const;
  YAML::Node value_or_default(const std::string& path) const;

  YAML::Node root_;
  const Schema* schema_ = nullptr;
  std::string file_;
  std::string prefix_;   // schema path prefix of this view, e.g. "regions[]."
  std::string display_;  // shown prefix of this view in messages, e.g. "regions[0]."
};

// Canonical text of a YAML subtree (maps with sorted keys, numbers as written, flow style)
// so that two files that mean the same thing hash the same. Scalars are written plain when
// they consist of [A-Za-z0-9_.+-] only, else double-quoted with escapes; null is "~".
std::string canonical_yaml(const YAML::Node& node);
// Canonical text of the map `node` (absent: every default) read as the section `path` of
// `schema`: its declared keys normalised with defaults filled in, as Config::canonical_text,
// and, where the section is open (KeySpec::open_sections), its other keys as written.
std::string canonical_section_text(const Schema& schema, const YAML::Node& node,
                                   const std::string& path);
// Shortest decimal text that reads back as exactly `v` ("0.3", "1e+07", "60").
std::string format_number(double v);

}  // namespace mpmdem::config
