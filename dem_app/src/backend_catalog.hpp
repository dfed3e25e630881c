// The DEM backends by name: what each one is, the section of `coupling:` it declares, the
// rules of that section and the per-RVE outputs it computes. dem_app's schema
// (coupling_schema.cpp), its configuration rules (coupling_rules.cpp) and
// `dem_app --list-backends` read this table; backend_factory.cpp makes the backends built
// into this dem_app. Adding a backend: one row here and its maker there.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "mpmdem/config/schema.hpp"

namespace mpmdem::dem {

struct BackendSpec {
  std::string name;     // coupling.backend, dem_app --backend
  std::string summary;  // one line (dem_app --list-backends --long)
  // Declares its section(s) of coupling: (coupling.<name>.*).
  void (*add_keys)(config::Schema& schema) = nullptr;
  // The rules between the keys it reads, for a scene whose coupling.backend is this one
  // (each throws config::ConfigError naming the key, value, file and line).
  void (*check)(const config::Config& cfg) = nullptr;
  std::uint32_t outputs = 0;  // protocol::OutputBits it computes (the handshake's offer)
};

// Every backend this version of dem_app knows, built into it or not (yade needs
// MPMDEM_WITH_YADE): elastic, yade, native, cuda.
const std::vector<BackendSpec>& backend_catalog();
// The row of that name, or nullptr.
const BackendSpec* find_backend(const std::string& name);
// The catalog's names, in order.
std::vector<std::string> backend_names();

}  // namespace mpmdem::dem
