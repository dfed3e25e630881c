// The device side without CUDA (MPMDEM_WITH_CUDA off): see batch_device.hpp.
#include "backends/batch/batch_device.hpp"

#ifndef MPMDEM_HAVE_CUDA
namespace mpmdem::dem::batch {

bool cuda_built() {
  return false;
}

std::unique_ptr<DeviceBatch> DeviceBatch::create(int, int, int) {
  throw NoDeviceError(
      "cuda backend: built without CUDA, so no GPU (set coupling.cuda.device: host to run the "
      "batch on the CPU, or rebuild where nvcc is found: MPMDEM_WITH_CUDA)");
}

}  // namespace mpmdem::dem::batch
#endif
