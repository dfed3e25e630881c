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

// Contiguous ranges of [0, cost.size()) for `parts` ranks that minimise the largest sum of
// cost (the bottleneck rank): bisection on the bottleneck, greedy fill from the left. Every
// range holds at least one item when cost.size() >= parts. Costs must be >= 0.
std::vector<Partition> partition_by_cost(const std::vector<double>& cost, int parts);

// Largest range sum over the mean range sum (1: perfectly balanced).
double partition_imbalance(const std::vector<double>& cost, const std::vector<Partition>& parts);

}  // namespace mpmdem
