#include "run/bar_vibration_observer.hpp"

#include <exception>
#include <ostream>

namespace mpmdem::mpm {

void BarVibrationObserver::on_start(RunContext& run) {
  try {
    bar_.emplace(run.scene);
    bar_->record(run.solver.time(), run.solver.particles());
  } catch (const std::exception& e) {  // a verification fault does not stop the run
    bar_.reset();
    run.err << "warning: bar_vibration verification disabled: " << e.what() << std::endl;
  }
}

void BarVibrationObserver::after_step(RunContext& run) {
  if (bar_) bar_->record(run.solver.time(), run.solver.particles());
}

void BarVibrationObserver::add_figures(RunContext& run, RunSummary& summary) {
  if (run.status != RunStatus::kComplete || !bar_) return;
  try {
    const BarVibrationResult v = bar_->result();
    summary.verification = {{"period_s", v.period_s},
                            {"period_expected_s", v.period_expected_s},
                            {"period_rel_error", v.period_rel_error},
                            {"zero_crossings", static_cast<double>(v.crossings)},
                            {"wave_speed_m_s", v.wave_speed_m_s},
                            {"length_m", v.length_m}};
  } catch (const std::exception& e) {
    run.err << "warning: verification " << summary.verification_kind
            << " not computed: " << e.what() << std::endl;
    summary.verification.clear();
  }
}

}  // namespace mpmdem::mpm
