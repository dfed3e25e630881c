// Preparing a rank's native RVEs once per distinct state: see rve_preparation.hpp.
#include "backends/native/rve_preparation.hpp"

#include <algorithm>
#include <map>
#include <optional>
#include <stdexcept>

#include "backends/native/measures.hpp"
#include "backends/native/neighbour_list.hpp"

namespace mpmdem::dem::native {

namespace {

Eigen::Vector3d goal_of(const double (&stress)[9]) {
  return {stress[0], stress[4], stress[8]};
}

bool has_goal(const double (&stress)[9]) {
  return goal_of(stress).cwiseAbs().maxCoeff() > 0;
}

}  // namespace

PreparedRve prepare_one(const RveState& start, const double (&stress)[9],
                        const ConsolidationParams& p, double verlet_skin) {
  PreparedRve out;
  out.state = start;
  NeighbourList nl(verlet_skin);
  if (has_goal(stress)) {
    const Consolidation c = consolidate(out.state, nl, goal_of(stress), p);
    out.steps = c.steps;
    out.converged = c.converged;
  }
  finish_preparation(out.state, nl, p.damping);
  out.unbalanced = unbalanced_force(out.state);
  out.state.spheres.release_forces();
  return out;
}

PreparedSet prepare_rves(const std::vector<PreparationInput>& in, const ConsolidationParams& p,
                         double verlet_skin, ConsolidationCache* cache, int rank, int n_ranks) {
  PreparedSet set;
  set.of.resize(in.size());
  // The groups, numbered in the order of their first RVE.
  std::map<ConsolidationKey, std::size_t> index;
  std::vector<ConsolidationKey> keys;
  std::vector<std::size_t> first;
  for (std::size_t k = 0; k < in.size(); ++k) {
    ConsolidationKey key =
        consolidation_key(in[k].start_hash, in[k].stress, p, verlet_skin, in[k].start->law);
    const auto [it, fresh] = index.emplace(std::move(key), keys.size());
    if (fresh) {
      keys.push_back(it->first);
      first.push_back(k);
    }
    set.of[k] = it->second;
  }
  const std::size_t n = keys.size();
  set.groups.resize(n);
  // The groups in an order that does not depend on the rank (by key), entered at r/n of it.
  std::vector<std::size_t> order(n);
  for (std::size_t g = 0; g < n; ++g) order[g] = g;
  std::sort(order.begin(), order.end(),
            [&](std::size_t a, std::size_t b) { return keys[a] < keys[b]; });
  const std::size_t start = n_ranks > 1 ? n * static_cast<std::size_t>(std::max(rank, 0)) /
                                              static_cast<std::size_t>(n_ranks)
                                        : 0;
  PreparationTally& t = set.tally;
  const std::size_t rejected_before = cache ? cache->rejected() : 0;
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t g = order[(start + i) % n];
    const PreparationInput& src = in[first[g]];
    if (!has_goal(src.stress)) {  // two DEM steps: not worth a file
      set.groups[g] = prepare_one(*src.start, src.stress, p, verlet_skin);
      continue;
    }
    ++t.distinct;
    std::optional<PreparedRve> stored = cache ? cache->load(keys[g]) : std::nullopt;
    if (stored) {
      ++t.from_cache;
      if (!stored->converged && !p.keep_on_failure) {
        throw std::runtime_error(not_converged_message(goal_of(src.stress), p.max_steps) +
                                 " (the state stored as reached in " +
                                 cache->file(keys[g]).string() + ")");
      }
      set.groups[g] = std::move(*stored);
      continue;
    }
    set.groups[g] = prepare_one(*src.start, src.stress, p, verlet_skin);
    ++t.computed;
    t.steps_run += set.groups[g].steps;
    if (cache) cache->store(keys[g], set.groups[g]);
  }
  if (cache) t.rejected = cache->rejected() - rejected_before;
  for (std::size_t k = 0; k < in.size(); ++k) {
    if (!has_goal(in[k].stress)) continue;
    const PreparedRve& g = set.groups[set.of[k]];
    ++t.consolidated;
    t.steps_sum += g.steps;
    t.steps_max = std::max(t.steps_max, g.steps);
    if (!g.converged) ++t.not_converged;
  }
  return set;
}

}  // namespace mpmdem::dem::native
