// Schema declaration and the printed reference, plus the helpers shared by the config
// machinery. Validation: config_validate.cpp; typed access: config_document.cpp.
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

namespace detail {

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

}  // namespace detail

using namespace detail;

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
    case Type::kNumberList:
      return "list of numbers";
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
  if (!spec.choices.empty() && spec.type != Type::kEnum && spec.type != Type::kStringList) {
    throw std::logic_error("schema: '" + path +
                           "' has choices but is not an enum or a string list (declare it "
                           "Type::kEnum: other types do not check them)");
  }
  if (spec.nonempty && spec.type != Type::kString) {
    throw std::logic_error("schema: not_empty() applies to strings only ('" + path + "')");
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
      validate_value(*this, spec, YAML::Load(spec.default_yaml), path);
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
    std::string allowed = k.nonempty ? "not empty" : range_text(k);
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
      if (!k->open_doc.empty()) {
        os << "| `" << k->path << ".<other>` | map | optional |  |  | " << cell(k->open_doc)
           << " |\n";
      }
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
    if (!k->open_doc.empty()) {
      os << "| `" << k->path << ".<other>` | map | optional |  |  | " << cell(k->open_doc)
         << " |\n";
    }
  }
  return os.str();
}

}  // namespace mpmdem::config
