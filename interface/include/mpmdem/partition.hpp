// The paper's parallel scheme: material points 0..n-1 are split into N nearly equal,
// contiguous partitions, one per server rank; partition r holds RVEs [offset, offset+count).
#pragma once

#include <cstddef>
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

// The rank whose partition holds item `i`, or -1 if none does (parts contiguous, in order).
inline int owner_of(const std::vector<Partition>& parts, std::uint64_t i) {
  for (std::size_t r = 0; r < parts.size(); ++r) {
    if (i >= parts[r].offset && i < parts[r].offset + parts[r].count) return static_cast<int>(r);
  }
  return -1;
}

// Contiguous ranges of [0, cost.size()) for `parts` ranks that minimise the largest sum of
// cost (the bottleneck rank): bisection on the bottleneck, greedy fill from the left. Every
// range holds at least one item when cost.size() >= parts. Costs must be >= 0.
std::vector<Partition> partition_by_cost(const std::vector<double>& cost, int parts);

// Order of the RVEs on the wire (coupling.rve_order): slot s of the scatter/gather carries
// the RVE of material point order[s], and server rank r owns a contiguous range of slots.
// "contiguous" is the identity. "interleaved" is the bit-reversal (van der Corput) order:
// any contiguous range of slots samples the points evenly (slots [0, n/2) hold the even
// points, [0, n/4) every fourth, ...), for every rank count. Material points are numbered
// cell by cell, so the identity hands each rank one region of the body, and RVE costs,
// which follow the local strain rate, differ between regions and drift as the body moves;
// interleaved ranges see the same mix of regions. Independent of the rank count, so a run
// gives the same results on any number of ranks.
enum class RveOrder { kContiguous, kInterleaved };
std::vector<std::uint64_t> rve_order(std::uint64_t n, RveOrder kind);

// Largest range sum over the mean range sum (1: perfectly balanced).
double partition_imbalance(const std::vector<double>& cost, const std::vector<Partition>& parts);

}  // namespace mpmdem
