// Canonical text of YAML subtrees, for the handshake hash of the shared `coupling:` section:
// two files that mean the same thing give the same bytes.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>

#include "mpmdem/config/schema.hpp"

namespace mpmdem::config {

namespace {

bool plain_safe(const std::string& s) {
  if (s.empty() || s == "~") return false;
  for (char c : s) {
    const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                    c == '_' || c == '.' || c == '+' || c == '-';
    if (!ok) return false;
  }
  return true;
}

std::string quoted(const std::string& s) {
  std::string out = "\"";
  for (unsigned char c : s) {
    switch (c) {
      case '"':
        out += "\\\"";
        break;
      case '\\':
        out += "\\\\";
        break;
      case '\n':
        out += "\\n";
        break;
      case '\t':
        out += "\\t";
        break;
      default:
        if (c < 0x20) {
          char buf[8];
          std::snprintf(buf, sizeof buf, "\\x%02x", c);
          out += buf;
        } else {
          out += static_cast<char>(c);
        }
    }
  }
  return out + "\"";
}

void emit(const YAML::Node& node, std::string& out) {
  if (!node.IsDefined() || node.IsNull()) {
    out += "~";
  } else if (node.IsScalar()) {
    out += plain_safe(node.Scalar()) ? node.Scalar() : quoted(node.Scalar());
  } else if (node.IsSequence()) {
    out += "[";
    for (std::size_t i = 0; i < node.size(); ++i) {
      if (i) out += ", ";
      emit(node[i], out);
    }
    out += "]";
  } else {  // map: keys sorted bytewise
    std::map<std::string, YAML::Node> sorted;
    for (auto it = node.begin(); it != node.end(); ++it) {
      std::string k;
      emit(it->first, k);
      sorted.emplace(k, it->second);
    }
    out += "{";
    bool first = true;
    for (const auto& [k, v] : sorted) {
      if (!first) out += ", ";
      first = false;
      out += k + ": ";
      emit(v, out);
    }
    out += "}";
  }
}

// The value of a validated key as normalised text: numbers in shortest round-trip form.
YAML::Node normalised(const KeySpec& spec, const YAML::Node& v) {
  auto num = [](const YAML::Node& s) {
    return YAML::Node(format_number(std::strtod(s.Scalar().c_str(), nullptr)));
  };
  switch (spec.type) {
    case Type::kDouble:
      return num(v);
    case Type::kInt:
      return YAML::Node(std::to_string(std::strtoll(v.Scalar().c_str(), nullptr, 10)));
    case Type::kVec3:
    case Type::kNumberList: {
      YAML::Node out(YAML::NodeType::Sequence);
      if (v.IsSequence()) {
        for (std::size_t i = 0; i < v.size(); ++i) out.push_back(num(v[i]));
      }
      return out;
    }
    case Type::kStringList: {
      YAML::Node out(YAML::NodeType::Sequence);
      if (v.IsSequence()) {
        for (std::size_t i = 0; i < v.size(); ++i) out.push_back(YAML::Node(v[i].Scalar()));
      }
      return out;
    }
    default:
      return YAML::Node(v.Scalar());
  }
}

// A copy of the (possibly absent) map `node` whose keys are the children of schema path
// `parent`, with defaults filled in for absent keys; where `parent` is open
// (KeySpec::open_sections), its undeclared keys as written.
YAML::Node filled(const Schema& schema, const YAML::Node& node, const std::string& parent) {
  YAML::Node out(YAML::NodeType::Map);
  const KeySpec* owner = parent.empty() ? nullptr : schema.find(parent);
  if (owner && !owner->open_doc.empty() && node.IsDefined() && node.IsMap()) {
    for (auto it = node.begin(); it != node.end(); ++it) {
      const std::string name = it->first.Scalar();
      if (!schema.find(parent + "." + name)) out[name] = it->second;
    }
  }
  for (const KeySpec* spec : schema.children(parent)) {
    const std::string name = spec->path.substr(parent.empty() ? 0 : parent.size() + 1);
    YAML::Node v(YAML::NodeType::Undefined);
    if (node.IsDefined() && node.IsMap()) {
      const YAML::Node& c = node;
      const YAML::Node found = c[name];  // invalid if absent: reset() would throw
      if (found.IsDefined()) v.reset(found);
    }
    const bool present = v.IsDefined() && !v.IsNull();
    switch (spec->type) {
      case Type::kMap:
        out[name] = filled(schema, present ? v : YAML::Node(), spec->path);
        break;
      case Type::kList: {
        YAML::Node items(YAML::NodeType::Sequence);
        if (present) {
          for (std::size_t i = 0; i < v.size(); ++i) {
            items.push_back(filled(schema, v[i], spec->path + "[]"));
          }
        }
        out[name] = items;
        break;
      }
      default:
        if (present) {
          out[name] = normalised(*spec, v);
        } else if (!spec->default_yaml.empty()) {
          out[name] = normalised(*spec, YAML::Load(spec->default_yaml));
        }  // absent optional key without default: left out
    }
  }
  return out;
}

}  // namespace

std::string format_number(double v) {
  if (v == 0.0) return "0";  // also -0
  char buf[40];
  if (std::abs(v) < 1e15 && v == std::trunc(v)) {  // whole numbers without exponent: "60"
    std::snprintf(buf, sizeof buf, "%.0f", v);
    return buf;
  }
  for (int precision = 1; precision <= 17; ++precision) {
    std::snprintf(buf, sizeof buf, "%.*g", precision, v);
    if (std::strtod(buf, nullptr) == v) break;
  }
  return buf;
}

std::string canonical_yaml(const YAML::Node& node) {
  std::string out;
  emit(node, out);
  return out;
}

std::string canonical_section_text(const Schema& schema, const YAML::Node& node,
                                   const std::string& path) {
  const KeySpec* s = schema.find(path);
  if (!s || s->type != Type::kMap) {
    throw std::logic_error("config: canonical text needs a map section, got '" + path + "'");
  }
  return canonical_yaml(filled(schema, node, path));
}

std::string Config::canonical_text(const std::string& section) const {
  return canonical_section_text(*schema_, lookup(section), prefix_ + section);
}

}  // namespace mpmdem::config
