#include "run_support.hpp"

#include <cmath>
#include <cstdio>
#include <ctime>
#include <sstream>

#include "run_driver.hpp"
#include "solver.hpp"
#include "verification/bar_vibration.hpp"
#include "verification/elastic_column.hpp"

namespace mpmdem::mpm {

namespace run_support {

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

}  // namespace

bool stop_requested() {
  return g_stop != 0;
}

void clear_stop_request() {
  g_stop = 0;
}

SignalGuard::SignalGuard(bool active) : active_(active) {
  if (!active_) return;
  struct sigaction sa {};
  sa.sa_handler = on_stop_signal;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, &old_int_);
  sigaction(SIGTERM, &sa, &old_term_);
}

SignalGuard::~SignalGuard() {
  if (!active_) return;
  sigaction(SIGINT, &old_int_, nullptr);
  sigaction(SIGTERM, &old_term_, nullptr);
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

double total_mass(const Grid& g) {
  double m = 0.0;
  for (double m_i : g.m_i) m += m_i;
  return m;
}

namespace {

bool finite(const Vec3& v) {
  return v.allFinite();
}
bool finite(const Mat3& v) {
  return v.allFinite();
}
bool finite(double v) {
  return std::isfinite(v);
}

}  // namespace

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

std::string stop_reason(const std::string& status, const std::string& column_end) {
  if (status == "failed" || status == "interrupted") return status;
  if (status == "truncated") return "max_steps";
  return column_end.empty() ? "end_time" : column_end;
}

std::vector<std::pair<std::string, double>> verification_figures(const Scene& scene,
                                                                 const Particles& p,
                                                                 const BarVibrationMonitor* bar) {
  if (scene.verification.kind == VerificationKind::kElasticColumn) {
    const ElasticColumnResult v = verify_elastic_column(scene, p);
    return {{"stress_rel_error", v.stress_rel_error},
            {"settlement_rel_error", v.settlement_rel_error},
            {"settlement_top_m", v.settlement_top_m},
            {"settlement_top_expected_m", v.settlement_top_expected_m},
            {"settlement_surface_expected_m", v.settlement_surface_expected_m}};
  }
  if (bar) {
    const BarVibrationResult v = bar->result();
    return {{"period_s", v.period_s},
            {"period_expected_s", v.period_expected_s},
            {"period_rel_error", v.period_rel_error},
            {"zero_crossings", static_cast<double>(v.crossings)},
            {"wave_speed_m_s", v.wave_speed_m_s},
            {"length_m", v.length_m}};
  }
  return {};
}

std::vector<std::pair<std::string, double>> remote_figures(Solver& solver,
                                                           std::int64_t rve_particles) {
  ConstitutiveProvider& provider = solver.provider();
  return {{"n_rve_particles", static_cast<double>(rve_particles)},
          {"dem_ranks", static_cast<double>(provider.dem_ranks())},
          {"rebalances", static_cast<double>(provider.rebalances())},
          {"rve_evaluations", static_cast<double>(provider.rve_evaluations())},
          {"rve_skipped", static_cast<double>(provider.rve_skipped())},
          {"rve_no_contact_updates", static_cast<double>(solver.no_contact_updates())},
          {"rve_no_contact_points_final", static_cast<double>(solver.no_contact_points())}};
}

}  // namespace run_support

void request_stop() {
  run_support::g_stop = 1;
}

}  // namespace mpmdem::mpm
