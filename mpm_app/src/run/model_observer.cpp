#include "run/model_observer.hpp"

#include "constitutive/model_registry.hpp"

namespace mpmdem::mpm {

void ModelObserver::restore(RunContext& run, const DriverState& d) {
  (void)run;
  resumed_rve_particles_ = d.rve_particles;
}

std::int64_t ModelObserver::rve_particles() const {
  return resumed_rve_particles_ ? *resumed_rve_particles_ : solver_.provider().rve_particles();
}

void ModelObserver::save(DriverState& d) {
  d.rve_particles = rve_particles();
}

void ModelObserver::add_figures(RunContext& run, RunSummary& summary) {
  const ConstitutiveParams& params = run.scene.constitutive;
  if (params.is_remote()) {
    const ConstitutiveProvider& provider = solver_.provider();
    const std::pair<std::string, double> figures[] = {
        {"n_rve_particles", static_cast<double>(rve_particles())},
        {"dem_ranks", static_cast<double>(provider.dem_ranks())},
        {"rebalances", static_cast<double>(provider.rebalances())},
        {"rve_evaluations", static_cast<double>(provider.rve_evaluations())},
        {"rve_skipped", static_cast<double>(provider.rve_skipped())},
        {"rve_no_contact_updates", static_cast<double>(solver_.no_contact_updates())},
        {"rve_no_contact_points_final", static_cast<double>(solver_.no_contact_points())}};
    for (const auto& kv : figures) summary.analysis.push_back(kv);
  } else if (const LocalModel* model = find_local_model(params.model); model && model->figures) {
    for (const auto& kv : model->figures(params, solver_)) summary.analysis.push_back(kv);
  }
}

}  // namespace mpmdem::mpm
