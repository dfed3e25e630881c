// Internal helpers of the config machinery, shared by config_schema.cpp (Schema,
// reference), config_validate.cpp (document validation) and config_document.cpp (Config).
#pragma once

#include <yaml-cpp/yaml.h>

#include <cstdint>
#include <string>
#include <vector>

#include "mpmdem/config/schema.hpp"

namespace mpmdem::config::detail {

std::string parent_of(const std::string& path);
std::string leaf_of(const std::string& path);
std::vector<std::string> split_path(const std::string& path);
int line_of(const YAML::Node& node);
bool is_quoted(const YAML::Node& n);
bool parse_double(const std::string& text, double& out);
bool parse_int(const std::string& text, std::int64_t& out);
std::string describe(const YAML::Node& n);
std::string vec_text(const std::vector<double>& v);
std::string join(const std::vector<std::string>& items, const std::string& sep);
bool in_range(const KeySpec& s, double v);
std::size_t edit_distance(const std::string& a, const std::string& b);
std::string cell(std::string s);  // escape a markdown table cell

// Version gate, then every key of `root` (or only of top-level `section`) against `schema`.
// Throws ConfigError on the first fault.
void validate(const YAML::Node& root, const Schema& schema, const std::string& file,
              const std::string& section);

// One value against its KeySpec (used to check schema defaults when keys are declared).
void validate_value(const Schema& schema, const KeySpec& spec, const YAML::Node& value,
                    const std::string& path);

}  // namespace mpmdem::config::detail
