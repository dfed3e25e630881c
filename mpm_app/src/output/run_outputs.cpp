#include "output/run_outputs.hpp"

#include <limits>

#include "errors.hpp"
#include "output/hdf5_writer.hpp"
#include "run_support.hpp"

namespace mpmdem::mpm {

void require_finite(const Particles& p, std::int64_t step) {
  const std::string bad = run_support::find_non_finite(p);
  if (!bad.empty()) {
    throw SimulationError(bad + " at step " + std::to_string(step) + "; the state is not written");
  }
}

RunOutputs::RunOutputs(const Scene& scene, std::string dir) : scene_(scene), dir_(std::move(dir)) {}

void RunOutputs::restore(RunContext& run, const DriverState& d) {
  const std::int64_t step = run.solver.step_count();
  energy_.emplace(dir_ + "/energies.csv", step);
  timings_.emplace(dir_ + "/timings.csv", step);
  rve_costs_from_ = step;
  if (scene_.output.vtk) vtk_.emplace(dir_, d.frame_times);
  last_frame_step_ = d.last_frame_step;
  last_energy_step_ = d.last_energy_step;
  next_frame_ = d.next_frame;
  next_energy_ = d.next_energy;
}

void RunOutputs::on_start(RunContext& run) {
  const Solver& solver = run.solver;
  if (run.resumed) {
    if (run.frame_wanted && !frame_written_at(solver.step_count())) write_frame(solver);
    run.frame_wanted = false;
    return;
  }
  energy_.emplace(dir_ + "/energies.csv");
  timings_.emplace(dir_ + "/timings.csv");
  log_energy(solver, 0.0);
  if (scene_.output.vtk) vtk_.emplace(dir_);
  write_frame(solver);
  run.frame_wanted = false;
  const double frame_interval = scene_.output.interval;
  const double energy_interval = scene_.output.energy_interval;
  next_frame_ = frame_interval > 0.0 ? frame_interval : std::numeric_limits<double>::infinity();
  next_energy_ = energy_interval > 0.0 ? energy_interval : 0.0;
}

void RunOutputs::after_step(RunContext& run) {
  Solver& solver = run.solver;
  const double dt = run.dt;
  const std::int64_t step = solver.step_count();
  const double t = solver.time();
  if (timings_) timings_->append(step, t, solver.last_timing());
  if (scene_.output.rve_costs && solver.provider().last_rve_costs(cost_s_, cost_rank_)) {
    if (!rve_costs_) rve_costs_.emplace(dir_, cost_s_.size(), rve_costs_from_);
    rve_costs_->append(step, cost_s_, cost_rank_);
  }
  const double tol = 1e-6 * dt;
  if (t >= next_energy_ - tol) {
    log_energy(solver, dt);
    const double interval = scene_.output.energy_interval;
    while (interval > 0.0 && next_energy_ <= t + tol) next_energy_ += interval;
  }
  if (t >= next_frame_ - tol) {
    write_frame(solver);
    while (next_frame_ <= t + tol) next_frame_ += scene_.output.interval;
  } else if (run.frame_wanted) {
    write_frame(solver);
  }
  run.frame_wanted = false;
}

void RunOutputs::log_energy(const Solver& solver, double dt) {
  const Energies e = solver.energies();
  const EnergyBudget& b = solver.energy_budget();
  energy_->append({solver.time(), solver.step_count(), dt, e.E_p, e.E_k, e.E_strain,
                   solver.initial_potential_energy(), b.E_k0, b.W_int, b.W_damp, b.W_bc,
                   b.W_transfer, b.W_transfer_walls});
  last_energy_step_ = solver.step_count();
}

void RunOutputs::write_frame(const Solver& solver) {
  if (!vtk_) return;
  require_finite(solver.particles(), solver.step_count());
  vtk_->write_frame(solver.particles(), solver.time());
  last_frame_step_ = solver.step_count();
}

void RunOutputs::on_end(RunContext& run) {
  const Solver& solver = run.solver;
  if (last_energy_step_ != solver.step_count()) log_energy(solver, run.dt);
  if (last_frame_step_ != solver.step_count()) write_frame(solver);
  if (scene_.output.hdf5) {
    require_finite(solver.particles(), solver.step_count());
    write_final_state(dir_ + "/final_state.h5", solver.particles(),
                      {solver.time(), solver.step_count(), scene_.name, scene_.source_file});
  }
}

void RunOutputs::save(DriverState& d) {
  d.next_frame = next_frame_;
  d.next_energy = next_energy_;
  if (vtk_) d.frame_times = vtk_->frame_times();
  d.last_frame_step = last_frame_step_;
  d.last_energy_step = last_energy_step_;
  if (timings_) timings_->flush();
  if (rve_costs_) rve_costs_->flush();
}

void RunOutputs::add_figures(RunContext& run, RunSummary& summary) {
  (void)run;
  if (timings_) {
    timings_->flush();
    for (const auto& kv : timings_->totals()) summary.analysis.push_back(kv);
  }
  if (rve_costs_) rve_costs_->flush();
}

}  // namespace mpmdem::mpm
