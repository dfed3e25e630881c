// Cost-aware load balance of the RVEs over the DEM server ranks (client side; issue 5).
//
// The servers return each RVE's backend time (RveReply::cost_s). The balancer keeps an
// exponentially smoothed cost per RVE, c <- (1 - w) c + w min(cost_s, kSpikeCap c) (a pause
// of the process, a page fault storm or a preempted core makes one step of one RVE look
// hundreds of times dearer; a real change, such as a tiled cell, is at most a few times and
// passes within a few steps), and after each step sums it
// over the current partition's ranks. When max/mean - 1 exceeds `threshold` (and at least
// `min_interval` steps have passed since the start or the last rebalance) it proposes the
// contiguous partition that minimises the largest rank cost (partition_by_cost), if that
// lowers the predicted imbalance by at least half the excess. The remote provider sends it
// to the servers (RveClient::rebalance), which move the RVE states.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "mpmdem/partition.hpp"
#include "mpmdem/protocol.hpp"

namespace mpmdem::mpm {

class LoadBalancer {
 public:
  // threshold 0: off (observe() never proposes anything).
  LoadBalancer(double threshold, std::int64_t min_interval, double smoothing);

  // A step's cost counts for at most this many times the RVE's smoothed cost.
  static constexpr double kSpikeCap = 4.0;

  bool enabled() const { return threshold_ > 0.0; }
  // After a step: fold in the replies' costs; a new partition if one is due.
  std::optional<std::vector<Partition>> observe(std::int64_t step,
                                                const std::vector<protocol::RveReply>& replies,
                                                const std::vector<Partition>& current);
  // The proposal was applied at `step`.
  void applied(std::int64_t step);

  std::int64_t rebalances() const { return rebalances_; }
  double last_imbalance_before() const { return before_; }
  double last_imbalance_predicted() const { return predicted_; }
  const std::vector<double>& smoothed_cost() const { return cost_; }

 private:
  double threshold_;
  std::int64_t min_interval_;
  double smoothing_;
  std::vector<double> cost_;
  std::int64_t last_step_ = -1;  // step of the last rebalance; -1: none yet
  std::int64_t first_step_ = -1;
  std::int64_t rebalances_ = 0;
  double before_ = 1.0, predicted_ = 1.0;
};

}  // namespace mpmdem::mpm
