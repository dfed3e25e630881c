// The device side without CUDA (MPMDEM_WITH_CUDA off): see batch_device.hpp.
#include "backends/batch/batch_device.hpp"

#ifndef MPMDEM_HAVE_CUDA
namespace mpmdem::dem::batch {

bool cuda_built() {
  return false;
}

std::unique_ptr<DeviceBatch> DeviceBatch::create(int, int, int) {
  throw NoDeviceError(
      "cuda backend: this dem_app was built without CUDA (MPMDEM_WITH_CUDA=OFF: no nvcc at "
      "configure time, or the sanitizer build), so coupling.cuda.device: gpu has no device; "
      "set coupling.cuda.device: host to run the same batch code on the CPU, or rebuild "
      "where nvcc is found");
}

}  // namespace mpmdem::dem::batch
#endif
