// rve_costs.csv and rve_ranks.csv (output.rve_costs; remote model): what each material
// point's RVE cost the DEM server in every step, and which server rank ran it. For load-
// balance analysis: the costs of a 1-rank run, summed over an n-rank run's ranks, give the
// imbalance of that run's partition apart from how fast each core happened to run
// (scripts/scaling_study reports it as the partition efficiency).
//   rve_costs.csv  step, p0, p1, ...: the backend time of point i's RVE in that step [us,
//                  4 significant digits]
//                  (0 for an RVE the server skipped; coupling.lazy_tolerance).
//   rve_ranks.csv  step, p0, p1, ...: the server rank that owns point i from that step on;
//                  a row at the first step and after every load-balance migration.
// Rows are buffered and written every 100 steps and at the end.
#pragma once

#include <cstdint>
#include <fstream>
#include <string>
#include <vector>

namespace mpmdem::mpm {

class RveCostLog {
 public:
  // A new run (last_step < 0) or a resumed one: keeps the rows up to `last_step`, appends.
  RveCostLog(const std::string& dir, std::size_t n_points, std::int64_t last_step = -1);
  ~RveCostLog();
  RveCostLog(const RveCostLog&) = delete;
  RveCostLog& operator=(const RveCostLog&) = delete;

  void append(std::int64_t step, const std::vector<double>& cost_s, const std::vector<int>& rank);
  void flush();

 private:
  std::string costs_path_, ranks_path_;
  std::ofstream costs_, ranks_;
  std::string costs_buffer_, ranks_buffer_;
  std::vector<int> last_rank_;
  int pending_ = 0;
};

}  // namespace mpmdem::mpm
