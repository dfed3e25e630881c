#include "run/elastic_column_observer.hpp"

#include <exception>
#include <ostream>

#include "verification/elastic_column.hpp"

namespace mpmdem::mpm {

void ElasticColumnObserver::add_figures(RunContext& run, RunSummary& summary) {
  if (run.status != RunStatus::kComplete) return;
  try {
    const ElasticColumnResult v = verify_elastic_column(run.scene, run.solver.particles());
    summary.verification = {{"stress_rel_error", v.stress_rel_error},
                            {"settlement_rel_error", v.settlement_rel_error},
                            {"settlement_top_m", v.settlement_top_m},
                            {"settlement_top_expected_m", v.settlement_top_expected_m},
                            {"settlement_surface_expected_m", v.settlement_surface_expected_m}};
  } catch (const std::exception& e) {
    run.err << "warning: verification " << summary.verification_kind
            << " not computed: " << e.what() << std::endl;
    summary.verification.clear();
  }
}

}  // namespace mpmdem::mpm
