// What a contact law's arithmetic needs beyond + - * / and comparisons, per lane type T: a law
// (frict.hpp, frict_visco.hpp) is written once as templates over T and compiled for
//  * T = double: the native scalar kernel (contact_kernel.cpp, measures.cpp, vectorised by
//    SIMD clones), the batch backend's host path and its CUDA kernel (batch/);
//  * T = 8 AVX-512 lanes: contact_kernel_avx512.cpp, which specialises LawMath for them.
// The same source gives the same bits on every path as long as the kernels are built without
// contraction (-ffp-contract=off, nvcc --fmad=false). Values of type T are passed by
// reference and results written to out parameters: a 64-byte vector returned by value from a
// function compiled without AVX-512 would change the ABI (GCC's -Wpsabi), and these functions
// are inlined into kernels that have it.
#pragma once

#include <cmath>

#ifdef __CUDACC__
#define MPMDEM_LAW_INLINE __host__ __device__ __forceinline__
#else
#define MPMDEM_LAW_INLINE inline __attribute__((always_inline))
#endif

namespace mpmdem::dem::laws {

// What every contact of an RVE's DEM step shares (its one material and law).
struct LawParams {
  double young;   // contact modulus E [Pa]
  double ks_kn;   // FrictMat.poisson: ks / kn
  double tan2;    // tan(friction angle)^2
  double beta_n;  // viscous laws: c_n / (2 sqrt(m* kn)) (FrictViscoMat.betan); else 0
};

template <class T>
struct LawMath;

template <>
struct LawMath<double> {
  static MPMDEM_LAW_INLINE void sqrt(const double& x, double& out) {
#ifdef __CUDACC__
    out = ::sqrt(x);
#else
    out = std::sqrt(x);
#endif
  }
  // Coulomb's cap: fs *= sqrt(max_fs) / |fs| where fs2 = |fs|^2 > max_fs. The ratio is below
  // 1 exactly then (sqrt and division are monotonic; 0/0 is NaN, not below 1), so the test on
  // it is the same and the division is not moved into a branch (which would stop the
  // vectorisation of the scalar kernel).
  static MPMDEM_LAW_INLINE void cap(double (&fs)[3], const double& max_fs, const double& fs2) {
    double a, b;
    sqrt(max_fs, a);
    sqrt(fs2, b);
    const double ratio = a / b;
    const double scale = ratio < 1.0 ? ratio : 1.0;
    for (int q = 0; q < 3; ++q) fs[q] *= scale;
  }
};

}  // namespace mpmdem::dem::laws
