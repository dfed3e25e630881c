// From a config file to a validated Scene. Throws config::ConfigError (exit code 2).
#pragma once

#include <string>

#include "mpmdem/config/schema.hpp"
#include "scene.hpp"

namespace mpmdem::mpm {

// The full scene schema (mpm keys + the shared `coupling:` section).
const config::Schema& scene_schema();
// Load, validate and convert. Cross-key checks (material inside the domain, regions not
// empty, ...) are done here too, each naming the key, value, file and line.
Scene load_scene(const std::string& file);

}  // namespace mpmdem::mpm
