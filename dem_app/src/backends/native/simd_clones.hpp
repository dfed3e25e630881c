// GCC function multiversioning for the native backend's vectorised loops: a function marked
// MPMDEM_SIMD_CLONES is compiled for AVX-512 and AVX2 besides the baseline, and the one the
// CPU supports is chosen at load time. More lanes, the same bits: dem_server is built with
// -ffp-contract=off (no contraction into FMA) and -fno-math-errno (sqrt vectorises).
#pragma once

#if defined(__GNUC__) && defined(__x86_64__) && !defined(__clang__)
#define MPMDEM_SIMD_CLONES __attribute__((target_clones("avx512f", "avx2", "default")))
#define MPMDEM_ALWAYS_INLINE inline __attribute__((always_inline))
// The contact update written for AVX-512 (contact_kernel_avx512.cpp), used when the CPU has
// it; drop this line together with "avx512f" above for a build without AVX-512 code.
#define MPMDEM_AVX512_KERNEL 1
#else
#define MPMDEM_SIMD_CLONES
#define MPMDEM_ALWAYS_INLINE inline
#endif
