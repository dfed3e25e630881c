// Schema of the shared `coupling:` section, declared once. Both programs read this section
// (mpm_app: connection and outputs; dem_app: everything) and hash its canonical form with
// defaults filled in, so a server started with other coupling settings is refused.
#pragma once

#include "mpmdem/config/schema.hpp"

namespace mpmdem {

// Adds every `coupling.*` key (generic, elastic backend, yade backend) to `schema`.
void add_coupling_keys(config::Schema& schema);
// `config_version` + the `coupling:` section: what dem_app validates.
const config::Schema& coupling_schema();

}  // namespace mpmdem
