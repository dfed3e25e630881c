// The device side of the batch backend: a copy of the batch (BatchState's arrays) in the
// memory of one GPU, stepped by one kernel launch per coupling step (one thread block per
// RVE, rve_step.hpp's physics compiled for the device). Per step: the inputs (dF, ns, flags:
// one copy) go up, the replies (one copy) come down; the state stays on the device and is
// copied whole only when the host needs it (checkpoint, export, tiling, load balance).
// Built from batch_device.cu with MPMDEM_WITH_CUDA; otherwise create() throws.
#pragma once

#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>

#include "backends/batch/batch_state.hpp"

namespace mpmdem::dem::batch {

// No usable GPU (none visible, or this dem_app built without CUDA): says what to change.
class NoDeviceError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct TransferTally {
  std::int64_t steps = 0, copies = 0, bytes = 0;   // host-device copies during steps
  std::int64_t state_copies = 0, state_bytes = 0;  // whole-state uploads and downloads
  double kernel_s = 0;                             // device time of the step kernels
};

class DeviceBatch {
 public:
  virtual ~DeviceBatch() = default;
  // Device `index` (-1: rank mod the visible devices); threads per block of the kernel.
  static std::unique_ptr<DeviceBatch> create(int index, int rank, int threads_per_block);
  virtual std::string name() const = 0;      // e.g. "NVIDIA H200 (device 0, sm_90)"
  virtual void upload(BatchState& b) = 0;    // the whole batch, replacing the device copy
  virtual void download(BatchState& b) = 0;  // the whole state back into b
  // One coupling step: b.in() up, the kernel, b.out() down.
  virtual void step(BatchState& b, const BatchParams& p) = 0;
  virtual const TransferTally& tally() const = 0;
};

// Whether this build has the device kernel (MPMDEM_WITH_CUDA).
bool cuda_built();

}  // namespace mpmdem::dem::batch
