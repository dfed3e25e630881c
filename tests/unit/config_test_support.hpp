// Helpers shared by the config tests (test_config.cpp, test_config_files.cpp): a minimal
// valid scene, text substitution, temporary files, and EXPECT_CONTAINS.
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <string>

#include "config/scene_loader.hpp"
#include "coupling_schema.hpp"
#include "mpmdem/config/schema.hpp"
#include "mpmdem/config_hash.hpp"
#include "mpmdem/protocol.hpp"

namespace fs = std::filesystem;
using mpmdem::config::Config;
using mpmdem::config::ConfigError;
using mpmdem::config::key;
using mpmdem::config::Schema;
using mpmdem::config::Type;
using mpmdem::mpm::load_scene;
using mpmdem::mpm::scene_schema;

namespace config_test {

// EXPECT_CONTAINS(text, part): `text` contains `part` (prints both otherwise).
inline ::testing::AssertionResult contains(const char* text_expr, const char*,
                                           const std::string& text, const std::string& part) {
  if (text.find(part) != std::string::npos) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure()
         << text_expr << " is\n  " << text << "\nwhich does not contain\n  " << part;
}
#define EXPECT_CONTAINS(text, part) EXPECT_PRED_FORMAT2(contains, text, part)

// A small valid scene; line numbers are referred to by the tests below.
inline const char* const kMinimal =
    "config_version: 1\n"         // 1
    "grid:\n"                     // 2
    "  extent: [1, 1, 1]\n"       // 3
    "  cell_size: 0.1\n"          // 4
    "regions:\n"                  // 5
    "  - min: [0, 0, 0]\n"        // 6
    "    max: [0.5, 0.5, 0.5]\n"  // 7
    "    density: 1000\n"         // 8
    "solver:\n"                   // 9
    "  end_time: 0.1\n"           // 10
    "constitutive:\n"             // 11
    "  linear_elastic:\n"         // 12
    "    youngs_modulus: 1e6\n"   // 13
    "    poisson_ratio: 0.25\n";  // 14

inline std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const auto pos = text.find(from);
  EXPECT_NE(pos, std::string::npos) << "test text has no '" << from << "'";
  if (pos != std::string::npos) text.replace(pos, from.size(), to);
  return text;
}

// Writes `text` to a file in the build tree and returns its path.
inline std::string write_file(const std::string& name, const std::string& text) {
  const fs::path dir = fs::path(MPMDEM_BINARY_DIR) / "test_config_files";
  fs::create_directories(dir);
  const fs::path p = dir / name;
  std::ofstream(p) << text;
  return p.string();
}

// The message of the ConfigError that validating `text` as a scene raises ("" if none).
inline std::string scene_error(const std::string& text, int* line = nullptr) {
  try {
    Config::from_string(text, scene_schema(), "configs/x.yaml");
  } catch (const ConfigError& e) {
    if (line) *line = e.line();
    return e.what();
  }
  return "";
}

// The message of the ConfigError that load_scene raises for `text` ("" if none).
inline std::string load_error(const std::string& name, const std::string& text) {
  const std::string file = write_file(name, text);
  try {
    load_scene(file);
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.file(), file);
    return e.what();
  }
  return "";
}

}  // namespace config_test
