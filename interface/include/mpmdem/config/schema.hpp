// Self-documenting configuration: the schema (type, default, unit, one-line doc, range) of
// every key is declared once in code; from it come validation (unknown keys, wrong types,
// out-of-range values rejected with key path, value, file and line), defaults, and the
// printed reference (`--print-config-reference`).
//
// Paths use dots for maps and `[]` for list items: "solver.cfl", "regions[].density".
#pragma once

#include <yaml-cpp/yaml.h>

#include <array>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace mpmdem::config {

inline constexpr int kConfigVersion = 1;  // `config_version:` this build reads

enum class Type {
  kDouble,      // number
  kInt,         // integer
  kBool,        // true/false
  kString,      // any string
  kEnum,        // one of KeySpec::choices
  kVec3,        // [x, y, z]
  kStringList,  // [a, b, ...] each one of KeySpec::choices if choices are given
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
};

// A user/config fault: names what to change. Exit code 2 in the programs.
class ConfigError : public std::runtime_error {
 public:
  ConfigError(const std::string& file, int line, const std::string& key,
              const std::string& what);
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
  Schema& add(KeySpec spec);
  const KeySpec* find(const std::string& path) const;
  const std::vector<KeySpec>& keys() const { return keys_; }
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
  std::vector<std::string> strings(const std::string& path) const;
  std::vector<Config> list(const std::string& path) const;  // items of a kList
  int line(const std::string& path) const;  // 1-based line of the key, or of the section
  const std::string& file() const { return file_; }
  // Raise a ConfigError about `path` (for cross-key checks done by loaders).
  [[noreturn]] void fail(const std::string& path, const std::string& what) const;
  const YAML::Node& root() const { return root_; }

 private:
  Config(YAML::Node root, const Schema* schema, std::string file, std::string prefix);
  YAML::Node lookup(const std::string& path) const;
  const KeySpec& spec(const std::string& path) const;
  YAML::Node value_or_default(const std::string& path) const;

  YAML::Node root_;
  const Schema* schema_ = nullptr;
  std::string file_;
  std::string prefix_;  // schema path prefix of this view, e.g. "regions[]."
};

// Canonical text of a YAML subtree (maps with sorted keys, numbers as written, flow style)
// so that two files that mean the same thing hash the same.
std::string canonical_yaml(const YAML::Node& node);

}  // namespace mpmdem::config
