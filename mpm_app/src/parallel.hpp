// OpenMP policy of the MPM loops: loops over fewer items than this run on one thread, where
// a parallel region would cost more than the work (small test scenes, oversubscribed cores).
#pragma once

#include <cstddef>

namespace mpmdem::mpm {

inline constexpr std::ptrdiff_t kParallelMin = 4096;

}  // namespace mpmdem::mpm
