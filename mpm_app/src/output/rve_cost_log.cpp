#include "output/rve_cost_log.hpp"

#include <cassert>
#include <cstdio>
#include <stdexcept>

#include "output/run_directory.hpp"

namespace mpmdem::mpm {

namespace {

std::string header(std::size_t n_points) {
  std::string h = "step";
  for (std::size_t p = 0; p < n_points; ++p) h += ",p" + std::to_string(p);
  return h;
}

}  // namespace

RveCostLog::RveCostLog(const std::string& dir, std::size_t n_points, std::int64_t last_step)
    : costs_path_(dir + "/rve_costs.csv"), ranks_path_(dir + "/rve_ranks.csv") {
  const std::string head = header(n_points);
  costs_ = open_step_log(costs_path_, head, last_step, 0);
  ranks_ = open_step_log(ranks_path_, head, last_step, 0);
}

RveCostLog::~RveCostLog() {
  try {
    flush();
  } catch (...) {  // a destructor must not throw; the rows are lost, the run is not
  }
}

void RveCostLog::append(std::int64_t step, const std::vector<double>& cost_s,
                        const std::vector<int>& rank) {
  assert(cost_s.size() == rank.size());
  const std::string s = std::to_string(step);
  costs_buffer_ += s;
  char value[32];
  for (const double c : cost_s) {
    std::snprintf(value, sizeof value, ",%.4g", c * 1e6);
    costs_buffer_ += value;
  }
  costs_buffer_ += '\n';
  if (rank != last_rank_) {  // the first step, or after a migration
    ranks_buffer_ += s;
    for (const int r : rank) ranks_buffer_ += ',' + std::to_string(r);
    ranks_buffer_ += '\n';
    last_rank_ = rank;
  }
  if (++pending_ >= 100) flush();
}

void RveCostLog::flush() {
  write_buffer(costs_, costs_buffer_, costs_path_);
  write_buffer(ranks_, ranks_buffer_, ranks_path_);
  pending_ = 0;
}

}  // namespace mpmdem::mpm
