// The `coupling:` section as dem_app validates it: the contract's generic keys
// (mpmdem/coupling_keys.hpp, which also holds the canonical text both sides hash) and every
// backend's own section.
#pragma once

#include "mpmdem/config/schema.hpp"
#include "mpmdem/coupling_keys.hpp"

namespace mpmdem {

// Adds every `coupling.*` key (generic, and the elastic, yade, native and cuda backends').
void add_coupling_keys(config::Schema& schema);
// `config_version` + the `coupling:` section: what dem_app validates.
const config::Schema& coupling_schema();
// The rules between keys of the section: coupling_rules.hpp.

}  // namespace mpmdem
