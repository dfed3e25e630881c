#include "run_driver.hpp"

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <iostream>
#include <limits>
#include <memory>
#include <optional>
#include <sstream>
#include <tuple>

#include "analysis/column_collapse.hpp"
#include "constitutive/model_registry.hpp"
#include "constitutive/remote.hpp"
#include "errors.hpp"
#include "mpmdem/config/schema.hpp"
#include "mpmdem/errors.hpp"
#include "output/checkpoint.hpp"
#include "output/hdf5_writer.hpp"
#include "output/run_directory.hpp"
#include "output/run_outputs.hpp"
#include "particle_init.hpp"
#include "progress.hpp"
#include "run_status.hpp"
#include "run_support.hpp"
#include "solver.hpp"
#include "verification/bar_vibration.hpp"

namespace mpmdem::mpm {

namespace {

using namespace run_support;

// One run: set-up, time loop, final outputs, summary. RunResult is filled as it goes.
class Run {
 public:
  Run(const Scene& scene, const RunOptions& opt)
      : scene_(scene),
        opt_(opt),
        out_(opt.out ? *opt.out : std::cout),
        err_(opt.err ? *opt.err : std::cerr),
        clock_(opt.clock ? opt.clock : steady_seconds),
        wall_start_(clock_()) {
    if (opt.threads > 0) scene_.solver.threads = opt.threads;
    if (scene_.solver.threads > 0) omp_set_num_threads(scene_.solver.threads);
    dir_ = opt.out_dir.empty() ? default_run_directory(scene_.name) : opt.out_dir;
  }

  RunResult execute() {
    clear_stop_request();
    if (!set_up()) return result_;
    SignalGuard signals(opt_.handle_signals);
    try {
      time_loop();
      final_outputs();
      if (status_ == RunStatus::kComplete) verify();
      result_.exit_code = exit_code(status_);
    } catch (const std::exception& e) {
      fail(e);
    }
    finish();
    return result_;
  }

 private:
  RunSummary& s() { return result_.summary; }
  // The run's wall time (also before a resume): what summary.json reports and what the
  // time-triggered checkpoints count (RunOptions::clock).
  double wall_time() const { return wall_before_ + (clock_() - wall_start_); }
  static double steady_seconds() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch())
        .count();
  }

  // Particles, provider and solver. Whatever can reject the scene is done before the run
  // directory is created or touched (a remote provider needs the directory for the server's
  // port file, so it comes after). Returns false if the run cannot start.
  bool set_up() {
    RunSummary& sum = s();
    sum.scene = scene_.name;
    // Absolute, so that tools reading summary.json find the scene from any directory.
    sum.config_file =
        scene_.source_file.empty()
            ? std::string()
            : std::filesystem::absolute(scene_.source_file).lexically_normal().string();
    sum.model = scene_.constitutive.model;
    sum.program_version = MPMDEM_VERSION;
    sum.end_time_s = scene_.solver.end_time;
    sum.threads = omp_get_max_threads();
    sum.verification_kind = verification_name(scene_.verification.kind);
    if (!opt_.resume.empty()) return set_up_resumed();
    try {
      check_run_directory(dir_, opt_.force);
      Particles particles = generate_particles(scene_);
      const std::size_t n = particles.size();
      sum.n_material_points = n;
      if (opt_.provider_factory || !scene_.constitutive.is_remote()) {
        solver_ = std::make_unique<Solver>(scene_, std::move(particles), local_provider(n));
        create_directory();
      } else {
        create_directory();
        solver_ = std::make_unique<Solver>(scene_, std::move(particles),
                                           make_remote_provider(scene_, n, dir_));
      }
    } catch (const std::exception& e) {
      return setup_failed("setting up the run failed: ", e);
    }
    if (scene_.column_collapse.enabled) column_.emplace(scene_);
    sum.model = solver_->provider().name();
    sum.mass_initial_kg = total_mass(solver_->particles());
    sum.dt_min_s = std::numeric_limits<double>::infinity();
    set_status(RunStatus::kComplete);
    out_ << "mpm_app " << MPMDEM_VERSION << ": scene '" << scene_.name << "' ("
         << scene_.source_file << ")\n  " << solver_->particles().size()
         << " material points, cell size " << scene_.grid.cell_size << " m, model " << sum.model
         << ", " << sum.threads << " thread(s), end time " << scene_.solver.end_time
         << " s\n  results: " << dir_ << std::endl;
    return true;
  }

  std::unique_ptr<ConstitutiveProvider> local_provider(std::size_t n) {
    if (opt_.provider_factory) return opt_.provider_factory(scene_, n);
    return local_model(scene_.constitutive.model).make(scene_.constitutive);
  }

  // Continue from a checkpoint in the existing run directory (outputs after it are redone).
  bool set_up_resumed() {
    RunSummary& sum = s();
    try {
      if (!std::filesystem::is_directory(dir_)) {
        throw RunDirectoryError("--resume: run directory '" + dir_ + "' does not exist");
      }
      resume_dir_ = opt_.resume == "latest" ? latest_checkpoint(dir_) : opt_.resume;
      if (resume_dir_.empty()) {
        throw RunDirectoryError("--resume latest: '" + dir_ +
                                "' holds no complete checkpoint (checkpoints/step_*/COMPLETE); "
                                "output.checkpoint_interval_s / _steps write them");
      }
      SolverState state;
      read_mpm_checkpoint(resume_dir_, state, resumed_);
      dir_created_ = true;
      result_.run_dir = dir_;
      sum.run_directory = dir_;
      const std::size_t n = state.n_slots;
      auto provider = (opt_.provider_factory || !scene_.constitutive.is_remote())
                          ? local_provider(n)
                          : make_remote_provider(scene_, n, dir_);
      solver_ = std::make_unique<Solver>(scene_, std::move(state), std::move(provider));
      solver_->provider().load_state(resumed_.provider_state);
    } catch (const std::exception& e) {
      return setup_failed("resuming the run failed: ", e);
    }
    if (scene_.column_collapse.enabled) {
      column_.emplace(scene_);
      column_->restore(resumed_.column);
    }
    sum.model = solver_->provider().name();
    sum.resumed_from_step = solver_->step_count();
    sum.mass_initial_kg = resumed_.mass_initial_kg;
    sum.step_wall_time_s = resumed_.step_wall_time_s;
    sum.step_cpu_time_s = resumed_.step_cpu_time_s;
    sum.dt_min_s = resumed_.dt_min_s;
    sum.dt_max_s = resumed_.dt_max_s;
    wall_before_ = resumed_.wall_time_s;
    newest_checkpoint_wall_s_ = resumed_.wall_time_s;
    set_status(RunStatus::kComplete);
    out_ << "mpm_app " << MPMDEM_VERSION << ": scene '" << scene_.name << "' resumed from "
         << resume_dir_ << " (step " << solver_->step_count() << ", t=" << solver_->time()
         << " s)\n  results: " << dir_ << std::endl;
    return true;
  }

  std::int64_t rve_particles() const {
    return resume_dir_.empty() ? solver_->provider().rve_particles() : resumed_.rve_particles;
  }

  // Both sides save their state; the checkpoint counts once both are done (COMPLETE).
  // Returns the wall time it took.
  double write_checkpoint() {
    require_finite();
    const double start = wall_time();
    const std::string dir = checkpoint_directory(dir_, solver_->step_count());
    const DriverState state = driver_state();
    write_mpm_checkpoint(dir, solver_->state(), state);
    solver_->provider().checkpoint(dir + "/dem", solver_->step_count());
    commit_checkpoint(dir_, dir, scene_.output.checkpoints_kept);
    newest_checkpoint_wall_s_ = state.wall_time_s;
    const double took = wall_time() - start;
    checkpoint_wall_s_ += took;
    ++checkpoints_;
    out_ << "[step " << solver_->step_count() << ", t=" << solver_->time() << " s] checkpoint "
         << dir << " (" << format_seconds(took) << " s)" << std::endl;
    return took;
  }

  // A peer fault (a DEM rank died, an MPI failure): mpm_app saves its own state, without
  // COMPLETE (the DEM side is lost, --resume never picks it). Returns the directory, or ""
  // if it could not be written.
  std::string write_fault_checkpoint() {
    const std::string dir = fault_checkpoint_directory(dir_, solver_->step_count());
    try {
      write_mpm_checkpoint(dir, solver_->state(), driver_state());
      return dir;
    } catch (const std::exception& e) {
      err_ << "warning: writing the fault checkpoint " << dir << " failed: " << e.what()
           << std::endl;
      return "";
    }
  }

  DriverState driver_state() {
    DriverState d;
    outputs_->save(d);
    if (column_) d.column = column_->state();
    d.step_wall_time_s = s().step_wall_time_s;
    d.step_cpu_time_s = s().step_cpu_time_s;
    d.wall_time_s = wall_time();
    d.dt_min_s = s().dt_min_s;
    d.dt_max_s = s().dt_max_s;
    d.mass_initial_kg = s().mass_initial_kg;
    d.rve_particles = rve_particles();
    d.provider_state = solver_->provider().save_state();
    return d;
  }

  void create_directory() {
    create_run_directory(dir_, opt_.force);
    dir_created_ = true;
    result_.run_dir = dir_;
    s().run_directory = dir_;
  }

  void set_status(RunStatus status) {
    status_ = status;
    s().status = status_text(status);
  }

  // A run that could not start: the message (an untyped fault's after `context`), the exit
  // code of its kind (run_status.hpp). Returns false.
  bool setup_failed(const std::string& context, const std::exception& e) {
    const RunStatus status = failure_status(e);
    const std::string what = (status == RunStatus::kFailed ? context : "") + e.what();
    err_ << "error: " << what << std::endl;
    result_.exit_code = exit_code(status);
    if (dir_created_) {  // mark the directory's (empty) results as failed
      set_status(status);
      s().error = what;
      s().wall_time_s = wall_time();
      write_summary_file();
    }
    return false;
  }

  // Step until the end time or a stop request; energies, frames and progress on the way.
  void time_loop() {
    outputs_.emplace(scene_, dir_);
    if (resume_dir_.empty()) {
      outputs_->start(*solver_);
    } else {
      outputs_->resume(*solver_, resumed_);
    }
    if (scene_.verification.kind == VerificationKind::kBarVibration) {
      try {
        bar_.emplace(scene_);
        bar_->record(solver_->time(), solver_->particles());
      } catch (const std::exception& e) {  // a verification fault does not stop the run
        err_ << "warning: bar_vibration verification disabled: " << e.what() << std::endl;
      }
    }
    print_events();
    observe_column();
    outputs_->start_checkpoints(wall_time());

    Progress progress(out_, scene_.output.progress_interval_s);
    progress.start(solver_->time());

    while (!solver_->finished() && !(column_ && column_->done(solver_->time()))) {
      if (stop_requested()) {
        set_status(RunStatus::kInterrupted);
        out_ << "stop requested: stopping after step " << solver_->step_count() << std::endl;
        break;
      }
      if (opt_.max_steps > 0 && solver_->step_count() >= opt_.max_steps) {
        set_status(RunStatus::kTruncated);
        out_ << "--max-steps " << opt_.max_steps << " reached: stopping" << std::endl;
        break;
      }
      timed_step();
      log_time_step();
      print_events();
      if (bar_) bar_->record(solver_->time(), solver_->particles());
      outputs_->after_step(*solver_, last_dt_);
      observe_column();
      if (outputs_->checkpoint_due(solver_->step_count(), wall_time())) {
        const double took = write_checkpoint();
        outputs_->checkpoint_written(wall_time(), took);
      }
      if (progress.due()) progress.update(progress_state());
    }
    progress.print(progress_state());
  }

  // Column collapse: the start of stage 2 and the snapshots at t_r + k t*.
  void observe_column() {
    if (!column_) return;
    const double t = solver_->time();
    if (column_->observe(t, solver_->boundary_conditions(), solver_->particles())) {
      out_ << "[step " << solver_->step_count() << ", t=" << t
           << " s] stage 2 (collapse) starts: stage 1 took " << t
           << " s; t* = " << column_->geometry().t_star
           << " s, the run ends at t = " << column_->end_time() << " s"
           << (column_->at_rest() ? " or earlier, once the deposit is at rest" : "") << std::endl;
    }
    if (column_->observe_rest(t, solver_->particles())) {
      const AtRestDetector& r = *column_->at_rest();
      out_ << "[step " << solver_->step_count() << ", t=" << t
           << " s] the deposit is at rest: E_k/E_p0 < " << r.kinetic_ratio()
           << " since t/t* = " << *r.quiet_since() / column_->geometry().t_star
           << "; stage 2 ends at t/t* = " << column_->time_over_t_star(t) << std::endl;
    }
    for (const std::string& label : column_->due_snapshots(t, 1e-6 * last_dt_)) {
      require_finite();
      std::filesystem::create_directories(dir_ + "/snapshots");
      write_final_state(dir_ + "/snapshots/" + label + ".h5", solver_->particles(),
                        {t, solver_->step_count(), scene_.name, scene_.source_file});
      if (!outputs_->frame_written_at(solver_->step_count())) outputs_->write_frame(*solver_);
      out_ << "[step " << solver_->step_count() << ", t=" << t << " s] snapshot " << label
           << " (t/t* = " << column_->time_over_t_star(t) << ")" << std::endl;
    }
  }

  // Simulated time at which the run will end (as far as known now).
  double expected_end_time() const {
    return std::min(scene_.solver.end_time, column_ ? column_->end_time() : scene_.solver.end_time);
  }

  void timed_step() {
    const auto wall_start = std::chrono::steady_clock::now();
    const double cpu_start = process_cpu_time();
    solver_->step();
    ++s().steps_this_run;
    s().step_wall_time_s +=
        std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
    s().step_cpu_time_s += process_cpu_time() - cpu_start;
    last_dt_ = solver_->dt();
    s().dt_min_s = std::min(s().dt_min_s, last_dt_);
    s().dt_max_s = std::max(s().dt_max_s, last_dt_);
  }

  void log_time_step() {
    const std::string line = dt_log_.line(last_dt_, solver_->step_count(), solver_->time());
    if (!line.empty()) out_ << line << std::endl;
  }

  void print_events() {
    for (const std::string& e : solver_->take_events()) {
      out_ << "[step " << solver_->step_count() << ", t=" << solver_->time() << " s] " << e
           << std::endl;
    }
  }

  void require_finite() const { mpm::require_finite(solver_->particles(), solver_->step_count()); }

  ProgressState progress_state() const {
    return {solver_->step_count(),   solver_->time(),
            expected_end_time(),     last_dt_,
            solver_->energies().E_k, solver_->initial_potential_energy()};
  }

  // Last energy row and frame (if not just written), and the final state (complete or
  // interrupted runs).
  void final_outputs() {
    outputs_->final_rows(*solver_, last_dt_);
    if (scene_.output.hdf5) {
      require_finite();
      write_final_state(dir_ + "/final_state.h5", solver_->particles(),
                        {solver_->time(), solver_->step_count(), scene_.name, scene_.source_file});
    }
  }

  // The verification figures of the scene's kind. A fault here (e.g. moduli not found) is
  // reported but does not turn a complete run into a failed one: the figures are absent.
  void verify() {
    try {
      s().verification =
          verification_figures(scene_, solver_->particles(), bar_ ? &*bar_ : nullptr);
    } catch (const std::exception& e) {
      err_ << "warning: verification " << s().verification_kind << " not computed: " << e.what()
           << std::endl;
      s().verification.clear();
    }
  }

  void fail(const std::exception& e) {
    // A SimulationError names the point and the step itself; other faults get the step.
    std::ostringstream msg;
    if (dynamic_cast<const SimulationError*>(&e) == nullptr) {
      msg << "at step " << solver_->step_count() << " (t=" << solver_->time() << " s): ";
    }
    msg << e.what();
    if (dynamic_cast<const PeerError*>(&e) != nullptr &&
        dynamic_cast<const HandshakeError*>(&e) == nullptr) {
      const std::string fault_dir = write_fault_checkpoint();
      if (!fault_dir.empty()) msg << "; mpm_app's own state at the fault: " << fault_dir;
      const std::string last = latest_checkpoint(dir_);
      if (const auto* lost = dynamic_cast<const PeerLost*>(&e)) {
        s().peer_fault = PeerFault{lost->kind() == PeerLost::Kind::kDied ? "died" : "no_reply",
                                   solver_->step_count(),
                                   lost->ranks(),
                                   lost->hosts(),
                                   lost->exact(),
                                   last,
                                   last.empty() ? 0.0 : newest_checkpoint_wall_s_};
      }
      msg << (last.empty() ? "; no complete checkpoint to resume from"
                           : "; the newest checkpoint complete on both sides is " + last +
                                 " (scripts/run --resume " + dir_ + ")");
    }
    set_status(failure_status(e));
    s().error = msg.str();
    err_ << "error: " << s().error << std::endl;
    result_.exit_code = exit_code(status_);
  }

  // Provider end, headline figures, summary.json, closing lines.
  void finish() {
    RunSummary& sum = s();
    // A complete or interrupted run ends the provider in order (remote: the servers shut
    // down and exit 0). After a failure it is not finished: destroying it aborts, so a
    // remote server ends with an error too.
    if (!is_failure(status_)) {
      try {
        solver_->provider().finish();
      } catch (const std::exception& e) {
        err_ << "warning: ending the constitutive provider: " << e.what() << std::endl;
      }
    }
    const Particles& p = solver_->particles();
    sum.steps = solver_->step_count();
    sum.time_s = solver_->time();
    sum.removed_points = solver_->removed_points();
    sum.n_material_points = p.size() + sum.removed_points;
    sum.mass_final_kg = total_mass(p);
    sum.mass_grid_kg = total_mass(solver_->grid());
    if (!(sum.dt_min_s <= sum.dt_max_s)) sum.dt_min_s = sum.dt_max_s = 0.0;
    const Energies e = solver_->energies();
    sum.E_p0_J = solver_->initial_potential_energy();
    sum.E_p_J = e.E_p;
    sum.E_k_J = e.E_k;
    const EnergyBudget& b = solver_->energy_budget();
    std::tie(sum.E_k0_J, sum.W_int_J, sum.W_damp_J, sum.W_bc_J, sum.W_transfer_J,
             sum.W_transfer_walls_J) =
        std::tie(b.E_k0, b.W_int, b.W_damp, b.W_bc, b.W_transfer, b.W_transfer_walls);
    sum.analysis.clear();
    if (column_) sum.analysis = column_->figures(solver_->time(), p);
    sum.stop_reason =
        stop_reason(sum.status, column_ ? column_->end_reason(solver_->time()) : std::string());
    sum.stop.clear();
    if (column_) sum.stop = column_->stop_figures(sum.time_s, sum.steps);
    if (scene_.constitutive.is_remote()) {
      for (const auto& kv : remote_figures(*solver_, rve_particles())) sum.analysis.push_back(kv);
    } else if (const LocalModel* model = find_local_model(scene_.constitutive.model);
               model && model->figures) {
      for (const auto& kv : model->figures(scene_.constitutive, *solver_)) {
        sum.analysis.push_back(kv);
      }
    }
    if (checkpoints_ > 0) {  // this process's part of the run (a resumed one: since resuming)
      sum.analysis.emplace_back("checkpoints", static_cast<double>(checkpoints_));
      sum.analysis.emplace_back("checkpoint_wall_time_s", checkpoint_wall_s_);
    }
    if (outputs_) {
      for (const auto& kv : outputs_->close()) sum.analysis.push_back(kv);
    }
    if (opt_.final_particles) *opt_.final_particles = p;
    sum.wall_time_s = wall_time();
    if (!write_summary_file() && result_.exit_code == 0) {
      result_.exit_code = exit_code(RunStatus::kFailed);
    }
    out_ << "status: " << sum.status << ", " << sum.steps << " steps, t=" << sum.time_s
         << " s, wall " << sum.wall_time_s << " s" << std::endl;
    for (const auto& [key, value] : sum.verification) out_ << "  " << key << " = " << value << "\n";
    out_ << "results: " << dir_ << std::endl;
  }

  bool write_summary_file() {
    try {
      write_summary(dir_ + "/summary.json", s());
      return true;
    } catch (const std::exception& e) {
      err_ << "error: writing summary.json: " << e.what() << std::endl;
      return false;
    }
  }

  Scene scene_;
  const RunOptions& opt_;
  std::ostream& out_;
  std::ostream& err_;
  std::function<double()> clock_;
  double wall_start_;
  std::string dir_;
  bool dir_created_ = false;
  RunResult result_;
  RunStatus status_ = RunStatus::kComplete;  // summary.json's "status" is status_text(status_)
  std::unique_ptr<Solver> solver_;
  std::optional<RunOutputs> outputs_;  // energy log, timings, frames, checkpoint triggers
  std::optional<BarVibrationMonitor> bar_;
  std::optional<ColumnCollapseMonitor> column_;
  std::string resume_dir_;  // checkpoint this run continues from ("" for a fresh run)
  DriverState resumed_;
  double wall_before_ = 0.0;               // wall time of the run before its last resume
  double newest_checkpoint_wall_s_ = 0.0;  // the run's wall time at its newest checkpoint
  std::int64_t checkpoints_ = 0;           // checkpoints written by this process
  double checkpoint_wall_s_ = 0.0;         // their wall time, both sides
  double last_dt_ = 0.0;
  TimeStepLog dt_log_;
};

}  // namespace

RunResult run_scene(const Scene& scene, const RunOptions& options) {
  return Run(scene, options).execute();
}

}  // namespace mpmdem::mpm
