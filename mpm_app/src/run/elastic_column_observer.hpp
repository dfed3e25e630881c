// Verification case elastic_column (verification/elastic_column.hpp): at the end of a
// complete run, the stress and settlement errors against the analytic solution in
// summary.json's "verification". A fault here (e.g. moduli not found) is a warning, not a
// failed run: the figures are then absent.
#pragma once

#include "run/observer.hpp"

namespace mpmdem::mpm {

class ElasticColumnObserver : public Observer {
 public:
  void add_figures(RunContext& run, RunSummary& summary) override;
};

}  // namespace mpmdem::mpm
