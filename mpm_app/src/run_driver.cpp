#include "run_driver.hpp"

#include <omp.h>

#include <chrono>
#include <cmath>
#include <csignal>
#include <iostream>
#include <limits>
#include <memory>
#include <optional>
#include <sstream>

#include "constitutive/linear_elastic.hpp"
#include "constitutive/remote.hpp"
#include "errors.hpp"
#include "mpmdem/config/schema.hpp"
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

std::string format_seconds(double s) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3e", s);
  return buf;
}

}  // namespace

void request_stop() {
  g_stop = 1;
}

RunResult run_scene(const Scene& scene_in, const RunOptions& opt) {
  std::ostream& out = opt.out ? *opt.out : std::cout;
  std::ostream& err = opt.err ? *opt.err : std::cerr;
  const auto wall_start = std::chrono::steady_clock::now();
  auto wall_time = [&wall_start] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  };

  Scene scene = scene_in;
  if (opt.threads > 0) scene.solver.threads = opt.threads;
  if (scene.solver.threads > 0) omp_set_num_threads(scene.solver.threads);
  g_stop = 0;

  RunResult result;
  RunSummary& s = result.summary;
  s.scene = scene.name;
  s.config_file = scene.source_file;
  s.model = model_name(scene.constitutive.model);
  s.program_version = MPMDEM_VERSION;
  s.end_time_s = scene.solver.end_time;
  s.threads = omp_get_max_threads();
  s.verification_kind = verification_name(scene.verification.kind);
  const std::string dir = opt.out_dir.empty() ? default_run_directory(scene.name) : opt.out_dir;

  // What can reject the scene is done before the run directory is created or touched.
  std::unique_ptr<Solver> solver;
  bool dir_created = false;
  auto setup_failed = [&](const std::string& what, int code) {
    err << "error: " << what << std::endl;
    result.exit_code = code;
    if (dir_created) {
      result.run_dir = dir;
      s.status = "failed";
      s.error = what;
      s.run_directory = dir;
      s.wall_time_s = wall_time();
      try {
        write_summary(dir + "/summary.json", s);
      } catch (const std::exception& e) {
        err << "error: " << e.what() << std::endl;
      }
    }
    return result;
  };
  try {
    check_run_directory(dir, opt.force);
    Particles particles = generate_particles(scene);
    s.n_material_points = particles.size();
    if (opt.provider_factory) {
      const std::size_t n = particles.size();
      solver =
          std::make_unique<Solver>(scene, std::move(particles), opt.provider_factory(scene, n));
      create_run_directory(dir, opt.force);
      dir_created = true;
    } else if (scene.constitutive.model == ModelKind::kLinearElastic) {
      solver = std::make_unique<Solver>(scene, std::move(particles),
                                        make_linear_elastic(scene.constitutive));
      create_run_directory(dir, opt.force);
      dir_created = true;
    } else {
      create_run_directory(dir, opt.force);
      dir_created = true;
      const std::size_t n = particles.size();
      solver = std::make_unique<Solver>(scene, std::move(particles),
                                        make_remote_provider(scene, n, dir));
    }
  } catch (const SceneError& e) {
    return setup_failed(e.what(), 2);
  } catch (const config::ConfigError& e) {
    return setup_failed(e.what(), 2);
  } catch (const RunDirectoryError& e) {
    return setup_failed(e.what(), 2);
  } catch (const std::exception& e) {
    return setup_failed(std::string("setting up the run failed: ") + e.what(), 4);
  }

  result.run_dir = dir;
  s.run_directory = dir;
  s.model = solver->provider().name();
  const Particles& P = solver->particles();
  s.mass_initial_kg = total_mass(P);
  out << "mpm_app " << MPMDEM_VERSION << ": scene '" << scene.name << "' (" << scene.source_file
      << ")\n"
      << "  " << P.size() << " material points, cell size " << scene.grid.cell_size << " m, model "
      << s.model << ", " << s.threads << " thread(s), end time " << scene.solver.end_time << " s\n"
      << "  results: " << dir << std::endl;

  SignalGuard signals(opt.handle_signals);
  Progress progress(out, scene.output.progress_interval_s);
  std::optional<EnergyLog> energy;
  std::optional<VtkSeries> vtk;
  std::optional<BarVibrationMonitor> bar;
  double dt_logged = 0.0;
  s.dt_min_s = std::numeric_limits<double>::infinity();
  s.dt_max_s = 0.0;
  s.status = "complete";
  std::int64_t last_energy_step = -1;
  std::int64_t last_frame_step = -1;
  double last_dt = 0.0;

  auto print_events = [&] {
    for (const std::string& e : solver->take_events()) {
      out << "[step " << solver->step_count() << ", t=" << solver->time() << " s] " << e
          << std::endl;
    }
  };
  auto require_finite = [&] {
    const std::string bad = find_non_finite(solver->particles());
    if (!bad.empty()) {
      throw SimulationError(bad + " at step " + std::to_string(solver->step_count()) +
                            "; the state is not written");
    }
  };
  auto log_energy = [&](double dt) {
    const Energies e = solver->energies();
    energy->append({solver->time(), solver->step_count(), dt, e.E_p, e.E_k, e.E_strain,
                    solver->initial_potential_energy()});
    last_energy_step = solver->step_count();
  };
  auto write_frame = [&] {
    if (!vtk) return;
    require_finite();
    vtk->write_frame(solver->particles(), solver->time());
    last_frame_step = solver->step_count();
  };
  auto progress_state = [&] {
    return ProgressState{solver->step_count(),   solver->time(),
                         scene.solver.end_time,  last_dt,
                         solver->energies().E_k, solver->initial_potential_energy()};
  };

  try {
    energy.emplace(dir + "/energies.csv");
    log_energy(0.0);
    if (scene.output.vtk) vtk.emplace(dir);
    write_frame();
    if (scene.verification.kind == VerificationKind::kBarVibration) {
      bar.emplace(scene);
      bar->record(solver->time(), P);
    }
    print_events();

    const double frame_interval = scene.output.interval;
    const double energy_interval = scene.output.energy_interval;
    double next_frame =
        frame_interval > 0.0 ? frame_interval : std::numeric_limits<double>::infinity();
    double next_energy = energy_interval > 0.0 ? energy_interval : 0.0;
    progress.start(solver->time());

    while (!solver->finished()) {
      if (g_stop) {
        s.status = "interrupted";
        out << "stop requested: stopping after step " << solver->step_count() << std::endl;
        break;
      }
      const auto step_start = std::chrono::steady_clock::now();
      solver->step();
      s.step_wall_time_s +=
          std::chrono::duration<double>(std::chrono::steady_clock::now() - step_start).count();
      const double t = solver->time();
      const double dt = solver->dt();
      last_dt = dt;
      s.dt_min_s = std::min(s.dt_min_s, dt);
      s.dt_max_s = std::max(s.dt_max_s, dt);
      if (dt_logged == 0.0) {
        out << "time step: dt = " << format_seconds(dt) << " s" << std::endl;
        dt_logged = dt;
      } else if (std::abs(dt - dt_logged) > 0.1 * dt_logged) {
        out << "time step: dt = " << format_seconds(dt) << " s from step " << solver->step_count()
            << " (t=" << t << " s; was " << format_seconds(dt_logged) << " s)" << std::endl;
        dt_logged = dt;
      }
      print_events();
      if (bar) bar->record(t, P);
      const double tol = 1e-6 * dt;
      if (t >= next_energy - tol) {
        log_energy(dt);
        while (energy_interval > 0.0 && next_energy <= t + tol) next_energy += energy_interval;
      }
      if (t >= next_frame - tol) {
        write_frame();
        while (next_frame <= t + tol) next_frame += frame_interval;
      }
      if (progress.due()) progress.update(progress_state());
    }

    // Final outputs (complete or interrupted).
    if (last_energy_step != solver->step_count()) log_energy(last_dt);
    if (last_frame_step != solver->step_count()) write_frame();
    if (scene.output.hdf5) {
      require_finite();
      write_final_state(dir + "/final_state.h5", solver->particles(),
                        {solver->time(), solver->step_count(), scene.name, scene.source_file});
    }
    if (s.status == "complete") {
      if (scene.verification.kind == VerificationKind::kElasticColumn) {
        const ElasticColumnResult v = verify_elastic_column(scene, solver->particles());
        s.verification = {{"stress_rel_error", v.stress_rel_error},
                          {"settlement_rel_error", v.settlement_rel_error},
                          {"settlement_top_m", v.settlement_top_m},
                          {"settlement_top_expected_m", v.settlement_top_expected_m},
                          {"settlement_surface_expected_m", v.settlement_surface_expected_m}};
      } else if (bar) {
        const BarVibrationResult v = bar->result();
        s.verification = {{"period_s", v.period_s},
                          {"period_expected_s", v.period_expected_s},
                          {"period_rel_error", v.period_rel_error},
                          {"zero_crossings", static_cast<double>(v.crossings)},
                          {"wave_speed_m_s", v.wave_speed_m_s},
                          {"length_m", v.length_m}};
      }
    }
    progress.print(progress_state());
    result.exit_code = s.status == "interrupted" ? 130 : 0;
  } catch (const std::exception& e) {
    // A SimulationError names the point and the step itself; other faults get the step.
    std::ostringstream msg;
    if (dynamic_cast<const SimulationError*>(&e) == nullptr) {
      msg << "at step " << solver->step_count() << " (t=" << solver->time() << " s): ";
    }
    msg << e.what();
    s.status = "failed";
    s.error = msg.str();
    err << "error: " << s.error << std::endl;
    result.exit_code = 4;
  }

  // A complete or interrupted run ends the provider in order (remote: the servers shut down
  // and exit 0). After a failure it is not finished: destroying it (at the end of this
  // function) aborts, so a remote server ends with an error too.
  if (s.status != "failed") {
    try {
      solver->provider().finish();
    } catch (const std::exception& e) {
      err << "warning: ending the constitutive provider: " << e.what() << std::endl;
    }
  }

  s.steps = solver->step_count();
  s.time_s = solver->time();
  s.removed_points = solver->removed_points();
  s.n_material_points = solver->particles().size() + s.removed_points;
  s.mass_final_kg = total_mass(solver->particles());
  if (!(s.dt_min_s <= s.dt_max_s)) s.dt_min_s = s.dt_max_s = 0.0;
  try {
    const Energies e = solver->energies();
    s.E_p0_J = solver->initial_potential_energy();
    s.E_p_J = e.E_p;
    s.E_k_J = e.E_k;
  } catch (const std::exception&) {
  }
  if (opt.final_particles) *opt.final_particles = solver->particles();
  s.wall_time_s = wall_time();
  try {
    write_summary(dir + "/summary.json", s);
  } catch (const std::exception& e) {
    err << "error: writing summary.json: " << e.what() << std::endl;
    if (result.exit_code == 0) result.exit_code = 4;
  }

  out << "status: " << s.status << ", " << s.steps << " steps, t=" << s.time_s << " s, wall "
      << s.wall_time_s << " s" << std::endl;
  for (const auto& [key, value] : s.verification) out << "  " << key << " = " << value << "\n";
  out << "results: " << dir << std::endl;
  return result;
}

}  // namespace mpmdem::mpm
