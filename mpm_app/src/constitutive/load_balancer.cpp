// Cost-aware load balance (see load_balancer.hpp).
#include "constitutive/load_balancer.hpp"

#include <algorithm>
#include <cmath>

namespace mpmdem::mpm {

LoadBalancer::LoadBalancer(double threshold, std::int64_t min_interval, double smoothing)
    : threshold_(threshold), min_interval_(min_interval), smoothing_(smoothing) {}

std::optional<std::vector<Partition>> LoadBalancer::observe(
    std::int64_t step, const std::vector<protocol::RveReply>& replies,
    const std::vector<Partition>& current) {
  if (!enabled() || current.size() < 2) return std::nullopt;
  if (cost_.size() != replies.size()) {
    cost_.assign(replies.size(), 0.0);
    for (std::size_t i = 0; i < replies.size(); ++i) {
      cost_[i] = std::isfinite(replies[i].cost_s) ? std::max(0.0, replies[i].cost_s) : 0.0;
    }
    first_step_ = step;
  } else {
    for (std::size_t i = 0; i < replies.size(); ++i) {
      double c = std::isfinite(replies[i].cost_s) ? std::max(0.0, replies[i].cost_s) : 0.0;
      if (cost_[i] > 0.0) c = std::min(c, kSpikeCap * cost_[i]);
      cost_[i] = (1.0 - smoothing_) * cost_[i] + smoothing_ * c;
    }
  }
  const std::int64_t since = last_step_ >= 0 ? last_step_ : first_step_;
  if (step - since < min_interval_) return std::nullopt;
  const double now = partition_imbalance(cost_, current);
  if (now - 1.0 <= threshold_) return std::nullopt;
  std::vector<Partition> next = partition_by_cost(cost_, static_cast<int>(current.size()));
  const double after = partition_imbalance(cost_, next);
  if (now - after < 0.5 * (now - 1.0) || next.size() != current.size()) return std::nullopt;
  before_ = now;
  predicted_ = after;
  return next;
}

void LoadBalancer::applied(std::int64_t step) {
  last_step_ = step;
  ++rebalances_;
}

}  // namespace mpmdem::mpm
