// Creating a backend of the catalog (backend_catalog.hpp) by name (dem_app --backend NAME):
// elastic, native and cuda (its host batch path always; its GPU kernel with
// MPMDEM_HAVE_CUDA) always, yade when built with MPMDEM_HAVE_YADE.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "backend.hpp"
#include "mpmdem/config/schema.hpp"

namespace mpmdem::dem {

// The catalog's backends this build offers, in the catalog's order, e.g. {"elastic", "native",
// "cuda"}.
std::vector<std::string> available_backends();
// coupling.backend of `cfg` is one of available_backends(); throws config::ConfigError
// naming the key and the backends of this build. (What each backend computes:
// backend_outputs() in coupling_rules.hpp.)
void check_backend_available(const config::Config& cfg);
// Throws std::invalid_argument naming the available backends if `name` is not one.
std::unique_ptr<RveBackend> make_backend(const std::string& name, const config::Config& cfg,
                                         const BackendContext& ctx);

}  // namespace mpmdem::dem
