// The DEM substeps the RVE updates of a run took, for the log line at the end of a run
// ("dem_app: substeps rank R: ..."). With the proportional rule (clamp(ceil(ns_factor
// max|dF - I|), ns_min, ns_max)) the share of updates at the largest and smallest counts says
// how often a clamp set the DEM strain rate instead of ns_factor: an update at ns_max strains
// its RVE faster than 1 / ns_factor per substep, and halving the MPM step then slows it
// (docs/transfers.md, "The walls' share of the transfers", on the multiscale slice).
#pragma once

#include <cstdint>
#include <cstdio>
#include <map>
#include <string>

#include "mpmdem/protocol.hpp"

namespace mpmdem::dem {

class SubstepTally {
 public:
  // Counts the replies of one kStep exchange; replies with no substeps (a skipped update, a
  // closed-form backend) are not updates here.
  void add(const protocol::RveReply* replies, std::size_t n) {
    for (std::size_t k = 0; k < n; ++k) {
      if (replies[k].n_substeps > 0) ++counts_[replies[k].n_substeps];
    }
  }
  std::int64_t updates() const {
    std::int64_t u = 0;
    for (const auto& [ns, c] : counts_) u += c;
    return u;
  }
  // "" when no update had substeps.
  std::string line(int rank) const {
    const std::int64_t u = updates();
    if (u == 0) return {};
    double sum = 0.0;
    for (const auto& [ns, c] : counts_) sum += static_cast<double>(ns) * static_cast<double>(c);
    const auto& [lo, n_lo] = *counts_.begin();
    const auto& [hi, n_hi] = *counts_.rbegin();
    const double share = 100.0 / static_cast<double>(u);
    char text[256];
    std::snprintf(text, sizeof text,
                  "dem_app: substeps rank %d: %lld RVE updates, mean %.2f substeps per update; "
                  "fewest %d (%.1f %% of the updates), most %d (%.1f %%)",
                  rank, static_cast<long long>(u), sum / static_cast<double>(u), lo,
                  share * static_cast<double>(n_lo), hi, share * static_cast<double>(n_hi));
    return text;
  }

 private:
  std::map<std::int32_t, std::int64_t> counts_;  // substeps -> updates
};

}  // namespace mpmdem::dem
