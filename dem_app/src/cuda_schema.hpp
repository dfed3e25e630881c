// Keys of `coupling.cuda.*` (the GPU backend's device settings), declared once. Its physics
// keys are the native backend's (coupling.native.*): the two backends run the same RVEs.
#pragma once

#include "mpmdem/config/schema.hpp"

namespace mpmdem {

void add_cuda_keys(config::Schema& schema);

}  // namespace mpmdem
