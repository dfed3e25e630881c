// Keys of `coupling.elastic.*` (the elastic stub backend).
#pragma once

#include "mpmdem/config/schema.hpp"

namespace mpmdem {

void add_elastic_keys(config::Schema& s);

}  // namespace mpmdem
