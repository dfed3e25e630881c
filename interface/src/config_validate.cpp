// Validation of a YAML document against a Schema: unknown keys, types, ranges and choices,
// each fault reported with key path, value, file and line.
#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <map>
#include <sstream>

#include "mpmdem/config/schema.hpp"

#include "config_detail.hpp"

namespace mpmdem::config {

namespace {

using namespace detail;

// ---- Validation -------------------------------------------------------------------------

// Walks a document against the schema; the first fault throws a ConfigError.
class Validator {
 public:
  Validator(const Schema& schema, std::string file) : schema_(schema), file_(std::move(file)) {}

  // A map whose keys are the children of schema path `parent` ("" = top level).
  // `shown` is its path as shown in messages ("" / "solver" / "regions[0]"), `line` the line
  // of its key (for missing-key messages).
  void map(const YAML::Node& node, const std::string& parent, const std::string& shown, int line,
           const std::string& only_section = "") {
    const std::string dot_shown = shown.empty() ? "" : shown + ".";
    std::map<std::string, int> seen;
    for (auto it = node.begin(); it != node.end(); ++it) {
      const YAML::Node k = it->first;  // a copy: `it->` returns a temporary proxy
      const YAML::Node v = it->second;
      const int key_line = line_of(k);
      if (!k.IsScalar()) fail(key_line, shown, "has a key that is not a plain name");
      const std::string name = k.Scalar();
      const std::string where = dot_shown + name;
      if (!only_section.empty() && name != only_section && name != "config_version") continue;
      if (auto [pos, fresh] = seen.emplace(name, key_line); !fresh) {
        fail(key_line, where,
             "appears twice (lines " + std::to_string(pos->second) + " and " +
                 std::to_string(key_line) + "); keep one");
      }
      const std::string path = parent.empty() ? name : parent + "." + name;
      const KeySpec* spec = schema_.find(path);
      if (!spec) {
        const KeySpec* owner = parent.empty() ? nullptr : schema_.find(parent);
        if (!owner || owner->open_doc.empty()) unknown(key_line, parent, name, where);
        if (!v.IsMap() && !v.IsNull()) {
          fail(key_line, where,
               "must be a map of keys (" + owner->open_doc + "), got " + describe(v));
        }
        continue;  // another program's section
      }
      value(*spec, v, where, key_line);
    }
    // Required keys and required sections of this map.
    for (const KeySpec* c : schema_.children(parent)) {
      const std::string name = leaf_of(c->path);
      if (!only_section.empty() && name != only_section) continue;
      if (c->required && !seen.count(name)) {
        const std::string in = shown.empty()
                                   ? "at the top level of the file"
                                   : "in '" + shown + "' (line " + std::to_string(line) + ")";
        const bool section = c->type == Type::kMap || c->type == Type::kList;
        const std::string unit = c->unit.empty() || c->unit == "-" ? "" : ", " + c->unit;
        fail(line, dot_shown + name,
             "is required but missing " + in + ": " + c->doc +
                 (section ? "" : " [" + type_name(c->type) + unit + "]"));
      }
    }
  }

  // One value of key `spec`, shown as `where`, whose key is on `line`.
  void value(const KeySpec& spec, const YAML::Node& v, const std::string& where, int line) {
    switch (spec.type) {
      case Type::kMap:
        if (v.IsNull()) {  // `section:` with nothing under it: all defaults
          map(YAML::Node(YAML::NodeType::Map), spec.path, where, line);
          return;
        }
        if (!v.IsMap()) fail(line, where, "must be a map of keys, got " + describe(v));
        map(v, spec.path, where, line);
        return;
      case Type::kList: {
        if (v.IsNull()) return;
        if (!v.IsSequence()) fail(line, where, "must be a list of maps, got " + describe(v));
        for (std::size_t i = 0; i < v.size(); ++i) {
          const YAML::Node item = v[i];
          const std::string item_where = where + "[" + std::to_string(i) + "]";
          const int item_line = line_of(item) ? line_of(item) : line;
          if (!item.IsMap()) {
            fail(item_line, item_where, "must be a map of keys, got " + describe(item));
          }
          map(item, spec.path + "[]", item_where, item_line);
        }
        return;
      }
      case Type::kDouble:
        range(spec, number(v, where, line), where, line);
        return;
      case Type::kInt: {
        std::int64_t i = 0;
        if (!v.IsScalar() || is_quoted(v) || !parse_int(v.Scalar(), i)) {
          fail(line, where, "must be an integer, got " + describe(v));
        }
        range(spec, static_cast<double>(i), where, line);
        return;
      }
      case Type::kBool:
        if (!v.IsScalar() || is_quoted(v) || (v.Scalar() != "true" && v.Scalar() != "false")) {
          fail(line, where, "must be true or false, got " + describe(v));
        }
        return;
      case Type::kString:
        if (!v.IsScalar()) fail(line, where, "must be a string, got " + describe(v));
        if (spec.nonempty && v.Scalar().empty()) {
          fail(line, where, "must not be empty: " + spec.doc);
        }
        return;
      case Type::kEnum:
        if (!v.IsScalar() ||
            std::find(spec.choices.begin(), spec.choices.end(), v.Scalar()) == spec.choices.end()) {
          fail(line, where, "must be one of " + join(spec.choices, ", ") + "; got " + describe(v));
        }
        return;
      case Type::kVec3: {
        if (!v.IsSequence() || v.size() != 3) {
          fail(line, where, "must be a list of 3 numbers [x, y, z], got " + describe(v));
        }
        std::vector<double> xyz;
        for (std::size_t i = 0; i < 3; ++i) {
          xyz.push_back(number(v[i], where + "[" + std::to_string(i) + "]", line));
        }
        for (double c : xyz) {
          if (!in_range(spec, c)) {
            fail(line, where, "components must be " + range_text(spec) + ", got " + vec_text(xyz));
          }
        }
        return;
      }
      case Type::kNumberList: {
        if (v.IsNull()) return;  // empty list
        if (!v.IsSequence())
          fail(line, where, "must be a list of numbers [a, b, ...], got " + describe(v));
        for (std::size_t i = 0; i < v.size(); ++i) {
          const std::string item_where = where + "[" + std::to_string(i) + "]";
          range(spec, number(v[i], item_where, line), item_where, line);
        }
        return;
      }
      case Type::kStringList: {
        if (v.IsNull()) return;  // empty list
        if (!v.IsSequence()) fail(line, where, "must be a list [a, b, ...], got " + describe(v));
        std::vector<std::string> seen;
        for (std::size_t i = 0; i < v.size(); ++i) {
          const std::string item_where = where + "[" + std::to_string(i) + "]";
          const YAML::Node item = v[i];
          if (!item.IsScalar()) fail(line, item_where, "must be a string, got " + describe(item));
          if (!spec.choices.empty() && std::find(spec.choices.begin(), spec.choices.end(),
                                                 item.Scalar()) == spec.choices.end()) {
            fail(line, item_where,
                 "must be one of " + join(spec.choices, ", ") + "; got " + describe(item));
          }
          if (std::find(seen.begin(), seen.end(), item.Scalar()) != seen.end()) {
            fail(line, item_where, "repeats '" + item.Scalar() + "'");
          }
          seen.push_back(item.Scalar());
        }
        return;
      }
    }
  }

 private:
  [[noreturn]] void fail(int line, const std::string& where, const std::string& what) const {
    throw ConfigError(file_, line, where, (where.empty() ? "" : where + " ") + what);
  }

  [[noreturn]] void unknown(int line, const std::string& parent, const std::string& name,
                            const std::string& where) const {
    std::string hint;
    std::size_t best = std::string::npos;
    std::vector<std::string> names;
    for (const KeySpec* c : schema_.children(parent)) {
      const std::string cand = leaf_of(c->path);
      names.push_back(cand);
      const std::size_t d = edit_distance(name, cand);
      if (d < best && d <= std::max<std::size_t>(2, cand.size() / 3)) {
        best = d;
        hint = cand;
      }
    }
    std::string what = "unknown key '" + where + "'";
    if (!hint.empty()) {
      what += " (did you mean '" + hint + "'?)";
    } else if (!names.empty()) {
      what += " (known keys here: " + join(names, ", ") + ")";
    }
    throw ConfigError(file_, line, where, what);
  }

  double number(const YAML::Node& v, const std::string& where, int line) const {
    double d = 0.0;
    if (!v.IsScalar() || is_quoted(v) || !parse_double(v.Scalar(), d) || !std::isfinite(d)) {
      fail(line, where, "must be a number, got " + describe(v));
    }
    return d;
  }

  void range(const KeySpec& spec, double v, const std::string& where, int line) const {
    if (!in_range(spec, v)) {
      fail(line, where, "must be " + range_text(spec) + ", got " + format_number(v));
    }
  }

  const Schema& schema_;
  std::string file_;
};

// The version gate, before anything else: a file of another format version would produce
// confusing unknown-key messages.
void check_version(const YAML::Node& root, const std::string& file) {
  const YAML::Node v = root["config_version"];
  if (!v.IsDefined() || v.IsNull()) {
    throw ConfigError(file, line_of(root), "config_version",
                      "config_version is missing: every config file starts with "
                      "'config_version: " +
                          std::to_string(kConfigVersion) + "'");
  }
  int line = line_of(v);
  for (auto it = root.begin(); it != root.end(); ++it) {
    if (it->first.IsScalar() && it->first.Scalar() == "config_version") line = line_of(it->first);
  }
  std::int64_t n = 0;
  if (!v.IsScalar() || is_quoted(v) || !parse_int(v.Scalar(), n)) {
    throw ConfigError(file, line, "config_version",
                      "config_version must be an integer, got " + describe(v));
  }
  if (n > kConfigVersion) {
    throw ConfigError(file, line, "config_version",
                      "config_version " + std::to_string(n) + " is newer than this build reads (" +
                          std::to_string(kConfigVersion) + "): upgrade mpmdem");
  }
  if (n < kConfigVersion) {
    throw ConfigError(file, line, "config_version",
                      "config_version " + std::to_string(n) + " is older than this build reads (" +
                          std::to_string(kConfigVersion) + "), and there is no older format: " +
                          "version 1 is the first; write 'config_version: 1'");
  }
}

}  // namespace

namespace detail {

void validate(const YAML::Node& root, const Schema& schema, const std::string& file,
              const std::string& section) {
  check_version(root, file);
  if (!section.empty()) {
    const KeySpec* s = schema.find(section);
    if (!s || parent_of(section) != "") {
      throw std::logic_error("Config::load: section '" + section + "' is not in the schema");
    }
  }
  Validator(schema, file).map(root, "", "", line_of(root), section);
}

void validate_value(const Schema& schema, const KeySpec& spec, const YAML::Node& value,
                    const std::string& path) {
  Validator(schema, "schema default").value(spec, value, path, 0);
}

}  // namespace detail

}  // namespace mpmdem::config
