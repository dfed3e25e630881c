// Typed access to a validated document, with schema defaults. See mpmdem/config/schema.hpp.
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

using namespace detail;

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
  validate(root, schema, file_label, section);
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

std::vector<double> Config::numbers(const std::string& path) const {
  const KeySpec& s = spec(path);
  if (s.type != Type::kNumberList) {
    throw std::logic_error("config: '" + s.path + "' is not a number list");
  }
  const YAML::Node v = value_or_default(path);
  std::vector<double> out(v.size());
  for (std::size_t i = 0; i < v.size(); ++i) parse_double(v[i].Scalar(), out[i]);
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
    // "regions[1]": the key "regions", then item 1 of its list.
    std::string name = part;
    std::int64_t item = -1;
    const auto open = part.find('[');
    if (open != std::string::npos && part.back() == ']') {
      name = part.substr(0, open);
      if (!parse_int(part.substr(open + 1, part.size() - open - 2), item)) break;
    }
    if (!cur.IsMap()) break;
    bool found = false;
    for (auto it = cur.begin(); it != cur.end(); ++it) {
      if (it->first.IsScalar() && it->first.Scalar() == name) {
        best = line_of(it->first);
        cur.reset(it->second);
        found = true;
        break;
      }
    }
    if (!found) break;
    if (item >= 0) {
      if (!cur.IsSequence() || static_cast<std::size_t>(item) >= cur.size()) break;
      const YAML::Node& seq = cur;
      const YAML::Node element = seq[static_cast<std::size_t>(item)];
      if (line_of(element) > 0) best = line_of(element);
      cur.reset(element);
    }
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
