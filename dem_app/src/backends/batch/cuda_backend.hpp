// The GPU RVE backend (coupling.backend: cuda, issue 39): every RVE of the rank in one batch
// (batch_state.hpp), stepped per coupling step by one kernel launch on one GPU (one thread
// block per RVE, each looping its own ns: batch_device.cu) or, with coupling.cuda.device: host,
// by the same code on the CPU (batch_host.cpp; what CI runs). The physics are the native
// backend's, and so are its keys (coupling.native.*: packings, substep rule, damping, ...),
// its initial consolidation (a NativeBackend inside prepares the RVEs), its checkpoints and
// migration blobs (the batch is unpacked into native states for them) and its tiling (done on
// the host for the rare RVE whose cell gets too thin). The per-request logic (substep rule,
// kFlagSkip cache, faults) is the RveDriver's (rve_driver.hpp); this backend is its
// BatchStepper.
#pragma once

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "backend.hpp"
#include "backends/batch/batch_device.hpp"
#include "backends/batch/batch_state.hpp"
#include "backends/native/native_backend.hpp"
#include "rve_driver.hpp"

namespace mpmdem::dem {

struct CudaParams {
  NativeParams native;
  bool on_gpu = true;  // coupling.cuda.device: gpu | host
  int gpu = -1;        // device index, -1: rank mod the visible devices
  int threads_per_block = 128;
  batch::Capacity capacity;
};

class CudaBackend final : public RveBackend, private BatchStepper {
 public:
  explicit CudaBackend(const CudaParams& p);
  ~CudaBackend() override;
  std::string name() const override { return "cuda"; }
  void setup(const BackendContext& ctx) override;
  void initialise(const protocol::RveInit* init, protocol::RveReply* reply) override;
  void step(const protocol::ControlHeader& header, const protocol::RveRequest* req,
            protocol::RveReply* reply) override;
  void checkpoint(const std::filesystem::path& dir) override;
  void restore(const std::filesystem::path& dir) override;
  std::string export_rve(std::uint64_t gid) override;
  void adopt(std::uint64_t first_rve, std::uint64_t n_rve,
             std::map<std::uint64_t, std::string> incoming) override;
  std::string last_fault_message() const override { return driver_.last_fault(); }

  // For tests: RVE k's state as a native record (the batch unpacked).
  native::RveRecord rve(std::size_t k);
  const batch::TransferTally* tally() const { return device_ ? &device_->tally() : nullptr; }
  int threads() const { return threads_; }
  void set_threads(int n) { threads_ = n < 1 ? 1 : n; }

 private:
  void pack();          // host_'s records -> the batch (and the device)
  void sync_to_host();  // the batch (from the device) -> host_'s records
  // BatchStepper: one kernel launch (or the host batch path) over the active RVEs.
  double dem_dt(std::size_t k) const override { return batch_.dt_[k]; }
  void step_batch(const protocol::ControlHeader& header, const std::vector<BatchUpdate>& updates,
                  protocol::RveReply* reply, double* kinetic) override;

  CudaParams p_;
  NativeBackend host_;  // initialise, restore, adopt, checkpoint files
  RveDriver driver_;
  BackendContext ctx_;
  batch::BatchState batch_;
  std::unique_ptr<batch::DeviceBatch> device_;
  bool host_current_ = true;  // host_'s records equal the batch
  int threads_ = 1;
  std::int64_t rve_steps_ = 0;
  double batch_s_ = 0;
};

CudaParams cuda_params(const config::Config& cfg);
std::unique_ptr<RveBackend> make_cuda_backend(const config::Config& cfg);

}  // namespace mpmdem::dem
