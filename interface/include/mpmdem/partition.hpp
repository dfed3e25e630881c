// The paper's parallel scheme: material points 0..n-1 are split into N nearly equal,
// contiguous partitions, one per server rank; partition r holds RVEs [offset, offset+count).
#pragma once

#include <cstdint>
#include <vector>

namespace mpmdem {

struct Partition {
  std::uint64_t offset;
  std::uint64_t count;
};

// Sizes differ by at most one; the first (n % parts) partitions get the extra item.
inline std::vector<Partition> partition_contiguous(std::uint64_t n, int parts) {
  std::vector<Partition> result;
  if (parts <= 0) return result;
  const auto p = static_cast<std::uint64_t>(parts);
  std::uint64_t offset = 0;
  for (std::uint64_t r = 0; r < p; ++r) {
    const std::uint64_t count = n / p + (r < n % p ? 1 : 0);
    result.push_back({offset, count});
    offset += count;
  }
  return result;
}

}  // namespace mpmdem
