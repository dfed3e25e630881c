// Keys of `coupling.yade.*` (the YADE backend's settings), declared once.
#pragma once

#include "mpmdem/config/schema.hpp"

namespace mpmdem {

void add_yade_keys(config::Schema& schema);

}  // namespace mpmdem
