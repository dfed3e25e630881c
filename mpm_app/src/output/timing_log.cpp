#include "output/timing_log.hpp"

#include <cstdio>
#include <cstdlib>
#include <stdexcept>

#include "output/run_directory.hpp"

namespace mpmdem::mpm {

TimingLog::TimingLog(const std::string& path, std::int64_t last_step)
    : path_(path), out_(open_step_log(path, kHeader, last_step, 0)) {}

TimingLog::~TimingLog() {
  try {
    flush();
  } catch (...) {  // a destructor must not throw; the rows are lost, the run is not
  }
}

void TimingLog::append(std::int64_t step, double time, const StepTiming& t) {
  const ProviderTiming& pt = t.provider;
  const double comm = pt.exchange_s > 0.0 ? pt.exchange_s - pt.dem_max_s : 0.0;
  char line[256];
  std::snprintf(line, sizeof line, "%lld,%.9e,%.4e,%.4e,%.4e,%.4e,%.4e,%.4e,%.4e,%.4e\n",
                static_cast<long long>(step), time, t.p2g_s, t.grid_s, t.g2p_s, t.stress_s,
                pt.exchange_s, pt.dem_max_s, pt.dem_mean_s, comm);
  buffer_ += line;
  p2g_ += t.p2g_s;
  grid_ += t.grid_s;
  g2p_ += t.g2p_s;
  stress_ += t.stress_s;
  exchange_ += pt.exchange_s;
  dem_max_ += pt.dem_max_s;
  dem_mean_ += pt.dem_mean_s;
  if (++pending_ >= 100) flush();
}

void TimingLog::flush() {
  write_buffer(out_, buffer_, path_);
  pending_ = 0;
}

std::vector<std::pair<std::string, double>> TimingLog::totals() const {
  return {{"time_p2g_s", p2g_},
          {"time_grid_s", grid_},
          {"time_g2p_dF_s", g2p_},
          {"time_stress_s", stress_},
          {"time_exchange_s", exchange_},
          {"time_dem_max_s", dem_max_},
          {"time_dem_mean_s", dem_mean_},
          {"time_comm_s", exchange_ > 0.0 ? exchange_ - dem_max_ : 0.0},
          {"dem_imbalance", dem_mean_ > 0.0 ? dem_max_ / dem_mean_ : 0.0}};
}

}  // namespace mpmdem::mpm
