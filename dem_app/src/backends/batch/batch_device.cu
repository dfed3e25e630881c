// The device side of the batch backend: see batch_device.hpp. One thread block per RVE runs
// rve_step.hpp (the same functions as the host batch path); compiled with --fmad=false (no
// contraction into FMA, as the host's -ffp-contract=off) so that the device gives the host's
// bits.
#include <cuda_runtime.h>

#include <chrono>
#include <string>
#include <vector>

#include "backends/batch/batch_device.hpp"
#include "backends/batch/rve_step.hpp"

namespace mpmdem::dem::batch {

namespace {

constexpr int kMaxThreads = 1024;

// A thread block: shared scratch for the reductions and scans.
struct DeviceCtx {
  double* red;  // blockDim.x doubles
  int* ired;    // blockDim.x ints
  __device__ int tid() const { return static_cast<int>(threadIdx.x); }
  __device__ int nt() const { return static_cast<int>(blockDim.x); }
  __device__ void sync() const { __syncthreads(); }
  __device__ double max_all(double x) const {
    __syncthreads();
    red[threadIdx.x] = x;
    __syncthreads();
    if (threadIdx.x == 0) {
      double m = red[0];
      for (int k = 1; k < nt(); ++k) m = hd_max(m, red[k]);
      red[0] = m;
    }
    __syncthreads();
    const double m = red[0];
    __syncthreads();
    return m;
  }
  __device__ int max_all(int x) const {
    __syncthreads();
    ired[threadIdx.x] = x;
    __syncthreads();
    if (threadIdx.x == 0) {
      int m = ired[0];
      for (int k = 1; k < nt(); ++k) m = m < ired[k] ? ired[k] : m;
      ired[0] = m;
    }
    __syncthreads();
    const int m = ired[0];
    __syncthreads();
    return m;
  }
  __device__ int scan(int x, int* total) const {
    __syncthreads();
    ired[threadIdx.x] = x;
    __syncthreads();
    if (threadIdx.x == 0) {
      int s = 0;
      for (int k = 0; k < nt(); ++k) {
        const int v = ired[k];
        ired[k] = s;
        s += v;
      }
      ired[nt()] = s;
    }
    __syncthreads();
    const int mine = ired[threadIdx.x];
    *total = ired[nt()];
    __syncthreads();
    return mine;
  }
  __device__ int atomic_add(int* p, int x) const { return atomicAdd(p, x); }
};

__global__ void batch_kernel(BatchView v, BatchParams p) {
  extern __shared__ double shared[];
  DeviceCtx ctx{shared, reinterpret_cast<int*>(shared + blockDim.x)};
  rve_step(v, p, static_cast<int>(blockIdx.x), ctx);
}

void check(cudaError_t e, const char* what) {
  if (e != cudaSuccess) {
    throw std::runtime_error(std::string("cuda backend: ") + what + ": " + cudaGetErrorString(e));
  }
}

// One device array mirroring one host vector.
struct Buffer {
  void* ptr = nullptr;
  std::size_t bytes = 0;
  ~Buffer() { cudaFree(ptr); }
  Buffer() = default;
  Buffer(const Buffer&) = delete;
  Buffer& operator=(const Buffer&) = delete;
};

class CudaDeviceBatch final : public DeviceBatch {
 public:
  CudaDeviceBatch(int device, int threads) : device_(device), threads_(threads) {
    check(cudaSetDevice(device_), "cudaSetDevice");
    cudaDeviceProp prop;
    check(cudaGetDeviceProperties(&prop, device_), "cudaGetDeviceProperties");
    name_ = std::string(prop.name) + " (device " + std::to_string(device_) + ", sm_" +
            std::to_string(prop.major) + std::to_string(prop.minor) + ")";
    check(cudaEventCreate(&start_), "cudaEventCreate");
    check(cudaEventCreate(&stop_), "cudaEventCreate");
  }
  ~CudaDeviceBatch() override {
    cudaEventDestroy(start_);
    cudaEventDestroy(stop_);
  }
  std::string name() const override { return name_; }

  void upload(BatchState& b) override {
    host_view_ = b.view();
    buffers_.clear();
    targets_.clear();
    buffers_.reserve(128);
    dev_ = host_view_;
    // Every pointer of the view: a device array of the host vector's size, filled.
    map(b.sph0_, dev_.sph0), map(b.con0_, dev_.con0), map(b.pair0_, dev_.pair0);
    map(b.n_con_, dev_.n_con), map(b.n_pair_, dev_.n_pair), map(b.cell_, dev_.cell);
    map(b.flags_, dev_.flags), map(b.dt_, dev_.dt), map(b.young_, dev_.young);
    map(b.ks_kn_, dev_.ks_kn), map(b.tan2_, dev_.tan2), map(b.p0_, dev_.p0);
    map(b.skin_, dev_.skin), map(b.max_cut_, dev_.max_cut), map(b.unbalanced_, dev_.unbalanced);
    map(b.iter_, dev_.iter), map(b.in_, dev_.in), map(b.out_, dev_.out);
    map(b.radius_, dev_.radius), map(b.mass_, dev_.mass), map(b.inertia_, dev_.inertia);
    map(b.inv_mass_, dev_.inv_mass), map(b.inv_inertia_, dev_.inv_inertia);
    map(b.ori_, dev_.ori), map(b.ref_ori_, dev_.ref_ori);
    map(b.inc_start_, dev_.inc_start), map(b.inc_fill_, dev_.inc_fill);
    map(b.id1_, dev_.id1), map(b.id2_, dev_.id2), map(b.pen_, dev_.pen);
    map(b.pair_of_, dev_.pair_of), map(b.inc_, dev_.inc), map(b.pi_, dev_.pi), map(b.pj_, dev_.pj);
    map(b.in_contact_, dev_.in_contact);
    for (int a = 0; a < 3; ++a) {
      map(b.pos_[a], dev_.pos[a]), map(b.vel_[a], dev_.vel[a]), map(b.ang_[a], dev_.ang[a]);
      map(b.force_[a], dev_.force[a]), map(b.torque_[a], dev_.torque[a]);
      map(b.x_ref_[a], dev_.x_ref[a]), map(b.ccell_[a], dev_.ccell[a]);
      map(b.normal_[a], dev_.normal[a]), map(b.shear_[a], dev_.shear[a]);
      map(b.of_[a], dev_.of[a]), map(b.ot1_[a], dev_.ot1[a]), map(b.ot2_[a], dev_.ot2[a]);
      map(b.pc_[a], dev_.pc[a]);
    }
    n_rve_ = b.n_rve();
  }

  void download(BatchState& b) override {
    // The buffers were made in upload() from b's vectors, in this order: copy each back.
    std::size_t k = 0;
    for (auto& t : targets_) {
      check(cudaMemcpy(t, buffers_[k]->ptr, buffers_[k]->bytes, cudaMemcpyDeviceToHost),
            "download");
      tally_.state_bytes += static_cast<std::int64_t>(buffers_[k]->bytes);
      ++tally_.state_copies;
      ++k;
    }
    (void)b;
  }

  void step(BatchState& b, const BatchParams& p) override {
    if (n_rve_ == 0) return;
    const std::size_t in_bytes = b.in_.size() * sizeof(StepIn);
    const std::size_t out_bytes = b.out_.size() * sizeof(StepOut);
    check(cudaMemcpy(const_cast<StepIn*>(dev_.in), b.in_.data(), in_bytes, cudaMemcpyHostToDevice),
          "step inputs");
    const std::size_t shared = threads_ * sizeof(double) + (threads_ + 1) * sizeof(int);
    check(cudaEventRecord(start_), "cudaEventRecord");
    batch_kernel<<<n_rve_, threads_, shared>>>(dev_, p);
    check(cudaGetLastError(), "kernel launch");
    check(cudaEventRecord(stop_), "cudaEventRecord");
    check(cudaMemcpy(b.out_.data(), dev_.out, out_bytes, cudaMemcpyDeviceToHost), "step replies");
    float ms = 0;
    check(cudaEventElapsedTime(&ms, start_, stop_), "cudaEventElapsedTime");
    tally_.kernel_s += ms * 1e-3;
    ++tally_.steps;
    tally_.copies += 2;
    tally_.bytes += static_cast<std::int64_t>(in_bytes + out_bytes);
  }

  const TransferTally& tally() const override { return tally_; }

 private:
  template <typename T, typename P>
  void map(std::vector<T>& host, P*& dev_ptr) {
    auto buf = std::make_unique<Buffer>();
    buf->bytes = host.size() * sizeof(T);
    if (buf->bytes > 0) {
      check(cudaMalloc(&buf->ptr, buf->bytes),
            "cudaMalloc (raise nothing: the batch does not "
            "fit this GPU's memory; fewer RVEs per rank)");
      check(cudaMemcpy(buf->ptr, host.data(), buf->bytes, cudaMemcpyHostToDevice), "upload");
      tally_.state_bytes += static_cast<std::int64_t>(buf->bytes);
      ++tally_.state_copies;
    }
    dev_ptr = static_cast<P*>(buf->ptr);
    targets_.push_back(host.data());
    buffers_.push_back(std::move(buf));
  }

  int device_, threads_, n_rve_ = 0;
  std::string name_;
  BatchView host_view_, dev_;
  std::vector<std::unique_ptr<Buffer>> buffers_;
  std::vector<void*> targets_;
  cudaEvent_t start_{}, stop_{};
  TransferTally tally_;
};

}  // namespace

bool cuda_built() {
  return true;
}

std::unique_ptr<DeviceBatch> DeviceBatch::create(int index, int rank, int threads_per_block) {
  int count = 0;
  const cudaError_t e = cudaGetDeviceCount(&count);
  if (e != cudaSuccess || count == 0) {
    throw NoDeviceError(
        std::string("cuda backend: no usable CUDA device here (set coupling.cuda.device: host to "
                    "run the batch on the CPU, or run on a GPU node); cudaGetDeviceCount: ") +
        (e != cudaSuccess ? cudaGetErrorString(e) : "0 devices"));
  }
  const int device = index >= 0 ? index : rank % count;
  if (device >= count) {
    throw NoDeviceError("cuda backend: coupling.cuda.gpu is " + std::to_string(index) +
                        " but this host has " + std::to_string(count) +
                        " CUDA devices; give an index below that, or -1 (rank mod count)");
  }
  if (threads_per_block < 32 || threads_per_block > kMaxThreads) {
    throw std::invalid_argument("cuda backend: threads per block must be in [32, 1024]");
  }
  return std::make_unique<CudaDeviceBatch>(device, threads_per_block);
}

}  // namespace mpmdem::dem::batch
