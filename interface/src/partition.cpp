// Cost-balanced contiguous partitions (see partition.hpp).
#include "mpmdem/partition.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstddef>

namespace mpmdem {

namespace {

// Greedy fill from the left under a bottleneck B, leaving at least one item for every later
// range. Returns the ranges, or an empty vector if the last range exceeds B.
std::vector<Partition> fill(const std::vector<double>& cost, std::size_t parts, double bound) {
  const std::size_t n = cost.size();
  std::vector<Partition> out;
  std::size_t i = 0;
  for (std::size_t r = 0; r < parts; ++r) {
    const std::size_t first = i;
    const std::size_t left_for_others = n >= parts ? parts - r - 1 : 0;
    if (r + 1 == parts) {
      i = n;
    } else {
      // The first item is always taken (bound >= the largest cost, so it fits).
      double load = 0.0;
      while (i + left_for_others < n && (i == first || load + cost[i] <= bound)) {
        load += cost[i];
        ++i;
      }
    }
    out.push_back({first, i - first});
  }
  double last = 0.0;
  for (std::size_t k = out.back().offset; k < n; ++k) last += cost[k];
  if (last > bound) out.clear();
  return out;
}

}  // namespace

std::vector<Partition> partition_by_cost(const std::vector<double>& cost, int parts) {
  if (parts <= 0) return {};
  const auto p = static_cast<std::size_t>(parts);
  double total = 0.0, biggest = 0.0;
  for (double c : cost) {
    assert(c >= 0.0 && std::isfinite(c));
    total += c;
    biggest = std::max(biggest, c);
  }
  if (cost.empty() || total <= 0.0) return partition_contiguous(cost.size(), parts);
  double lo = std::max(biggest, total / static_cast<double>(p)), hi = total;
  std::vector<Partition> best = fill(cost, p, hi);
  for (int it = 0; it < 60 && hi - lo > 1e-12 * total; ++it) {
    const double mid = 0.5 * (lo + hi);
    std::vector<Partition> trial = fill(cost, p, mid);
    if (trial.empty()) {
      lo = mid;
    } else {
      hi = mid;
      best = std::move(trial);
    }
  }
  return best;
}

std::vector<std::uint64_t> rve_order(std::uint64_t n, RveOrder kind) {
  std::vector<std::uint64_t> order;
  order.reserve(n);
  if (kind == RveOrder::kContiguous) {
    for (std::uint64_t i = 0; i < n; ++i) order.push_back(i);
    return order;
  }
  int bits = 0;
  while ((std::uint64_t{1} << bits) < n) ++bits;
  for (std::uint64_t k = 0; order.size() < n; ++k) {
    std::uint64_t r = 0;  // k with its `bits` lowest bits reversed
    for (int b = 0; b < bits; ++b) r |= ((k >> b) & 1u) << (bits - 1 - b);
    if (r < n) order.push_back(r);
  }
  return order;
}

double partition_imbalance(const std::vector<double>& cost, const std::vector<Partition>& parts) {
  if (parts.empty()) return 1.0;
  double total = 0.0, worst = 0.0;
  for (const Partition& part : parts) {
    double load = 0.0;
    for (std::uint64_t k = part.offset; k < part.offset + part.count; ++k) load += cost[k];
    total += load;
    worst = std::max(worst, load);
  }
  const double mean = total / static_cast<double>(parts.size());
  return mean > 0.0 ? worst / mean : 1.0;
}

}  // namespace mpmdem
