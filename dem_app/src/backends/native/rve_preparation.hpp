// Preparing a rank's native RVEs once per distinct state (issue 36, item 5). Every point of
// a geostatic scene at one depth has the same stress, and every RVE draws its packing from a
// few: the paper scene's 70,389 RVEs need 79 depths x its packings. So the RVEs are grouped
// by their key (consolidation_key.hpp: the starting state's content, the stress bit for bit,
// the parameters, the code), each group is prepared once (consolidate, finish_preparation)
// and every RVE of it gets an exact copy. With a cache folder (consolidation_cache.hpp) a
// group's state is first looked up on disk and, once consolidated, stored there: a second
// run reuses it, and the ranks of one run share it. Each rank takes its groups in the order
// of their keys, entered at a different place for each rank (rank r of n at r/n of its list),
// and looks on disk again before each one, so ranks that hold the same groups mostly
// consolidate different ones in a cold run (no locks: two ranks may still consolidate one
// group at once, and write the same file). Results do not depend on the order, the cache, the ranks
// or which copy an RVE gets: a state is a function of its key alone.
#pragma once

#include <cstddef>
#include <vector>

#include "backends/native/consolidation_cache.hpp"
#include "backends/native/consolidation_key.hpp"

namespace mpmdem::dem::native {

// One RVE to prepare: its starting state (a packing, or its built cloud) with that state's
// hash, and its target stress (RveInit::stress, tension positive; the servo reaches the
// diagonal, none if it is zero).
struct PreparationInput {
  const RveState* start = nullptr;
  StateHash start_hash;
  double stress[9] = {};
};

struct PreparationTally {
  // per RVE, as before the grouping (an RVE counts the steps its state took where it was made)
  std::size_t consolidated = 0;   // RVEs with a stress to reach
  std::size_t not_converged = 0;  // of them, kept as reached (consolidation_on_failure: warn)
  long steps_sum = 0, steps_max = 0;
  // per group
  std::size_t distinct = 0;    // groups with a stress to reach
  std::size_t computed = 0;    // of them, consolidated by this rank in this run
  std::size_t from_cache = 0;  // read from the cache folder
  std::size_t rejected = 0;    // unusable cache files (consolidated again, rewritten)
  long steps_run = 0;          // DEM steps this rank ran to consolidate
};

struct PreparedSet {
  std::vector<PreparedRve> groups;  // one prepared state per distinct key
  std::vector<std::size_t> of;      // of[k]: RVE k's group
  PreparationTally tally;
};

// The state one RVE has after its preparation from `start`, with a fresh Verlet list (what
// every RVE of a group gets a copy of). Throws as consolidate() does when p.keep_on_failure
// is not set.
PreparedRve prepare_one(const RveState& start, const double (&stress)[9],
                        const ConsolidationParams& p, double verlet_skin);

// cache: nullptr for none. rank, n_ranks: where this rank starts in its list of groups.
// Throws (not_converged_message) for a group that does not reach its stress, from the cache
// as from a fresh consolidation, unless p.keep_on_failure.
PreparedSet prepare_rves(const std::vector<PreparationInput>& in, const ConsolidationParams& p,
                         double verlet_skin, ConsolidationCache* cache, int rank, int n_ranks);

}  // namespace mpmdem::dem::native
