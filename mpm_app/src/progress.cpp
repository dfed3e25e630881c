#include "progress.hpp"

#include <cmath>
#include <cstdio>
#include <sstream>

namespace mpmdem::mpm {

std::string format_duration(double seconds) {
  if (!std::isfinite(seconds) || seconds < 0.0) return "?";
  const long long total = std::llround(seconds);
  char buf[32];
  std::snprintf(buf, sizeof buf, "%lld:%02lld:%02lld", total / 3600, (total / 60) % 60, total % 60);
  return buf;
}

std::string format_progress(const ProgressState& s, double eta_s) {
  const double percent = s.end_time > 0.0 ? 100.0 * s.time / s.end_time : 100.0;
  char energy[48];
  if (s.E_p0 != 0.0) {
    std::snprintf(energy, sizeof energy, "E_k/E_p0=%.1e", s.E_k / std::abs(s.E_p0));
  } else {
    std::snprintf(energy, sizeof energy, "E_k=%.1e J", s.E_k);
  }
  char line[256];
  std::snprintf(line, sizeof line, "step %lld  t=%.4f/%.4f s (%.1f%%)  dt=%.1e s  ETA %s  %s",
                static_cast<long long>(s.step), s.time, s.end_time, percent, s.dt,
                format_duration(eta_s).c_str(), energy);
  return line;
}

Progress::Progress(std::ostream& out, double interval_s)
    : out_(out), interval_s_(interval_s), start_(Clock::now()), last_(start_) {}

double Progress::elapsed_s() const {
  return std::chrono::duration<double>(Clock::now() - start_).count();
}

double Progress::eta(const ProgressState& s) const {
  const double done = s.time - start_sim_time_;
  if (start_sim_time_ < 0.0 || done <= 0.0) return -1.0;
  return elapsed_s() * (s.end_time - s.time) / done;
}

void Progress::start(double sim_time) {
  start_ = Clock::now();
  last_ = start_;
  start_sim_time_ = sim_time;
}

bool Progress::due() const {
  return interval_s_ > 0.0 &&
         std::chrono::duration<double>(Clock::now() - last_).count() >= interval_s_;
}

bool Progress::update(const ProgressState& s) {
  if (!due()) return false;
  last_ = Clock::now();
  out_ << format_progress(s, eta(s)) << std::endl;
  return true;
}

void Progress::print(const ProgressState& s) {
  last_ = Clock::now();
  out_ << format_progress(s, s.time >= s.end_time ? 0.0 : eta(s)) << std::endl;
}

std::string TimeStepLog::line(double dt, std::int64_t step, double time) {
  char buf[160];
  if (logged_ == 0.0) {
    std::snprintf(buf, sizeof buf, "time step: dt = %.3e s", dt);
  } else if (std::abs(dt - logged_) > 0.1 * logged_) {
    std::ostringstream t;
    t << time;  // as the other event lines print times
    std::snprintf(buf, sizeof buf, "time step: dt = %.3e s from step %lld (t=%s s; was %.3e s)", dt,
                  static_cast<long long>(step), t.str().c_str(), logged_);
  } else {
    return "";
  }
  logged_ = dt;
  return buf;
}

}  // namespace mpmdem::mpm
