// Schema declaration, validation of a YAML document against it, typed access with
// defaults, and the printed reference. See mpmdem/config/schema.hpp.
#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <map>
#include <sstream>

#include "mpmdem/config/schema.hpp"

namespace mpmdem::config {

namespace {

// ---- Paths ------------------------------------------------------------------------------

// "solver.cfl" -> "solver"; "regions[].min" -> "regions[]"; "scene" -> "".
std::string parent_of(const std::string& path) {
  const auto dot = path.rfind('.');
  return dot == std::string::npos ? std::string() : path.substr(0, dot);
}

std::string leaf_of(const std::string& path) {
  const auto dot = path.rfind('.');
  return dot == std::string::npos ? path : path.substr(dot + 1);
}

std::vector<std::string> split_path(const std::string& path) {
  std::vector<std::string> parts;
  std::string::size_type start = 0;
  while (true) {
    const auto dot = path.find('.', start);
    parts.push_back(path.substr(start, dot - start));
    if (dot == std::string::npos) break;
    start = dot + 1;
  }
  return parts;
}

int line_of(const YAML::Node& node) {
  const YAML::Mark m = node.Mark();
  return m.is_null() ? 0 : m.line + 1;
}

// ---- Scalars ----------------------------------------------------------------------------

bool is_quoted(const YAML::Node& n) {
  return n.Tag() == "!";
}

bool parse_double(const std::string& text, double& out) {
  if (text.empty()) return false;
  errno = 0;
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (end != text.c_str() + text.size() || errno == ERANGE) return false;
  out = v;
  return true;
}

bool parse_int(const std::string& text, std::int64_t& out) {
  if (text.empty()) return false;
  errno = 0;
  char* end = nullptr;
  const long long v = std::strtoll(text.c_str(), &end, 10);
  if (end != text.c_str() + text.size() || errno == ERANGE) return false;
  out = v;
  return true;
}

// What a node is, for "got ..." in messages.
std::string describe(const YAML::Node& n) {
  if (!n.IsDefined() || n.IsNull()) return "nothing";
  if (n.IsSequence()) return "a list";
  if (n.IsMap()) return "a map";
  if (is_quoted(n)) return "the quoted string \"" + n.Scalar() + "\"";
  return "'" + n.Scalar() + "'";
}

std::string vec_text(const std::vector<double>& v) {
  std::string s = "[";
  for (std::size_t i = 0; i < v.size(); ++i) s += (i ? ", " : "") + format_number(v[i]);
  return s + "]";
}

std::string join(const std::vector<std::string>& items, const std::string& sep) {
  std::string s;
  for (std::size_t i = 0; i < items.size(); ++i) s += (i ? sep : "") + items[i];
  return s;
}

bool in_range(const KeySpec& s, double v) {
  if (s.min_exclusive ? !(v > s.min) : !(v >= s.min)) return false;
  if (s.max_exclusive ? !(v < s.max) : !(v <= s.max)) return false;
  return true;
}

std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diag = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diag = up;
    }
  }
  return row[b.size()];
}

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
      if (!spec) unknown(key_line, parent, name, where);
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

std::string cell(std::string s) {
  std::string out;
  for (char c : s) {
    if (c == '|')
      out += "\\|";
    else
      out += c;
  }
  return out;
}

}  // namespace

// ---- Free helpers -----------------------------------------------------------------------

std::string type_name(Type type) {
  switch (type) {
    case Type::kDouble:
      return "number";
    case Type::kInt:
      return "integer";
    case Type::kBool:
      return "bool";
    case Type::kString:
      return "string";
    case Type::kEnum:
      return "choice";
    case Type::kVec3:
      return "[x, y, z]";
    case Type::kStringList:
      return "list of strings";
    case Type::kMap:
      return "map";
    case Type::kList:
      return "list of maps";
  }
  return "?";
}

std::string range_text(const KeySpec& s) {
  const bool lo = std::isfinite(s.min), hi = std::isfinite(s.max);
  if (lo && hi) {
    return std::string(s.min_exclusive ? "in (" : "in [") + format_number(s.min) + ", " +
           format_number(s.max) + (s.max_exclusive ? ")" : "]");
  }
  if (lo) return std::string(s.min_exclusive ? "> " : ">= ") + format_number(s.min);
  if (hi) return std::string(s.max_exclusive ? "< " : "<= ") + format_number(s.max);
  return "";
}

// ---- ConfigError ------------------------------------------------------------------------

namespace {
std::string located(const std::string& file, int line, const std::string& what) {
  if (file.empty()) return what;
  return what + " (" + file + (line > 0 ? " line " + std::to_string(line) : "") + ")";
}
}  // namespace

ConfigError::ConfigError(const std::string& file, int line, const std::string& key,
                         const std::string& what)
    : std::runtime_error(located(file, line, what)), file_(file), line_(line), key_(key) {}

// ---- Schema -----------------------------------------------------------------------------

Schema::Schema() {
  add(key("config_version", Type::kInt, "-",
          "format version of the file; this build reads " + std::to_string(kConfigVersion))
          .req()
          .ge(1));
}

Schema& Schema::add(KeySpec spec) {
  const std::string& path = spec.path;
  if (path.empty() || path.front() == '.' || path.back() == '.') {
    throw std::logic_error("schema: bad key path '" + path + "'");
  }
  const std::string parent = parent_of(path);
  if (!parent.empty()) {
    const bool list_item = parent.size() > 2 && parent.compare(parent.size() - 2, 2, "[]") == 0;
    const std::string owner = list_item ? parent.substr(0, parent.size() - 2) : parent;
    const KeySpec* p = find(owner);
    if (list_item) {
      if (!p || p->type != Type::kList) {
        throw std::logic_error("schema: '" + path + "' needs '" + owner +
                               "' declared as a list first");
      }
    } else if (!p) {
      add(key(owner, Type::kMap, "", ""));  // implicit section
    } else if (p->type != Type::kMap) {
      throw std::logic_error("schema: parent of '" + path + "' is not a map");
    }
  }
  if (spec.type == Type::kEnum && spec.choices.empty()) {
    throw std::logic_error("schema: enum '" + path + "' has no choices");
  }
  for (KeySpec& k : keys_) {
    if (k.path != path) continue;
    if (k.type == Type::kMap && spec.type == Type::kMap) {
      if (!spec.doc.empty()) k.doc = spec.doc;
      k.required = k.required || spec.required;
      return *this;
    }
    throw std::logic_error("schema: key '" + path + "' declared twice");
  }
  if (!spec.default_yaml.empty()) {  // a schema whose defaults are invalid is a bug
    try {
      Validator(*this, "schema default").value(spec, YAML::Load(spec.default_yaml), path, 0);
    } catch (const std::exception& e) {
      throw std::logic_error("schema: default of '" + path + "' is invalid: " + e.what());
    }
  }
  keys_.push_back(std::move(spec));
  return *this;
}

const KeySpec* Schema::find(const std::string& path) const {
  for (const KeySpec& k : keys_) {
    if (k.path == path) return &k;
  }
  return nullptr;
}

std::vector<const KeySpec*> Schema::children(const std::string& parent) const {
  std::vector<const KeySpec*> out;
  for (const KeySpec& k : keys_) {
    if (parent_of(k.path) == parent) out.push_back(&k);
  }
  return out;
}

std::string Schema::reference() const {
  std::ostringstream os;
  const std::string header =
      "| key | type | default | unit | allowed | description |\n"
      "|---|---|---|---|---|---|\n";
  auto row = [&](const KeySpec& k) {
    std::string def = k.default_yaml.empty() ? (k.required ? "**required**" : "optional")
                                             : "`" + k.default_yaml + "`";
    if (k.type == Type::kMap || k.type == Type::kList) {
      def = k.required ? "**required**" : "optional";
    }
    std::string allowed = range_text(k);
    if (!k.choices.empty()) {
      std::vector<std::string> c;
      for (const auto& x : k.choices) c.push_back("`" + x + "`");
      allowed = (k.type == Type::kStringList ? "each of " : "") + join(c, ", ");
    }
    os << "| `" << k.path << "` | " << type_name(k.type) << " | " << cell(def) << " | "
       << cell(k.unit) << " | " << cell(allowed) << " | " << cell(k.doc) << " |\n";
  };
  // Walk a section depth-first so that nested keys follow their map.
  std::function<void(const std::string&)> walk = [&](const std::string& parent) {
    for (const KeySpec* k : children(parent)) {
      row(*k);
      if (k->type == Type::kMap) walk(k->path);
      if (k->type == Type::kList) walk(k->path + "[]");
    }
  };
  os << "## Top level\n\n" << header;
  for (const KeySpec* k : children("")) {
    if (k->type != Type::kMap && k->type != Type::kList) row(*k);
  }
  for (const KeySpec* k : children("")) {
    if (k->type != Type::kMap && k->type != Type::kList) continue;
    os << "\n## `" << k->path << "`" << (k->type == Type::kList ? " (list)" : "") << "\n\n";
    if (!k->doc.empty()) os << k->doc << "\n\n";
    os << header;
    walk(k->type == Type::kList ? k->path + "[]" : k->path);
  }
  return os.str();
}

// ---- Config -----------------------------------------------------------------------------

Config::Config(YAML::Node root, const Schema* schema, std::string file, std::string prefix,
               std::string display)
    : root_(std::move(root)),
      schema_(schema),
      file_(std::move(file)),
      prefix_(std::move(prefix)),
      display_(std::move(display)) {}

Config Config::load(const std::string& file, const Schema& schema, const std::string& section) {
  std::ifstream in(file);
  if (!in) throw ConfigError(file, 0, "", "cannot open config file '" + file + "'");
  std::stringstream text;
  text << in.rdbuf();
  return from_string(text.str(), schema, file, section);
}

Config Config::from_string(const std::string& yaml_text, const Schema& schema,
                           const std::string& file_label, const std::string& section) {
  YAML::Node root;
  try {
    root = YAML::Load(yaml_text);
  } catch (const YAML::Exception& e) {
    throw ConfigError(file_label, e.mark.is_null() ? 0 : e.mark.line + 1, "",
                      "malformed YAML: " + e.msg);
  }
  if (!root.IsDefined() || root.IsNull()) {
    throw ConfigError(file_label, 0, "",
                      "the file is empty: it must start with 'config_version: " +
                          std::to_string(kConfigVersion) + "'");
  }
  if (!root.IsMap()) {
    throw ConfigError(
        file_label, line_of(root), "",
        "the top level must be a map of sections (key: value), got " + describe(root));
  }
  check_version(root, file_label);
  if (!section.empty()) {
    const KeySpec* s = schema.find(section);
    if (!s || parent_of(section) != "") {
      throw std::logic_error("Config::load: section '" + section + "' is not in the schema");
    }
  }
  Validator(schema, file_label).map(root, "", "", line_of(root), section);
  return Config(root, &schema, file_label, "", "");
}

YAML::Node Config::lookup(const std::string& path) const {
  YAML::Node cur = root_;
  for (const std::string& part : split_path(path)) {
    if (!cur.IsMap()) return YAML::Node(YAML::NodeType::Undefined);
    const YAML::Node& c = cur;
    YAML::Node next = c[part];
    if (!next.IsDefined()) return next;
    cur.reset(next);
  }
  return cur;
}

const KeySpec& Config::spec(const std::string& path) const {
  const KeySpec* s = schema_->find(prefix_ + path);
  if (!s) throw std::logic_error("config: '" + prefix_ + path + "' is not declared in the schema");
  return *s;
}

YAML::Node Config::value_or_default(const std::string& path) const {
  const KeySpec& s = spec(path);
  YAML::Node v = lookup(path);
  if (v.IsDefined() && !v.IsNull()) return v;
  if (s.default_yaml.empty()) {
    throw std::logic_error("config: '" + shown(path) +
                           "' has no value and no default; check has() first");
  }
  return YAML::Load(s.default_yaml);
}

bool Config::has(const std::string& path) const {
  spec(path);
  const YAML::Node v = lookup(path);
  return v.IsDefined() && !v.IsNull();
}

double Config::number(const std::string& path) const {
  const KeySpec& s = spec(path);
  if (s.type != Type::kDouble && s.type != Type::kInt) {
    throw std::logic_error("config: '" + s.path + "' is not a number");
  }
  double d = 0.0;
  parse_double(value_or_default(path).Scalar(), d);
  return d;
}

std::int64_t Config::integer(const std::string& path) const {
  const KeySpec& s = spec(path);
  if (s.type != Type::kInt) throw std::logic_error("config: '" + s.path + "' is not an integer");
  std::int64_t i = 0;
  parse_int(value_or_default(path).Scalar(), i);
  return i;
}

bool Config::boolean(const std::string& path) const {
  const KeySpec& s = spec(path);
  if (s.type != Type::kBool) throw std::logic_error("config: '" + s.path + "' is not a bool");
  return value_or_default(path).Scalar() == "true";
}

std::string Config::string(const std::string& path) const {
  const KeySpec& s = spec(path);
  if (s.type != Type::kString && s.type != Type::kEnum) {
    throw std::logic_error("config: '" + s.path + "' is not a string");
  }
  return value_or_default(path).Scalar();
}

std::array<double, 3> Config::vec3(const std::string& path) const {
  const KeySpec& s = spec(path);
  if (s.type != Type::kVec3) throw std::logic_error("config: '" + s.path + "' is not a vec3");
  const YAML::Node v = value_or_default(path);
  std::array<double, 3> out{};
  for (std::size_t i = 0; i < 3; ++i) parse_double(v[i].Scalar(), out[i]);
  return out;
}

std::vector<std::string> Config::strings(const std::string& path) const {
  const KeySpec& s = spec(path);
  if (s.type != Type::kStringList) {
    throw std::logic_error("config: '" + s.path + "' is not a string list");
  }
  std::vector<std::string> out;
  const YAML::Node v = value_or_default(path);
  for (std::size_t i = 0; i < v.size(); ++i) out.push_back(v[i].Scalar());
  return out;
}

std::vector<Config> Config::list(const std::string& path) const {
  const KeySpec& s = spec(path);
  if (s.type != Type::kList) throw std::logic_error("config: '" + s.path + "' is not a list");
  std::vector<Config> out;
  const YAML::Node v = lookup(path);
  if (!v.IsDefined() || !v.IsSequence()) return out;
  for (std::size_t i = 0; i < v.size(); ++i) {
    out.push_back(Config(v[i], schema_, file_, prefix_ + path + "[].",
                         display_ + path + "[" + std::to_string(i) + "]."));
  }
  return out;
}

int Config::line(const std::string& path) const {
  int best = line_of(root_);
  if (path.empty()) return best;
  YAML::Node cur = root_;
  for (const std::string& part : split_path(path)) {
    if (!cur.IsMap()) break;
    bool found = false;
    for (auto it = cur.begin(); it != cur.end(); ++it) {
      if (it->first.IsScalar() && it->first.Scalar() == part) {
        best = line_of(it->first);
        cur.reset(it->second);
        found = true;
        break;
      }
    }
    if (!found) break;
  }
  return best;
}

std::string Config::shown(const std::string& path) const {
  if (path.empty()) return display_.empty() ? "" : display_.substr(0, display_.size() - 1);
  return display_ + path;
}

void Config::fail(const std::string& path, const std::string& what) const {
  const std::string where = shown(path);
  throw ConfigError(file_, line(path), where, (where.empty() ? "" : where + " ") + what);
}

}  // namespace mpmdem::config
