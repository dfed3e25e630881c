// Keys of `coupling.native.*` (the native backend's settings), declared once.
#pragma once

#include "mpmdem/config/schema.hpp"

namespace mpmdem {

void add_native_keys(config::Schema& schema);

}  // namespace mpmdem
