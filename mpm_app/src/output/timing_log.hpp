// timings.csv: wall time of every step by phase (issue 5: per-phase timing), and the run's
// totals for summary.json. Columns [s]:
//   step, time, p2g, grid, g2p_dF (grid-to-particle, MUSL re-projection, dF/F/V),
//   stress (the provider's update; remote: the whole exchange with the DEM servers),
//   exchange, dem_max, dem_mean (slowest and mean server rank's backend time; remote only),
//   comm = exchange - dem_max (scatter, gather, waiting: what is not DEM work).
// Rows are buffered and written every 100 steps and at the end.
#pragma once

#include <cstdint>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include "solver.hpp"

namespace mpmdem::mpm {

class TimingLog {
 public:
  static constexpr const char* kHeader =
      "step,time,p2g,grid,g2p_dF,stress,exchange,dem_max,dem_mean,comm";
  // A new log (last_step < 0), or a resumed run's: keeps the rows up to `last_step`, then
  // appends.
  explicit TimingLog(const std::string& path, std::int64_t last_step = -1);
  ~TimingLog();
  TimingLog(const TimingLog&) = delete;
  TimingLog& operator=(const TimingLog&) = delete;

  void append(std::int64_t step, double time, const StepTiming& t);
  void flush();
  // Totals of this process's rows (for summary.json): name -> seconds, and dem_imbalance =
  // sum dem_max / sum dem_mean (1: balanced; 0 when there is no DEM side).
  std::vector<std::pair<std::string, double>> totals() const;

 private:
  std::string path_;
  std::ofstream out_;
  std::string buffer_;
  int pending_ = 0;
  double p2g_ = 0, grid_ = 0, g2p_ = 0, stress_ = 0, exchange_ = 0, dem_max_ = 0, dem_mean_ = 0;
};

}  // namespace mpmdem::mpm
