// MPMDEM_HD marks the batch backend's physics functions: __host__ __device__ under nvcc (the
// device kernel, batch_device.cu), nothing under g++ (the host batch path, batch_host.cpp).
// One definition of the physics, compiled for both.
#pragma once

#ifdef __CUDACC__
#define MPMDEM_HD __host__ __device__
#define MPMDEM_HD_INLINE __host__ __device__ __forceinline__
#else
#define MPMDEM_HD
#define MPMDEM_HD_INLINE inline
#endif

namespace mpmdem::dem::batch {

MPMDEM_HD_INLINE double hd_max(double a, double b) {
  return a < b ? b : a;
}  // std::max's
MPMDEM_HD_INLINE double hd_min(double a, double b) {
  return b < a ? b : a;
}  // std::min's
// std::isfinite without <cmath>'s overload set (the same answer: inf - inf and NaN are NaN).
MPMDEM_HD_INLINE bool hd_isfinite(double x) {
  return x - x == 0.0;
}
MPMDEM_HD_INLINE long long hd_min_i64(long long a, long long b) {
  return b < a ? b : a;
}

}  // namespace mpmdem::dem::batch
