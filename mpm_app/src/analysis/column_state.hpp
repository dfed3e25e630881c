// The column-collapse monitor's state as a checkpoint carries it (analysis/column_collapse.hpp
// fills and restores it; output/checkpoint.cpp stores it without knowing the analysis).
#pragma once

#include <optional>
#include <vector>

namespace mpmdem::mpm {

struct ColumnState {
  std::optional<double> release_time;  // start of stage 2
  double E_p0_release = 0.0;
  std::vector<char> snapshots_done;
  std::optional<double> rest_quiet_since;  // the at-rest detector's, in stage-2 time
  std::optional<double> rest_time;
};

}  // namespace mpmdem::mpm
