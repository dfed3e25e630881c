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
#include <vector>

#include "constitutive/model_registry.hpp"
#include "constitutive/remote.hpp"
#include "errors.hpp"
#include "mpmdem/config/schema.hpp"
#include "mpmdem/errors.hpp"
#include "output/checkpoint.hpp"
#include "output/run_directory.hpp"
#include "output/run_outputs.hpp"
#include "particle_init.hpp"
#include "run/bar_vibration_observer.hpp"
#include "run/checkpoints.hpp"
#include "run/column_observer.hpp"
#include "run/elastic_column_observer.hpp"
#include "run/model_observer.hpp"
#include "run/observer.hpp"
#include "run/progress_observer.hpp"
#include "run/signals.hpp"
#include "run/step_log.hpp"
#include "run_status.hpp"
#include "run_support.hpp"
#include "solver.hpp"

namespace mpmdem::mpm {

namespace {

using namespace run_support;

// One run: set up, the time loop over the observers (run/observer.hpp), finish with
// summary.json. RunResult is filled as it goes.
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
    ctx_.emplace(RunContext{scene_, dir_, *solver_, out_, err_, [this] { return wall_time(); },
                            [this] { return expected_end_time(); }});
    ctx_->resumed = !resume_dir_.empty();
    ctx_->status = status_;
    SignalGuard signals(opt_.handle_signals);
    try {
      make_observers();
      time_loop();
      for (auto& o : observers_) o->on_end(*ctx_);
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
    sum.model = solver_->provider().name();
    sum.resumed_from_step = solver_->step_count();
    sum.mass_initial_kg = resumed_.mass_initial_kg;
    sum.step_wall_time_s = resumed_.step_wall_time_s;
    sum.step_cpu_time_s = resumed_.step_cpu_time_s;
    sum.dt_min_s = resumed_.dt_min_s;
    sum.dt_max_s = resumed_.dt_max_s;
    wall_before_ = resumed_.wall_time_s;
    set_status(RunStatus::kComplete);
    out_ << "mpm_app " << MPMDEM_VERSION << ": scene '" << scene_.name << "' resumed from "
         << resume_dir_ << " (step " << solver_->step_count() << ", t=" << solver_->time()
         << " s)\n  results: " << dir_ << std::endl;
    return true;
  }

  // The observers of the time loop, in the order they see each step and add their figures
  // to summary.json (analysis figures: the column's, the model's, the checkpoints', the
  // timings'). A resumed run hands each its part of the checkpoint.
  void make_observers() {
    observers_.push_back(std::make_unique<StepLog>());
    if (scene_.verification.kind == VerificationKind::kBarVibration) {
      observers_.push_back(std::make_unique<BarVibrationObserver>());
    } else if (scene_.verification.kind == VerificationKind::kElasticColumn) {
      observers_.push_back(std::make_unique<ElasticColumnObserver>());
    }
    if (scene_.column_collapse.enabled) {
      observers_.push_back(std::make_unique<ColumnCollapseObserver>(scene_));
    }
    observers_.push_back(std::make_unique<ModelObserver>(*solver_));
    auto checkpoints = std::make_unique<Checkpoints>([this] { return run_state(); });
    checkpoints_ = checkpoints.get();
    observers_.push_back(std::move(checkpoints));
    observers_.push_back(std::make_unique<RunOutputs>(scene_, dir_));
    observers_.push_back(std::make_unique<ProgressObserver>());
    if (!resume_dir_.empty()) {
      for (auto& o : observers_) o->restore(*ctx_, resumed_);
    }
  }

  // The state a checkpoint holds besides the solver's: the run's own (timing sums, wall
  // time, time-step range, initial mass, the provider's state) and every observer's part.
  DriverState run_state() {
    DriverState d;
    d.step_wall_time_s = s().step_wall_time_s;
    d.step_cpu_time_s = s().step_cpu_time_s;
    d.wall_time_s = wall_time();
    d.dt_min_s = s().dt_min_s;
    d.dt_max_s = s().dt_max_s;
    d.mass_initial_kg = s().mass_initial_kg;
    d.provider_state = solver_->provider().save_state();
    for (auto& o : observers_) o->save(d);
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
    if (ctx_) ctx_->status = status;
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

  // Step until the end time, an observer ends the run, or a stop request. After each step
  // every observer sees it, then a checkpoint is written if one is due.
  void time_loop() {
    RunContext& run = *ctx_;
    for (auto& o : observers_) o->on_start(run);
    while (!solver_->finished() && !an_observer_ends_run()) {
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
      for (auto& o : observers_) o->after_step(run);
      if (checkpoints_->due(run)) checkpoints_->write(run);
    }
  }

  bool an_observer_ends_run() const {
    return std::any_of(observers_.begin(), observers_.end(),
                       [this](const auto& o) { return o->ends_run(*ctx_); });
  }

  // Simulated time at which the run will end (as far as known now).
  double expected_end_time() const {
    double end = scene_.solver.end_time;
    for (const auto& o : observers_) end = std::min(end, o->end_time());
    return end;
  }

  void timed_step() {
    const auto wall_start = std::chrono::steady_clock::now();
    const double cpu_start = process_cpu_time();
    solver_->step();
    ++s().steps_this_run;
    s().step_wall_time_s +=
        std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
    s().step_cpu_time_s += process_cpu_time() - cpu_start;
    const double dt = solver_->dt();
    ctx_->dt = dt;
    s().dt_min_s = std::min(s().dt_min_s, dt);
    s().dt_max_s = std::max(s().dt_max_s, dt);
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
      const std::string fault_dir = checkpoints_ ? checkpoints_->write_fault(*ctx_) : "";
      if (!fault_dir.empty()) msg << "; mpm_app's own state at the fault: " << fault_dir;
      const std::string last = latest_checkpoint(dir_);
      if (const auto* lost = dynamic_cast<const PeerLost*>(&e)) {
        s().peer_fault =
            PeerFault{lost->kind() == PeerLost::Kind::kDied ? "died" : "no_reply",
                      solver_->step_count(),
                      lost->ranks(),
                      lost->hosts(),
                      lost->exact(),
                      last,
                      (last.empty() || !checkpoints_) ? 0.0 : checkpoints_->newest_wall_time_s()};
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
    // Every observer adds its figures: the verification, the analysis, the stop reason.
    sum.analysis.clear();
    sum.stop_reason = stop_reason(status_);
    sum.stop.clear();
    for (auto& o : observers_) o->add_figures(*ctx_, sum);
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
  std::string resume_dir_;  // checkpoint this run continues from ("" for a fresh run)
  DriverState resumed_;
  double wall_before_ = 0.0;  // wall time of the run before its last resume
  std::optional<RunContext> ctx_;
  Observers observers_;  // make_observers()
  Checkpoints* checkpoints_ = nullptr;
};

}  // namespace

RunResult run_scene(const Scene& scene, const RunOptions& options) {
  return Run(scene, options).execute();
}

}  // namespace mpmdem::mpm
