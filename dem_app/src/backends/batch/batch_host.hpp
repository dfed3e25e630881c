// The host batch path: the batch's physics (rve_step.hpp) run on the CPU, one thread group of
// one thread per RVE, the RVEs over OpenMP threads. The same code as the device kernel
// (batch_device.cu), so CI runs it without a GPU (coupling.cuda.device: host).
#pragma once

#include "backends/batch/batch_layout.hpp"

namespace mpmdem::dem::batch {

void step_batch_host(const BatchView& v, const BatchParams& p, int threads);

}  // namespace mpmdem::dem::batch
