#include "run_driver.hpp"

#include <omp.h>

#include <chrono>
#include <cmath>
#include <csignal>
#include <ctime>
#include <iostream>
#include <limits>
#include <memory>
#include <optional>
#include <sstream>

#include "constitutive/linear_elastic.hpp"
#include "constitutive/remote.hpp"
#include "errors.hpp"
#include "mpmdem/config/schema.hpp"
#include "mpmdem/errors.hpp"
#include "output/energy_log.hpp"
#include "output/hdf5_writer.hpp"
#include "output/run_directory.hpp"
#include "output/vtk_writer.hpp"
#include "particle_init.hpp"
#include "progress.hpp"
#include "solver.hpp"
#include "verification/bar_vibration.hpp"
#include "verification/elastic_column.hpp"

namespace mpmdem::mpm {

namespace {

volatile std::sig_atomic_t g_stop = 0;

extern "C" void on_stop_signal(int sig) {
  if (g_stop) {  // second signal: stop at once
    std::signal(sig, SIG_DFL);
    std::raise(sig);
    return;
  }
  g_stop = 1;
}

// SIGINT/SIGTERM ask the run to stop after the current step, for the run's duration.
class SignalGuard {
 public:
  explicit SignalGuard(bool active) : active_(active) {
    if (!active_) return;
    struct sigaction sa {};
    sa.sa_handler = on_stop_signal;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGINT, &sa, &old_int_);
    sigaction(SIGTERM, &sa, &old_term_);
  }
  ~SignalGuard() {
    if (!active_) return;
    sigaction(SIGINT, &old_int_, nullptr);
    sigaction(SIGTERM, &old_term_, nullptr);
  }
  SignalGuard(const SignalGuard&) = delete;
  SignalGuard& operator=(const SignalGuard&) = delete;

 private:
  bool active_;
  struct sigaction old_int_ {};
  struct sigaction old_term_ {};
};

const char* model_name(ModelKind kind) {
  return kind == ModelKind::kRemote ? "remote" : "linear_elastic";
}

const char* verification_name(VerificationKind kind) {
  switch (kind) {
    case VerificationKind::kElasticColumn:
      return "elastic_column";
    case VerificationKind::kBarVibration:
      return "bar_vibration";
    case VerificationKind::kNone:
      break;
  }
  return "";
}

double total_mass(const Particles& p) {
  double m = 0.0;
  for (double m_p : p.m) m += m_p;
  return m;
}

bool finite(const Vec3& v) {
  return v.allFinite();
}
bool finite(const Mat3& v) {
  return v.allFinite();
}
bool finite(double v) {
  return std::isfinite(v);
}

// Names the first non-finite value of the state, or returns "" if all are finite.
std::string find_non_finite(const Particles& p) {
  auto where = [&p](std::size_t i, const char* field) {
    std::ostringstream msg;
    msg << "non-finite " << field << " at material point " << p.id[i] << " (initial position "
        << p.x0[i].transpose() << ")";
    return msg.str();
  };
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (!finite(p.x[i])) return where(i, "position");
    if (!finite(p.v[i])) return where(i, "velocity");
    if (!finite(p.sigma[i])) return where(i, "stress");
    if (!finite(p.F[i])) return where(i, "deformation gradient");
    if (!finite(p.V[i])) return where(i, "volume");
    if (!finite(p.m[i])) return where(i, "mass");
  }
  return "";
}

// CPU time of the whole process (all threads) [s].
double process_cpu_time() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

std::string format_seconds(double s) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3e", s);
  return buf;
}

}  // namespace

void request_stop() {
  g_stop = 1;
}

namespace {

// One run: set-up, time loop, final outputs, summary. RunResult is filled as it goes.
class Run {
 public:
  Run(const Scene& scene, const RunOptions& opt)
      : scene_(scene),
        opt_(opt),
        out_(opt.out ? *opt.out : std::cout),
        err_(opt.err ? *opt.err : std::cerr),
        wall_start_(std::chrono::steady_clock::now()) {
    if (opt.threads > 0) scene_.solver.threads = opt.threads;
    if (scene_.solver.threads > 0) omp_set_num_threads(scene_.solver.threads);
    dir_ = opt.out_dir.empty() ? default_run_directory(scene_.name) : opt.out_dir;
  }

  RunResult execute() {
    g_stop = 0;
    if (!set_up()) return result_;
    SignalGuard signals(opt_.handle_signals);
    try {
      time_loop();
      final_outputs();
      if (s().status == "complete") verify();
      result_.exit_code = s().status == "interrupted" ? 130 : 0;
    } catch (const std::exception& e) {
      fail(e);
    }
    finish();
    return result_;
  }

 private:
  RunSummary& s() { return result_.summary; }
  double wall_time() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start_).count();
  }

  // Particles, provider and solver. Whatever can reject the scene is done before the run
  // directory is created or touched (a remote provider needs the directory for the server's
  // port file, so it comes after). Returns false if the run cannot start.
  bool set_up() {
    RunSummary& sum = s();
    sum.scene = scene_.name;
    sum.config_file = scene_.source_file;
    sum.model = model_name(scene_.constitutive.model);
    sum.program_version = MPMDEM_VERSION;
    sum.end_time_s = scene_.solver.end_time;
    sum.threads = omp_get_max_threads();
    sum.verification_kind = verification_name(scene_.verification.kind);
    try {
      check_run_directory(dir_, opt_.force);
      Particles particles = generate_particles(scene_);
      const std::size_t n = particles.size();
      sum.n_material_points = n;
      if (opt_.provider_factory || scene_.constitutive.model == ModelKind::kLinearElastic) {
        auto provider = opt_.provider_factory ? opt_.provider_factory(scene_, n)
                                              : make_linear_elastic(scene_.constitutive);
        solver_ = std::make_unique<Solver>(scene_, std::move(particles), std::move(provider));
        create_directory();
      } else {
        create_directory();
        solver_ = std::make_unique<Solver>(scene_, std::move(particles),
                                           make_remote_provider(scene_, n, dir_));
      }
    } catch (const SceneError& e) {
      return setup_failed(e.what(), kExitConfigError);
    } catch (const config::ConfigError& e) {
      return setup_failed(e.what(), kExitConfigError);
    } catch (const RunDirectoryError& e) {
      return setup_failed(e.what(), kExitConfigError);
    } catch (const HandshakeError& e) {
      return setup_failed(e.what(), kExitHandshakeError);
    } catch (const std::exception& e) {
      return setup_failed(std::string("setting up the run failed: ") + e.what(), kExitPeerError);
    }
    sum.model = solver_->provider().name();
    sum.mass_initial_kg = total_mass(solver_->particles());
    sum.dt_min_s = std::numeric_limits<double>::infinity();
    sum.status = "complete";
    out_ << "mpm_app " << MPMDEM_VERSION << ": scene '" << scene_.name << "' ("
         << scene_.source_file << ")\n  " << solver_->particles().size()
         << " material points, cell size " << scene_.grid.cell_size << " m, model " << sum.model
         << ", " << sum.threads << " thread(s), end time " << scene_.solver.end_time
         << " s\n  results: " << dir_ << std::endl;
    return true;
  }

  void create_directory() {
    create_run_directory(dir_, opt_.force);
    dir_created_ = true;
    result_.run_dir = dir_;
    s().run_directory = dir_;
  }

  bool setup_failed(const std::string& what, int code) {
    err_ << "error: " << what << std::endl;
    result_.exit_code = code;
    if (dir_created_) {  // mark the directory's (empty) results as failed
      s().status = "failed";
      s().error = what;
      s().wall_time_s = wall_time();
      write_summary_file();
    }
    return false;
  }

  // Step until the end time or a stop request; energies, frames and progress on the way.
  void time_loop() {
    energy_.emplace(dir_ + "/energies.csv");
    log_energy(0.0);
    if (scene_.output.vtk) vtk_.emplace(dir_);
    write_frame();
    if (scene_.verification.kind == VerificationKind::kBarVibration) {
      try {
        bar_.emplace(scene_);
        bar_->record(solver_->time(), solver_->particles());
      } catch (const std::exception& e) {  // a verification fault does not stop the run
        err_ << "warning: bar_vibration verification disabled: " << e.what() << std::endl;
      }
    }
    print_events();

    const double frame_interval = scene_.output.interval;
    const double energy_interval = scene_.output.energy_interval;
    double next_frame =
        frame_interval > 0.0 ? frame_interval : std::numeric_limits<double>::infinity();
    double next_energy = energy_interval > 0.0 ? energy_interval : 0.0;
    Progress progress(out_, scene_.output.progress_interval_s);
    progress.start(solver_->time());

    while (!solver_->finished()) {
      if (g_stop) {
        s().status = "interrupted";
        out_ << "stop requested: stopping after step " << solver_->step_count() << std::endl;
        break;
      }
      timed_step();
      const double t = solver_->time();
      const double tol = 1e-6 * last_dt_;
      log_time_step();
      print_events();
      if (bar_) bar_->record(t, solver_->particles());
      if (t >= next_energy - tol) {
        log_energy(last_dt_);
        while (energy_interval > 0.0 && next_energy <= t + tol) next_energy += energy_interval;
      }
      if (t >= next_frame - tol) {
        write_frame();
        while (next_frame <= t + tol) next_frame += frame_interval;
      }
      if (progress.due()) progress.update(progress_state());
    }
    progress.print(progress_state());
  }

  void timed_step() {
    const auto wall_start = std::chrono::steady_clock::now();
    const double cpu_start = process_cpu_time();
    solver_->step();
    s().step_wall_time_s +=
        std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
    s().step_cpu_time_s += process_cpu_time() - cpu_start;
    last_dt_ = solver_->dt();
    s().dt_min_s = std::min(s().dt_min_s, last_dt_);
    s().dt_max_s = std::max(s().dt_max_s, last_dt_);
  }

  // The step used: at the first step and whenever it changed by more than 10%.
  void log_time_step() {
    if (dt_logged_ == 0.0) {
      out_ << "time step: dt = " << format_seconds(last_dt_) << " s" << std::endl;
    } else if (std::abs(last_dt_ - dt_logged_) > 0.1 * dt_logged_) {
      out_ << "time step: dt = " << format_seconds(last_dt_) << " s from step "
           << solver_->step_count() << " (t=" << solver_->time() << " s; was "
           << format_seconds(dt_logged_) << " s)" << std::endl;
    } else {
      return;
    }
    dt_logged_ = last_dt_;
  }

  void print_events() {
    for (const std::string& e : solver_->take_events()) {
      out_ << "[step " << solver_->step_count() << ", t=" << solver_->time() << " s] " << e
           << std::endl;
    }
  }

  void require_finite() const {
    const std::string bad = find_non_finite(solver_->particles());
    if (!bad.empty()) {
      throw SimulationError(bad + " at step " + std::to_string(solver_->step_count()) +
                            "; the state is not written");
    }
  }

  void log_energy(double dt) {
    const Energies e = solver_->energies();
    energy_->append({solver_->time(), solver_->step_count(), dt, e.E_p, e.E_k, e.E_strain,
                     solver_->initial_potential_energy()});
    last_energy_step_ = solver_->step_count();
  }

  void write_frame() {
    if (!vtk_) return;
    require_finite();
    vtk_->write_frame(solver_->particles(), solver_->time());
    last_frame_step_ = solver_->step_count();
  }

  ProgressState progress_state() const {
    return {solver_->step_count(),   solver_->time(),
            scene_.solver.end_time,  last_dt_,
            solver_->energies().E_k, solver_->initial_potential_energy()};
  }

  // Last energy row and frame (if not just written), and the final state (complete or
  // interrupted runs).
  void final_outputs() {
    if (last_energy_step_ != solver_->step_count()) log_energy(last_dt_);
    if (last_frame_step_ != solver_->step_count()) write_frame();
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
      verification_figures();
    } catch (const std::exception& e) {
      err_ << "warning: verification " << s().verification_kind << " not computed: " << e.what()
           << std::endl;
      s().verification.clear();
    }
  }

  void verification_figures() {
    if (scene_.verification.kind == VerificationKind::kElasticColumn) {
      const ElasticColumnResult v = verify_elastic_column(scene_, solver_->particles());
      s().verification = {{"stress_rel_error", v.stress_rel_error},
                          {"settlement_rel_error", v.settlement_rel_error},
                          {"settlement_top_m", v.settlement_top_m},
                          {"settlement_top_expected_m", v.settlement_top_expected_m},
                          {"settlement_surface_expected_m", v.settlement_surface_expected_m}};
    } else if (bar_) {
      const BarVibrationResult v = bar_->result();
      s().verification = {{"period_s", v.period_s},
                          {"period_expected_s", v.period_expected_s},
                          {"period_rel_error", v.period_rel_error},
                          {"zero_crossings", static_cast<double>(v.crossings)},
                          {"wave_speed_m_s", v.wave_speed_m_s},
                          {"length_m", v.length_m}};
    }
  }

  void fail(const std::exception& e) {
    // A SimulationError names the point and the step itself; other faults get the step.
    std::ostringstream msg;
    if (dynamic_cast<const SimulationError*>(&e) == nullptr) {
      msg << "at step " << solver_->step_count() << " (t=" << solver_->time() << " s): ";
    }
    msg << e.what();
    s().status = "failed";
    s().error = msg.str();
    err_ << "error: " << s().error << std::endl;
    result_.exit_code =
        dynamic_cast<const HandshakeError*>(&e) ? kExitHandshakeError : kExitPeerError;
  }

  // Provider end, headline figures, summary.json, closing lines.
  void finish() {
    RunSummary& sum = s();
    // A complete or interrupted run ends the provider in order (remote: the servers shut
    // down and exit 0). After a failure it is not finished: destroying it aborts, so a
    // remote server ends with an error too.
    if (sum.status != "failed") {
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
    if (!(sum.dt_min_s <= sum.dt_max_s)) sum.dt_min_s = sum.dt_max_s = 0.0;
    const Energies e = solver_->energies();
    sum.E_p0_J = solver_->initial_potential_energy();
    sum.E_p_J = e.E_p;
    sum.E_k_J = e.E_k;
    if (opt_.final_particles) *opt_.final_particles = p;
    sum.wall_time_s = wall_time();
    if (!write_summary_file() && result_.exit_code == 0) result_.exit_code = kExitPeerError;
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
  std::chrono::steady_clock::time_point wall_start_;
  std::string dir_;
  bool dir_created_ = false;
  RunResult result_;
  std::unique_ptr<Solver> solver_;
  std::optional<EnergyLog> energy_;
  std::optional<VtkSeries> vtk_;
  std::optional<BarVibrationMonitor> bar_;
  double last_dt_ = 0.0;
  double dt_logged_ = 0.0;
  std::int64_t last_energy_step_ = -1;
  std::int64_t last_frame_step_ = -1;
};

}  // namespace

RunResult run_scene(const Scene& scene, const RunOptions& options) {
  return Run(scene, options).execute();
}

}  // namespace mpmdem::mpm
