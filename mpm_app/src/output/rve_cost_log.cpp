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

std::ofstream open(const std::string& path, const std::string& head, std::int64_t last_step) {
  if (last_step < 0) {
    std::ofstream out(path, std::ios::trunc);
    if (!out) throw std::runtime_error("cannot write '" + path + "'");
    out << head << '\n';
    return out;
  }
  keep_rows_up_to_step(path, head, last_step, 0);
  std::ofstream out(path, std::ios::app);
  if (!out) throw std::runtime_error("cannot append to '" + path + "'");
  return out;
}

void write(std::ofstream& out, std::string& buffer, const std::string& path) {
  if (buffer.empty()) return;
  out << buffer;
  out.flush();
  if (!out) throw std::runtime_error("write to '" + path + "' failed (disk full?)");
  buffer.clear();
}

}  // namespace

RveCostLog::RveCostLog(const std::string& dir, std::size_t n_points, std::int64_t last_step)
    : costs_path_(dir + "/rve_costs.csv"), ranks_path_(dir + "/rve_ranks.csv") {
  const std::string head = header(n_points);
  costs_ = open(costs_path_, head, last_step);
  ranks_ = open(ranks_path_, head, last_step);
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
  write(costs_, costs_buffer_, costs_path_);
  write(ranks_, ranks_buffer_, ranks_path_);
  pending_ = 0;
}

}  // namespace mpmdem::mpm
